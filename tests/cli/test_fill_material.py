"""``x3dpd fill --material NAME`` and the time step a filled deck gets (issue 20, item 2).

The step contract: a filled deck's DTMAX is the step ``x3dpd check`` recommends for ITS
particles (here recomputed from Hertz's closed form, not read back from the code), so that
``x3dpd check`` finds the deck clean; ``--dt`` overrides it, ``--keep-dt`` keeps the template's.
"""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from cli_helpers import DECKS, run_cli

from x3dpd.deck import read_deck
from x3dpd.deck.generate import Material3, box_cavity_deck, lattice_fill
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model

INCH = 0.0254
LBF = 0.45359237 * 9.80665
PSI = LBF / INCH**2
G = 386.1  # beam_64's BODY [in/s^2]
CAVITY = (0.263, 0.372, 0.372)  # beam_64's cavity [in]


def hertz_wall_step(radius, rho, e_inst, nu, steps=50):
    """Section 7.2.1-7.2.2: a sphere on a rigid wall, E* = E/(1 - nu^2), at the speed of a fall
    across the cavity's largest extent, v = sqrt(2 g L): delta_m = (15 m v^2 / (16 E* sqrt R))
    ^(2/5), t_c = 2.9432 delta_m / v; the step is t_c / 50."""
    m = rho * 4.0 / 3.0 * math.pi * radius**3
    v = math.sqrt(2.0 * G * max(CAVITY))
    e_star = e_inst / (1.0 - nu**2)
    delta = (15.0 * m * v**2 / (16.0 * e_star * math.sqrt(radius))) ** 0.4
    return 2.9432 * delta / v / steps


def test_small_spheres_get_the_step_they_need_and_check_is_clean(tmp_path, capsys):
    """The issue's case: 200 spheres of R 0.02 in beam_64 (template DTMAX 5e-7 s)."""
    out = tmp_path / "x.inp"
    assert run_cli("fill", DECKS / "beam_64.inp", "--n", 200, "--radius", 0.02, "-o", out) == 0
    assert "recommended" in capsys.readouterr().out
    tpl, deck = read_deck(DECKS / "beam_64.inp"), read_deck(out)
    want = hertz_wall_step(0.02, 7.32971e-4, 27.5e6 + 5.0e6, 0.33)
    dt = deck.parameters.dtmax
    assert want * 0.99 < dt <= want * (1 + 1e-3)  # floored to 3 digits; the constant 2.9432
    assert deck.parameters.dtmin == dt  # a constant-step deck stays one
    # the trace keeps its interval: ITRAC x DTMAX = the template's (to one step)
    interval = tpl.parameters.itrac * tpl.parameters.dtmax
    assert abs(deck.parameters.itrac * dt - interval) <= dt
    # the template's step would have been flagged: the premise of the issue
    coarse = check_model(build_model(replace(deck, parameters=tpl.parameters)))
    assert [w for w in coarse.warnings if w.code == "time-step"]
    assert tpl.parameters.dtmax / dt > 7
    # and x3dpd check on the written deck: clean, exit 0, no note
    capsys.readouterr()
    assert run_cli("check", out) == 0
    assert f"{out}: clean\n" in capsys.readouterr().out


def test_dt_given_is_kept_and_keep_dt_keeps_the_template(tmp_path, capsys):
    out = tmp_path / "x.inp"
    assert run_cli("fill", DECKS / "beam_64.inp", "--n", 10, "--dt", 2.5e-8, "-o", out) == 0
    assert read_deck(out).parameters.dtmax == 2.5e-8
    assert "as given" in capsys.readouterr().out
    assert (
        run_cli("fill", DECKS / "beam_64.inp", "--n", 10, "--keep-dt", "-o", out, "--overwrite")
        == 0
    )
    kept, tpl = read_deck(out).parameters, read_deck(DECKS / "beam_64.inp").parameters
    assert (kept.dtmin, kept.dtmax, kept.itrac) == (tpl.dtmin, tpl.dtmax, tpl.itrac)
    assert (
        run_cli(
            "fill",
            DECKS / "beam_64.inp",
            "--n",
            10,
            "--keep-dt",
            "--dt",
            1e-7,
            "-o",
            tmp_path / "y.inp",
        )
        == 2
    )
    assert "exclude each other" in capsys.readouterr().err
    assert not (tmp_path / "y.inp").exists()


