"""A deck at temperature (the TEMPERATURE card, x3dpd.model.temperature; issue 31 item 6).

Every expected value is computed here from the raw numbers of the material library's file
(x3dpd/materials/library.toml: its mean-expansion and modulus tables, linear between their
points) and the deck's own numbers, never from the code under test:

* a sphere of radius R heated from its table's reference temperature by dT has radius
  R (1 + alpha dT), alpha the table's mean coefficient at T;
* a bore's clearance changes by the difference of the two expansions: along the axis by
  L s_w - 2 r s_p, across by 2 R s_w - 2 r s_p (s = (eps(T) - eps(T0)) / (1 + eps(T0)), eps from
  the tables);
* at T = T0 the model is the deck's, bit for bit.
"""

from __future__ import annotations

import tomllib
from dataclasses import fields, replace

import numpy as np
import pytest
from factories import closed_box_deck, small_cylinder_deck

from x3dpd.deck import format_deck, parse_deck
from x3dpd.errors import DeckError
from x3dpd.materials import LIBRARY
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model

RAW = tomllib.loads(LIBRARY.read_text())["material"]
PSI = 0.45359237 * 9.80665 / 0.0254**2  # Pa per psi


def celsius(t_f: float) -> float:
    return (t_f - 32.0) * 5.0 / 9.0


def table_value(table: dict, t: float) -> float:
    """A raw table's value at ``t`` (in its own T_unit), linear between its points."""
    ts, vs = table["T"], table["values"]
    k = max(i for i in range(len(ts) - 1) if ts[i] <= t)
    return vs[k] + (vs[k + 1] - vs[k]) * (t - ts[k]) / (ts[k + 1] - ts[k])


def eps(name: str, t_f: float) -> float:
    """(L(T) - L(T_ref)) / L(T_ref) of a degC mean table: alpha_mean(T) (T - T_ref)."""
    table = RAW[name]["temperature"]["alpha_mean"]
    assert table["T_unit"] == "degC" and table["unit"] == "1e-6/K"
    t = celsius(t_f)
    return table_value(table, t) * 1e-6 * (t - table["reference"])


def strain(name: str, t0_f: float, t_f: float) -> float:
    return (eps(name, t_f) - eps(name, t0_f)) / (1.0 + eps(name, t0_f))


def hot_text(deck, card: str, units: bool = True) -> str:
    """``deck``'s text with a TEMPERATURE card of the records ``card`` (and a UNITS card)."""
    unit_card = "UNITS\n in lbf s\nEND\n" if units and deck.units is None else ""
    return format_deck(deck) + unit_card + f"TEMPERATURE\n{card}\nEND\n"


def at(deck, card: str, units: bool = True):
    """``deck`` with a TEMPERATURE card of the records ``card``, read back from its text as a
    user's deck is."""
    return parse_deck(hot_text(deck, card, units), "hot.inp")


WC_MATERIAL = dict(e0=7.6e7, e1=1.4e7, tau1=2e-6, nu=0.22, mu=0.4, density=1.4e-3)


def bore(r_bore: float = 0.0703125, pos=((0.15, -0.006, 0.0),)):
    """One 1/8 in sphere (x3dpd.deck.generate's cylinder deck: axis from 0 to 0.3 along x) in
    a bore of radius ``r_bore``, a WALLMAT of Ti-6Al-4V's room-temperature modulus."""
    from x3dpd.deck.cards import WallMat
    from x3dpd.deck.generate import Material3

    deck = small_cylinder_deck(np.array(pos), material=Material3(**WC_MATERIAL))
    deck = replace(deck, pdmp=(replace(deck.pdmp[0], rzero=0.0625),))
    walls = tuple(replace(w, params=(r_bore,)) for w in deck.analytic_walls)
    return replace(deck, analytic_walls=walls, wallmat=(WallMat(1, 16.5e6, 0.342, 0.4),))


def test_a_sphere_heated_by_dt_has_radius_r_times_one_plus_alpha_dt():
    """Assembled at the carbide table's reference (20 C = 68 F): R(T) = R (1 + alpha(T) dT)
    with alpha the table's mean coefficient at T, and PRHO falls by (1 + s)^3 so the mass
    stays."""
    cold = build_model(bore())
    for t_f in (-94.0, 365.0, 850.0):
        hot = build_model(at(bore(), f"OPERATING {t_f}\nASSEMBLY 20C\nPARTICLES wc\nWALLS ti"))
        table = RAW["tungsten-carbide"]["temperature"]["alpha_mean"]
        alpha = table_value(table, celsius(t_f)) * 1e-6 * 5.0 / 9.0  # per degF
        want = 0.0625 * (1.0 + alpha * (t_f - 68.0))
        assert hot.radius[0] == pytest.approx(want, rel=1e-14, abs=0.0)
        p = hot.particle_start
        assert hot.mass[p] == pytest.approx(cold.mass[p], rel=1e-14)


