"""Materials at temperature (x3dpd.materials: tables, at_temperature): every expected value is
computed here from the raw numbers of library.toml and unit factors written out (1 in = 0.0254 m,
1 lbf = 0.45359237 kg x 9.80665 m/s^2, T[K] = (T[F] - 32) 5/9 + 273.15), never from the code
under test."""

from __future__ import annotations

import math
import tomllib

import pytest

from x3dpd.materials import (
    LIBRARY,
    MaterialError,
    material,
    material_at,
    mean_expansion,
    properties_at,
    thermal_strain,
)

PSI = 0.45359237 * 9.80665 / 0.0254**2
#: SI factor of every unit the shipped tables use.
FACTOR = {
    "Msi": 1e6 * PSI,
    "GPa": 1e9,
    "g/cm^3": 1e3,
    "1e-6/K": 1e-6,
    "1e-6/degF": 1.8e-6,
    None: 1.0,
}
SUFFIX = {"degF": "F", "degC": "C", "K": "K"}
RAW = tomllib.loads(LIBRARY.read_text())["material"]
HOT = {key: t["temperature"] for key, t in RAW.items() if "temperature" in t}
PROPERTIES = ("E", "nu", "rho", "alpha_mean")


def kelvin(t: float, unit: str) -> float:
    return {"degF": (t - 32.0) * 5.0 / 9.0 + 273.15, "degC": t + 273.15, "K": t}[unit]


def tables(key: str):
    """(property, raw table) of every tabulated property of material ``key``."""
    return [(p, HOT[key][p]) for p in PROPERTIES if p in HOT[key] and "T" in HOT[key][p]]


def interpolate(table: dict, t: float) -> float:
    """The raw table's value at ``t`` (in its T_unit), linear between its points, in SI."""
    ts, vs = table["T"], table["values"]
    k = max(i for i in range(len(ts) - 1) if ts[i] <= t)
    v = vs[k] + (vs[k + 1] - vs[k]) * (t - ts[k]) / (ts[k + 1] - ts[k])
    return v * FACTOR[table.get("unit")]


def strain_from_reference(table: dict, t: float) -> float:
    """eps(T) = alpha_mean(T) (T - T0) of a raw mean table, T in its T_unit."""
    per_degree = 5.0 / 9.0 if table["T_unit"] == "degF" else 1.0  # K per degree
    return interpolate(table, t) * (t - table["reference"]) * per_degree


def at(key: str, t: float, unit: str):
    return properties_at(key, kelvin(t, unit))


def test_the_hot_damper_materials_have_tables_over_their_range():
    """Issue 31 item 5: the report's materials and a hot damper's; 70 F assembly to 850 F for
    all, down to -94 F (report Figure 20) for the titanium capsule and its WC spheres."""
    need = {name: (70, 850) for name in ("302", "304", "316", "718", "alumina", "si3n4")}
    need |= {"titanium": (-94, 850), "tungsten carbide": (-94, 850), "440C": (70, 212)}
    for name, (low, high) in need.items():
        tables_of = material(name).temperature
        assert tables_of is not None, name
        assert tables_of.low <= kelvin(low, "degF") and kelvin(high, "degF") <= tables_of.high


def test_every_property_has_a_source_and_a_value_at_every_table_point():
    for key, block in HOT.items():
        expansion = [k for k in ("alpha_mean", "alpha") if k in block]
        assert {"E", "nu", "rho"} <= set(block) and len(expansion) == 1, key
        for name, entry in block.items():
            assert entry["source"].strip(), (key, name)
            if "T" in entry:
                assert len(entry["T"]) == len(entry["values"]) >= 2, (key, name)
        mat = material(key)
        points = {kelvin(t, e["T_unit"]) for _, e in tables(key) for t in e["T"]}
        inside = [k for k in points if mat.temperature.covers(k)]
        assert len(inside) >= 2, key
        for k in inside:
            hot = properties_at(key, k)
            for value in (hot.E, hot.nu, hot.rho, hot.alpha_mean, hot.alpha, hot.strain):
                assert value is not None and math.isfinite(value), (key, k)
            assert 1e9 < hot.E < 7.5e11 and 0 < hot.nu < 0.5 and 800 < hot.rho < 23000
            assert 0 < hot.alpha < 3e-5, (key, k)
            assert all(hot.sources[p].strip() for p in ("E", "nu", "rho", "alpha", "mu"))