def test_fill_by_material_sets_the_pdmp_card_and_the_mass(tmp_path, capsys):
    """Tungsten carbide (library: 620 GPa, 14.95 g/cm^3, nu 0.22, mu 0.40, elastic) into the
    report's inch-lbf-s deck: PDMP E0 = 620e9 Pa / psi, PRHO = 14950 kg/m^3 in^4 / lbf, E1 = 0;
    each particle's mass 4/3 pi R^3 PRHO; the step follows the stiffer, heavier spheres."""
    out = tmp_path / "wc.inp"
    r = 0.03125
    assert (
        run_cli(
            "fill", DECKS / "beam_64.inp", "--n", 20, "--material", "Tungsten Carbide", "-o", out
        )
        == 0
    )
    assert "material tungsten-carbide" in capsys.readouterr().out
    deck = read_deck(out)
    pd = deck.pdmp[0]
    rho = 14950.0 * INCH**4 / LBF
    assert pd.e0 == pytest.approx(620e9 / PSI, rel=1e-11)
    assert pd.prho == pytest.approx(rho, rel=1e-11)
    assert (pd.ppoi, pd.pcof, pd.e1) == (0.22, 0.40, 0.0) and pd.t1 > 0
    report = check_model(build_model(deck))
    assert report.groups[0].mass == pytest.approx(4 / 3 * math.pi * r**3 * rho, rel=1e-12)
    want = hertz_wall_step(r, rho, 620e9 / PSI, 0.22)
    assert want * 0.99 < deck.parameters.dtmax <= want * (1 + 1e-3)
    assert not report.warnings


def test_unknown_material_is_an_error_that_names_close_ones(tmp_path, capsys):
    out = tmp_path / "x.inp"
    assert run_cli("fill", DECKS / "beam_64.inp", "--material", "tungstn", "-o", out) == 2
    err = capsys.readouterr().err
    assert "unknown material 'tungstn'" in err and "tungsten" in err and "Traceback" not in err
    assert not out.exists()


def test_generator_takes_library_names():
    """x3dpd.deck.generate by name: lead (16 GPa, 11.34 g/cm^3, nu 0.44, mu 0.95) in psi."""
    size = (0.3, 0.3, 0.3)
    pos = lattice_fill(size, 0.05, 4)
    kw = dict(
        size=size, particles=pos, radius=0.05, structure_mass=1e-3, stiffness=10.0, damping=1e-4
    )
    pd = box_cavity_deck(material="lead", **kw).pdmp[0]
    assert pd.e0 == pytest.approx(16e9 / PSI, rel=1e-11)
    assert pd.prho == pytest.approx(11340.0 * INCH**4 / LBF, rel=1e-11)
    assert (pd.ppoi, pd.pcof) == (0.44, 0.95)
    beam = box_cavity_deck(material="beam steel", **kw).pdmp[0]
    assert (beam.e0, beam.e1, beam.t1, beam.prho) == (27.5e6, 5.0e6, 2.0e-6, 7.32971e-4)
    assert Material3.named("beam steel") == Material3(27.5e6, 5.0e6, 2.0e-6, 0.33, 0.30, 7.32971e-4)


def test_a_generated_deck_gets_its_step_through_the_api():
    """x3dpd.deck.generate writes the DTMAX it is given; x3dpd.fit_time_step sets the one its
    particles need (the same estimate as fill), check clean; a variable-step deck keeps a
    smaller DTMIN."""
    import x3dpd

    r = 0.01
    pos = lattice_fill(CAVITY, r, 30, gap=0.05 * r)
    deck = box_cavity_deck(
        size=CAVITY,
        particles=pos,
        radius=r,
        material="alumina",
        structure_mass=2.04213e-4,
        stiffness=11.4823,
        damping=3.08293e-4,
    )
    assert [w.code for w in check_model(build_model(deck)).warnings] == ["time-step"]
    fitted = x3dpd.fit_time_step(deck)
    rho = 3890.0 * INCH**4 / LBF
    want = hertz_wall_step(r, rho, 370e9 / PSI, 0.22)
    assert want * 0.99 < fitted.dt <= want * (1 + 1e-3)
    assert fitted.deck.parameters.dtmax == fitted.dt and fitted.advice.binding == "contact"
    assert not check_model(build_model(fitted.deck)).warnings
    variable = replace(deck, parameters=replace(deck.parameters, dtmin=1e-9))
    assert x3dpd.fit_time_step(variable).deck.parameters.dtmin == 1e-9
    assert x3dpd.fit_time_step(deck, dt=3e-8).deck.parameters.dtmax == 3e-8


def test_material_follows_the_templates_units(tmp_path):
    """A template declaring UNITS mm N s gets MPa and t/mm^3: E0 = 620e9 Pa / 1e6, PRHO =
    14950 kg/m^3 x 1e-12 (t = 1000 kg, mm^3 = 1e-9 m^3)."""
    from x3dpd.deck.cards import Units
    from x3dpd.deck.writer import write_deck

    tpl = tmp_path / "mm.inp"
    write_deck(replace(read_deck(DECKS / "beam_64.inp"), units=Units("mm", "N", "s")), tpl)
    out = tmp_path / "out.inp"
    assert run_cli("fill", tpl, "--n", 5, "--material", "wc", "--keep-dt", "-o", out) == 0
    pd = read_deck(out).pdmp[0]
    assert pd.e0 == pytest.approx(620e9 / 1e6, rel=1e-11)
    assert pd.prho == pytest.approx(14950.0 * 1e-12, rel=1e-11)