def test_a_bores_clearance_changes_by_the_difference_of_the_two_expansions():
    """Ti-6Al-4V bore (length 0.3, radius 9/128 in), 1/8 in WC sphere, assembled at 70 F."""
    length, big_r, r = 0.3, 0.0703125, 0.0625
    for t_f in (-94.0, 365.0, 850.0):
        model = build_model(at(bore(), f"OPERATING {t_f}F\nPARTICLES wc\nWALLS titanium"))
        s_w, s_p = strain("titanium", 70.0, t_f), strain("tungsten-carbide", 70.0, t_f)
        gaps = {c.what: c for c in model.temperature.clearances}
        along, across = gaps["cylinder along its axis"], gaps["cylinder across"]
        assert along.assembly == pytest.approx(length - 2 * r, rel=1e-13)
        assert across.assembly == pytest.approx(2 * (big_r - r), rel=1e-13)
        # the differences, to the rounding of a length of 0.3 in (1e-16 in)
        assert along.operating - along.assembly == pytest.approx(
            length * s_w - 2 * r * s_p, abs=2e-15
        )
        assert across.operating - across.assembly == pytest.approx(
            2 * big_r * s_w - 2 * r * s_p, abs=2e-15
        )
        # the bore grew about its axis' midpoint: A and B moved by -+ L s_w / 2 along x
        a, b = model.x0[model.shape_nodes[0]]
        assert (a[0], b[0]) == pytest.approx((-0.15 * s_w + 0.0, 0.3 + 0.15 * s_w), abs=1e-15)
        assert model.shape_params[0, 0] == pytest.approx(big_r * (1 + s_w), rel=1e-15)
        assert (along.operating > along.assembly) == (t_f > 70.0)  # Ti expands more than WC


def test_moduli_take_the_tables_ratio_and_friction_stays():
    """At 800 F, a point of Ti-6Al-4V's E table (91 GPa against 113.8 at 70 F): WALLMAT's E
    times 91/113.8 exactly, NU and MU as written; the carbide's table is constant (E0, E1 kept)."""
    model = build_model(at(bore(), "OPERATING 800F\nPARTICLES wc\nWALLS titanium"))
    table = RAW["titanium"]["temperature"]["E"]
    ratio = table["values"][table["T"].index(800)] / table["values"][table["T"].index(70)]
    e, nu, mu = model.wall_material[0]
    assert e == pytest.approx(16.5e6 * ratio, rel=1e-15)
    assert (nu, mu) == (0.342, 0.4)
    assert tuple(model.moduli[0]) == (7.6e7, 1.4e7)
    assert model.poisson[0] == 0.22


def test_a_triangulated_cavity_grows_about_its_centroid():
    """A fixed steel-304 box (x3dpd's box of 12 triangles, 1 x 0.5 x 0.25 in) at 850 F: every
    corner c + (1 + s)(x - c), c the corners' mean; the particle carried along; the clearance
    along x grows by 1 s_w - 2 r s_p."""
    steel = dict(e0=28e6, e1=0.0, tau1=1.0, nu=0.29, mu=0.3, density=7.5e-4)
    deck = closed_box_deck([(0.3, 0.2, 0.1)], [(0, 0, 0)], dt=1e-7, size=(1.0, 0.5, 0.25), **steel)
    cold = build_model(deck)
    hot = build_model(at(deck, "OPERATING 850F\nPARTICLES steel-302\nWALLS 1 steel-304"))
    s_w, s_p = strain_f("steel-304", 850.0), strain_f("steel-302", 850.0)
    centre = np.array([0.5, 0.25, 0.125])
    corners = cold.x0[:8]
    assert np.allclose(hot.x0[:8], centre + (1 + s_w) * (corners - centre), rtol=0, atol=1e-15)
    p = hot.particle_start
    assert np.allclose(hot.x0[p], centre + (1 + s_w) * (cold.x0[p] - centre), atol=1e-15)
    gaps = {c.what: c for c in hot.temperature.clearances}
    r = cold.radius[0]
    assert gaps["box along x"].operating - gaps["box along x"].assembly == pytest.approx(
        1.0 * s_w - 2 * r * s_p, abs=2e-15
    )


def strain_f(name: str, t_f: float) -> float:
    """The strain from 70 F to ``t_f`` of a degF mean table (the stainless steels')."""
    table = RAW[name]["temperature"]["alpha_mean"]
    assert table["T_unit"] == "degF" and table["unit"] == "1e-6/degF"

    def own(t):
        return table_value(table, t) * 1e-6 * (t - table["reference"])

    return (own(t_f) - own(70.0)) / (1.0 + own(70.0))


def test_at_the_assembly_temperature_the_model_is_the_decks_bit_for_bit():
    plain = build_model(bore())
    same = build_model(at(bore(), "OPERATING 70F\nASSEMBLY 70F\nPARTICLES wc\nWALLS titanium"))
    for f in fields(plain):
        a, b = getattr(plain, f.name), getattr(same, f.name)
        if f.name in ("temperature", "path", "units"):
            continue
        if isinstance(a, np.ndarray):
            assert a.tobytes() == b.tobytes(), f.name
        elif not callable(a):
            assert a == b, f.name