@pytest.mark.parametrize("key", sorted(HOT))
def test_tables_interpolate_exactly_at_their_points(key):
    mat = material(key)
    for name, table in tables(key):
        unit = table["T_unit"]
        for t, v in zip(table["T"], table["values"]):
            want = v * FACTOR[table.get("unit")]
            if not mat.temperature.covers(kelvin(t, unit)):
                with pytest.raises(MaterialError, match="outside its temperature table"):
                    material_at(key, f"{t}{SUFFIX[unit]}")
                continue
            hot = at(key, t, unit)
            got = {"E": hot.E, "nu": hot.nu, "rho": hot.rho, "alpha_mean": hot.alpha_mean}[name]
            assert got == pytest.approx(want, rel=1e-12), (name, t)
            # and bit for bit the value read from the file: no rounding by interpolation
            stored = getattr(mat.temperature, name, None) or mat.temperature.expansion.table
            assert got == stored.values[stored.kelvin.index(kelvin(t, unit))], (name, t)


@pytest.mark.parametrize("key", sorted(HOT))
def test_tables_are_linear_between_their_points(key):
    mat = material(key)
    for name, table in tables(key):
        unit, ts, vs = table["T_unit"], table["T"], table["values"]
        for k in range(len(ts) - 1):
            for share in (0.25, 0.5):
                t = ts[k] + share * (ts[k + 1] - ts[k])
                if not mat.temperature.covers(kelvin(t, unit)):
                    continue
                want = (vs[k] + share * (vs[k + 1] - vs[k])) * FACTOR[table.get("unit")]
                hot = at(key, t, unit)
                got = {"E": hot.E, "nu": hot.nu, "rho": hot.rho, "alpha_mean": hot.alpha_mean}
                assert got[name] == pytest.approx(want, rel=1e-12), (name, t)


def test_outside_a_table_is_refused_naming_material_and_range():
    with pytest.raises(MaterialError) as info:
        material_at("titanium", "1200F")
    assert str(info.value) == (
        "material 'titanium': 1200 °F is outside its temperature table, -99.67 °F to 1000 °F"
    )
    with pytest.raises(MaterialError, match=r"'steel-302': 0 °C is outside .*, 0 °C to 648.89 °C"):
        material_at("SS-302", "-0.0001C")  # 0 C shown to 0.01 degree; the table starts at 32 F
    with pytest.raises(MaterialError, match=r"'alumina': 1600 °C .* 20 °C to 1500 °C"):
        thermal_strain("alumina", "70F", "1600C")
    for key in HOT:
        mat = material(key).temperature
        for k in (mat.low - 0.01, mat.high + 0.01):
            with pytest.raises(MaterialError, match=f"material '{key}': .* to "):
                properties_at(key, k)


def test_room_temperature_materials_answer_only_at_room_temperature():
    """The report's steels (and lead, brass, ...) have no tables: their nominal values at 20 to
    25 C, no expansion, and a refusal elsewhere that points at the materials that have tables."""
    steel = material("steel-report")
    hot = material_at("steel-report", "70F")
    assert (hot.E, hot.nu, hot.rho) == (30.0e6, 0.33, 7.32971e-4)  # psi, lbf s^2/in^4
    assert hot.alpha is None and hot.alpha_mean is None and hot.strain is None
    assert properties_at(steel, kelvin(25, "degC")).E == steel.E
    assert thermal_strain("steel-beam", "70F", "70F") == 0.0
    for call in (
        lambda: material_at("steel-report", "850F"),
        lambda: material_at("lead", "19.9C"),
        lambda: thermal_strain("steel-beam", "70F", "75F"),
    ):
        with pytest.raises(MaterialError, match="room-temperature values only") as info:
            call()
        assert "steel-302" in str(info.value) or "no expansion data" in str(info.value)


@pytest.mark.parametrize(
    ("key", "t1", "t2"),
    [("steel-302", 70, 850), ("titanium", -94, 850), ("titanium", 400, 70), ("alumina", 100, 2500)],
)
def test_thermal_strain_is_the_secant_relation_of_the_table(key, t1, t2):
    """strain(T1 -> T2) = (L2 - L1)/L1 = (eps(T2) - eps(T1)) / (1 + eps(T1)), eps(T) = alpha_mean(T)
    (T - T0) from the raw table; back and forth returns the length: (1 + s12)(1 + s21) = 1."""
    table = HOT[key]["alpha_mean"]
    unit = table["T_unit"]

    def own(t_f):
        t = t_f if unit == "degF" else (t_f - 32.0) * 5.0 / 9.0
        return strain_from_reference(table, t)

    eps1, eps2 = own(t1), own(t2)
    want = (eps2 - eps1) / (1.0 + eps1)
    assert thermal_strain(key, f"{t1}F", f"{t2}F") == pytest.approx(want, rel=1e-10)
    assert thermal_strain(key, t1, t2) == thermal_strain(key, f"{t1}F", f"{t2}F")  # bare: degF
    back = thermal_strain(key, f"{t2}F", f"{t1}F")
    assert (1 + want) * (1 + back) == pytest.approx(1.0, abs=1e-14)
    # the mean coefficient between the two, per degF: strain / (T2 - T1)
    assert mean_expansion(key, t1, t2) == pytest.approx(want / (t2 - t1), rel=1e-10)


