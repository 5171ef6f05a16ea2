"""The material library (x3dpd.materials): every value sourced and plausible, names tolerant,
unit conversion against closed forms written out here (1 in = 0.0254 m, 1 lbf =
0.45359237 kg x 9.80665 m/s^2, both exact by definition)."""

from __future__ import annotations

import math
import tomllib

import pytest

from x3dpd.materials import (
    LIBRARY,
    Material,
    MaterialError,
    in_units,
    material,
    materials,
    read_library,
)

INCH = 0.0254
LBF = 0.45359237 * 9.80665
PSI = LBF / INCH**2


def test_every_value_of_every_material_has_a_source():
    raw = tomllib.loads(LIBRARY.read_text())["material"]
    assert len(raw) >= 16
    for key, table in raw.items():
        for name in ("E", "nu", "rho", "mu"):
            assert table[name]["source"].strip(), (key, name)
        for arm in table.get("maxwell", []):
            assert arm["source"].strip(), key
    for m in materials():
        want = {"E", "nu", "rho", "mu"} | ({"maxwell"} if m.maxwell else set())
        assert want <= set(m.sources), m.name
        assert all(m.sources[k].strip() for k in want)


@pytest.mark.parametrize("m", materials(), ids=lambda m: m.name)
def test_values_are_physically_plausible(m: Material):
    # densities of engineering solids: polymers ~0.9 to osmium 22.6 g/cm^3
    assert 800.0 <= m.rho <= 23000.0
    # moduli: polymers ~1 GPa to cemented carbides ~700 GPa
    assert 1e9 <= m.E <= 7.5e11
    # isotropic stability bounds -1 < nu < 0.5; real solids 0 < nu < 0.5
    assert 0.0 < m.nu < 0.5
    assert 0.0 <= m.mu <= 1.5
    for e, tau in m.maxwell:
        assert 0.0 < e and 0.0 < tau < 1.0
    assert m.restitution is None or 0.0 < m.restitution <= 1.0


def test_the_report_and_damper_materials_are_there():
    for name in (
        "tungsten carbide",
        "lead",
        "tungsten",
        "brass",
        "titanium",
        "acrylic",
        "steel",
        "beam steel",
        "302",
        "SS-304",
        "316",
        "440C",
        "aluminium",
        "6061-T6",
        "Inconel 718",
        "alumina",
    ):
        assert isinstance(material(name), Material), name


def test_names_are_case_and_alias_tolerant():
    wc = material("tungsten-carbide")
    assert material("Tungsten Carbide") is wc
    assert material("WC") is wc
    assert material("tungsten_carbide") is wc
    assert material(wc) is wc


def test_unknown_name_lists_close_matches():
    with pytest.raises(
        MaterialError,
        match=r"unknown material 'tungstn carbde'.*"
        r"tungsten-carbide",
    ):
        material("tungstn carbde")
    with pytest.raises(MaterialError, match="x3dpd materials"):
        material("unobtainium")


def test_report_beam_steel_is_the_beam_decks_pdmp():
    """Section 8.2: E0 27.5e6 psi, E1 5.0e6 psi, tau1 2e-6 s, nu 0.33, mu 0.30, and the
    density 0.283 lbf/in^3 / 386.1 in/s^2 of Appendix A's PDMP card, back exactly in psi."""
    d = in_units(material("beam-steel"))
    assert d.pdmp_fields() == {
        "prho": 7.32971e-4,
        "ppoi": 0.33,
        "e0": 27.5e6,
        "e1": 5.0e6,
        "t1": 2.0e-6,
        "pcof": 0.30,
        "extra_terms": (),
    }
    assert material("steel-beam").E == pytest.approx(27.5e6 * PSI, rel=1e-12)


def test_conversion_to_si_and_inch_lbf_s_closed_form():
    wc = material("tungsten carbide")
    assert wc.E == pytest.approx(620e9, rel=1e-12)
    assert wc.rho == pytest.approx(14950.0, rel=1e-12)
    si = in_units(wc, ("m", "N", "s"))
    assert si.E == pytest.approx(620e9, rel=1e-11) and si.rho == pytest.approx(14950.0, rel=1e-11)
    inch = in_units(wc, "in lbf s")
    assert inch.E == pytest.approx(620e9 / PSI, rel=1e-11)  # ~89.9e6 psi
    # mass density: kg/m^3 -> (lbf s^2/in) / in^3 = kg/m^3 * in^4 / lbf
    assert inch.rho == pytest.approx(14950.0 * INCH**4 / LBF, rel=1e-11)
    # the same thing through weight density: 14.95 g/cm^3 = 0.5401 lb/in^3, / g in in/s^2
    assert inch.rho == pytest.approx(14950.0 * INCH**3 / 0.45359237 / (9.80665 / INCH), rel=1e-11)
    assert inch.nu == wc.nu and inch.mu == wc.mu


def test_conversion_mm_n_s_and_milliseconds():
    steel = material("steel-beam")
    mm = in_units(steel, "mm N s")  # MPa and t/mm^3
    assert mm.E == pytest.approx(steel.E / 1e6, rel=1e-11)
    assert mm.rho == pytest.approx(steel.rho * 1e-12, rel=1e-11)
    ms = in_units(steel, ("m", "N", "ms"))  # time 1e-3 s: tau in ms, rho in N ms^2/m^4
    assert ms.maxwell[0][1] == pytest.approx(2.0e-3, rel=1e-12)
    assert ms.rho == pytest.approx(steel.rho * 1e6, rel=1e-11)
    with pytest.raises(MaterialError, match="units: LENGTH unit 'furlong'"):
        in_units(steel, "furlong N s")


def test_a_value_without_source_is_refused(tmp_path):
    bad = tmp_path / "lib.toml"
    bad.write_text(
        '[material.x]\nE = { value = 1.0, unit = "GPa" }\n'
        'nu = { value = 0.3, source = "a" }\n'
        'rho = { value = 1.0, unit = "g/cm^3", source = "a" }\n'
        'mu = { value = 0.3, source = "a" }\n'
    )
    with pytest.raises(MaterialError, match=r"lib.toml: material 'x': E has no source"):
        read_library(bad)
    bad.write_text(bad.read_text().replace('unit = "GPa" }', 'unit = "bar", source = "a" }'))
    with pytest.raises(MaterialError, match="E unit 'bar': expected one of"):
        read_library(bad)


def test_elastic_material_pdmp_has_report_placeholder_tau():
    """Appendix B: an elastic particle has E1 = 0 and T1 any nonzero number."""
    f = in_units("lead").pdmp_fields()
    assert f["e1"] == 0.0 and f["t1"] != 0.0
    assert math.isclose(f["e0"], 16e9 / PSI, rel_tol=1e-11)