def test_check_prints_each_clearance_at_both_temperatures_and_warns_when_one_closes():
    """A steel-302 sphere (17e-6/K) in a tungsten-carbide bore (4.3e-6/K) 1e-4 in wider than it
    all round: at 850 F the sphere outgrows the bore by about 3e-4 in across."""
    tight = bore(r_bore=0.0626, pos=((0.15, 0.0, 0.0),))
    cold = check_model(build_model(at(tight, "OPERATING 70F\nPARTICLES steel-302\nWALLS wc")))
    assert not [w for w in cold.warnings if w.code == "clearance-closes"]
    report = check_model(build_model(at(tight, "OPERATING 850F\nPARTICLES ss-302\nWALLS wc")))
    (shut,) = [w for w in report.warnings if w.code == "clearance-closes"]
    assert "850 °F" in shut.headline and "70 °F" in shut.headline
    assert shut.details[0].startswith("set 1 cylinder across: 0.0002 at 70 °F, -0.000")
    lines = "\n".join(report.temperature)
    assert "clearance, set 1, cylinder along its axis: 0.175 at 70 °F" in lines
    assert "walls of set 1: tungsten-carbide, strain +" in lines


@pytest.mark.parametrize(
    ("card", "message"),
    [
        (
            "OPERATING 1200F\nPARTICLES wc\nWALLS titanium",
            "hot.inp:{line}:11: TEMPERATURE: OPERATING 1200F: material 'titanium': 1200 °F is "
            "outside its temperature table, -99.67 °F to 1000 °F",
        ),
        (
            "OPERATING 850F\nPARTICLES steel-beam\nWALLS titanium",
            "hot.inp:{line}:11: TEMPERATURE: OPERATING 850F: material 'steel-beam' has "
            "room-temperature values only",
        ),
        ("OPERATING 850F\nWALLS titanium", "TEMPERATURE: PDMP group NODLIM 3 has no material"),
        ("OPERATING 850F\nPARTICLES wc", "the walls of CONTACT set 1 have no material"),
        (
            "OPERATING 850F\nPARTICLES wc\nWALLS 2 titanium",
            "2 names no CONTACT set with walls (they are: 1)",
        ),
    ],
)
def test_a_card_the_materials_cannot_take_is_one_error_at_the_card(card, message):
    deck = at(bore(), card)
    line = hot_text(bore(), card).splitlines().index(card.splitlines()[0]) + 1
    with pytest.raises(DeckError) as info:
        build_model(deck)
    assert message.format(line=line) in str(info.value)
    assert "\n" not in str(info.value)


def test_a_bare_temperature_needs_the_units_card():
    with pytest.raises(DeckError) as info:
        at(bore(), "OPERATING 850\nPARTICLES wc\nWALLS ti", units=False)
    text = str(info.value)
    assert text.startswith("hot.inp:") and ": TEMPERATURE: OPERATING 850: a temperature " in text
    assert "needs the deck's UNITS card" in text and "850F, 850C or 850K" in text
    # with the card: degF in an inch deck, degC in a metric one
    assert at(bore(), "OPERATING 850\nPARTICLES wc\nWALLS ti").temperature.operating.unit == (
        "degF"
    )
    metric = replace(bore(), units=None)
    text = format_deck(metric) + "UNITS\n m N s\nEND\nTEMPERATURE\nOPERATING 455\nWALLS ti\nEND\n"
    assert parse_deck(text).temperature.operating.kelvin == pytest.approx(455 + 273.15)


def test_a_drilled_plates_holes_and_pitch_grow_with_the_plate():
    """decks/mip_apparatus_05.inp (PLATES: 0.505 in holes at 0.6 in pitch, plate 1 0.501 in
    thick + 0.009 in shim, 0.5 in spheres) with carbide spheres in SS-302 plates at 800 F: the
    free length changes by L s_w - 2 r s_p, the diametral clearance by 2 R s_w - 2 r s_p, and
    the holes' radius and pitch by (1 + s_w)."""
    from pathlib import Path

    deck_file = Path(__file__).resolve().parents[2] / "decks" / "mip_apparatus_05.inp"
    text = deck_file.read_text() + "UNITS\n in lbf s\nEND\n"
    text += "TEMPERATURE\n OPERATING 800F\n PARTICLES wc\n WALLS steel-302\nEND\n"
    model = build_model(parse_deck(text, "mip_hot.inp"))
    s_w, s_p = strain_f("steel-302", 800.0), strain("tungsten-carbide", 70.0, 800.0)
    gaps = {(c.set_id, c.what): c for c in model.temperature.clearances}
    along, across = gaps[(1, "holes along its axis")], gaps[(1, "holes across")]
    assert along.assembly == pytest.approx(0.01, abs=1e-14)
    assert along.operating - along.assembly == pytest.approx(0.51 * s_w - 0.5 * s_p, abs=2e-15)
    assert across.operating - across.assembly == pytest.approx(0.505 * s_w - 0.5 * s_p, abs=2e-15)
    first = int(np.flatnonzero(model.shape_cavity == 0)[0])
    assert model.shape_params[first, :2] == pytest.approx(
        (0.2525 * (1 + s_w), 0.6 * (1 + s_w)), rel=1e-14
    )