def test_thermal_strain_is_the_integral_of_the_instantaneous_coefficient():
    """eps(T2) - eps(T1) = integral of alpha(T) dT, alpha the tangent the code reports
    (midpoint rule, 20000 steps; alpha jumps at table points, hence 1e-5)."""
    for key, (t1, t2) in {"steel-304": (70, 1100), "inconel-718": (100, 1300)}.items():
        k1, k2 = kelvin(t1, "degF"), kelvin(t2, "degF")
        n = 20000
        h = (k2 - k1) / n
        integral = sum(properties_at(key, k1 + (i + 0.5) * h).alpha for i in range(n)) * h
        eps1 = properties_at(key, k1).strain
        assert thermal_strain(key, f"{t1}F", f"{t2}F") * (1 + eps1) == pytest.approx(
            integral, rel=1e-5
        )


def test_a_sphere_and_a_cavity_grow_by_their_tables():
    """Issue 31, must hold: a radius R heated by dT is R (1 + alpha dT) with alpha the mean
    coefficient over dT, and a cavity's clearance changes by the difference of the two
    expansions -- here a Ti-6Al-4V bore of radius 0.0630 in around a 0.0625 in WC sphere."""
    bore, sphere = 0.0630, 0.0625
    for t in (-94, 365, 850):
        celsius = (t - 32) * 5 / 9, (70 - 32) * 5 / 9
        ti, ti0 = (strain_from_reference(HOT["titanium"]["alpha_mean"], c) for c in celsius)
        wc, wc0 = (strain_from_reference(HOT["tungsten-carbide"]["alpha_mean"], c) for c in celsius)
        want = bore * (1 + ti) / (1 + ti0) - sphere * (1 + wc) / (1 + wc0)
        got = bore * (1 + thermal_strain("titanium", 70, t)) - sphere * (
            1 + thermal_strain("wc", 70, t)
        )
        assert got == pytest.approx(want, rel=1e-9)
        assert (got > bore - sphere) == (t > 70)  # titanium expands more than the carbide


def test_density_follows_the_expansion_or_its_own_table():
    """rho(T) = rho(T_rho) ((1 + eps(T_rho)) / (1 + eps(T)))^3 where the table derives it
    (steel-304: 8000 kg/m^3 quoted at 68 F); alumina's own density table agrees with its
    expansion table to 0.1 % (the two are NIST's, independently tabulated)."""
    table = HOT["steel-304"]["alpha_mean"]
    eps68 = strain_from_reference(table, 68)
    assert at("steel-304", 68, "degF").rho == pytest.approx(8000.0, rel=1e-14)
    for t in (32, 500, 850, 1200):
        want = 8000.0 * ((1 + eps68) / (1 + strain_from_reference(table, t))) ** 3
        assert at("steel-304", t, "degF").rho == pytest.approx(want, rel=1e-12)
    alumina = HOT["alumina"]
    for t, rho in zip(alumina["rho"]["T"], alumina["rho"]["values"]):
        from_expansion = 3984.0 / (1 + strain_from_reference(alumina["alpha_mean"], t)) ** 3
        assert from_expansion == pytest.approx(rho * 1e3, rel=1e-3)


def test_in_a_decks_units():
    """material_at converts like in_units: psi and lbf s^2/in^4 for inch decks, with alpha per
    degF; Pa, kg/m^3 and alpha per degC (= per K) for m N s, whose bare numbers are degC."""
    inch = material_at("steel-302", "850F", "in lbf s")
    assert inch.E == pytest.approx((24.1 + 23.5) / 2 * 1e6, rel=1e-12)  # ASME row, Msi
    assert inch.temperature == 850.0 and inch.temperature_unit == "degF"
    si = material_at("steel-302", 400, ("m", "N", "s"))  # a bare number: 400 degC
    assert si.temperature_unit == "degC" and si.temperature == 400.0
    assert si.E == pytest.approx(material_at("steel-302", "752F").E * PSI, rel=1e-11)
    with pytest.raises(MaterialError, match="850 °C is outside"):
        material_at("steel-302", 850, "m N s")
    si = material_at("steel-302", "455C", "m N s")
    assert si.alpha_mean == pytest.approx(inch.alpha_mean * 1.8, rel=1e-3)  # 850 F ~ 454.4 C
    assert si.reference == 0.0 and inch.reference == 32.0
    assert inch.pdmp_fields()["e0"] == inch.E and inch.pdmp_fields()["prho"] == inch.rho
