"""`x3dpd study`: the ladder, the errors against the finest run, the Pareto front, the verdict,
the files (every shipped deck: test_study_decks.py).

Closed form for the impact scene: the Hertz peak force of a sphere on a rigid wall,
F_max = K a_max^(3/2) with a_max = (5 m v^2 / 4K)^(2/5), K = 4/3 E/(1-nu^2) sqrt(R) (report
Sec. 7.2.2; decks/impact_wall.inp's header: 22.96 lbf). The finest run must find it within the
sampling error of a peak resolved at ~1e4 steps per contact, (pi/n)^2/2 ~ 1e-7, plus the
m dv/dt estimate's error (mean of two force samples) of the same order: 1e-4 allows both.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from x3dpd.cli import main
from x3dpd.study import run_study
from x3dpd.study.settings import Setting, ladder

DECKS = Path(__file__).resolve().parents[2] / "decks"


def hertz_peak_force(v=62.832, r=0.0625, e=30e6, nu=0.33, rho=0.283 / 386.1):
    m = rho * 4 / 3 * math.pi * r**3
    k = 4 / 3 * e / (1 - nu**2) * math.sqrt(r)
    a = (5 * m * v * v / (4 * k)) ** 0.4
    return k * a**1.5


def test_the_ladder_marks_the_deck_setting_and_adds_fidelity_and_repeats():
    s = ladder(5e-7, viscoelastic=True, friction=True, chaotic=True)
    own = [x for x in s if x.own]
    assert len(own) == 1 and own[0].dt == 5e-7
    assert [
        x.dt for x in s if x.contact == "deck" and x.friction == "regularized" and not x.repeat
    ] == [1.25e-7, 2.5e-7, 5e-7, 1e-6, 2e-6, 4e-6]
    assert Setting(5e-7, contact="elastic") in s and Setting(5e-7, friction="coulomb") in s
    assert sum(1 for x in s if x.repeat) == 3
    # the tangential laws as fidelity choices: the report's two and Hertz-Mindlin
    assert Setting(5e-7, friction="mindlin") in s


def test_a_deck_with_a_friction_card_is_studied_under_its_own_law():
    """A deck whose FRICTION card selects Hertz-Mindlin runs every setting under that law
    (the study does not override the card with the default), and offers the report's two
    Coulomb laws as the fidelity choices."""
    s = ladder(5e-7, viscoelastic=False, friction=True, chaotic=True, friction_law="mindlin")
    assert all(x.friction == "mindlin" for x in s if x.own or x.repeat)
    assert {x.friction for x in s if not x.own and x.dt == 5e-7 and not x.repeat} == {
        "regularized",
        "coulomb",
    }


def test_an_impact_study_measures_the_hertz_peak_force(tmp_path):
    res = run_study(
        str(DECKS / "impact_wall.inp"),
        tmp_path / "out",
        tmax=1.0e-5,
        dts=[1e-9, 4e-9, 1.6e-8, 6.4e-8],
    )
    assert res.scene.kind == "impact" and not res.scene.chaotic
    assert res.reference["peak_force"] == pytest.approx(hertz_peak_force(), rel=1e-4)
    assert res.reference["restitution"] == pytest.approx(1.0, abs=1e-4)
    errors = [r["error"] for r in res.rows]
    assert errors[0] == 0.0 and all(e >= 0 for e in errors)
    # coarser steps err more: peak sampling error grows like dt^2 (4x step, ~16x error)
    assert errors[-1] > errors[1]
    assert any(r["pareto"] for r in res.rows)
    with open(tmp_path / "out" / "study.csv") as f:
        rows = list(csv.DictReader(f))
    assert {"dt", "wall_s_per_sim_s", "error"} <= set(rows[0])
    assert [float(r["dt"]) for r in rows] == [1e-9, 4e-9, 1.6e-8, 6.4e-8]
    assert (tmp_path / "out" / "study.png").stat().st_size < 300_000
    assert "peak force" in res.verdict


def test_the_cli_refuses_to_overwrite_and_prints_a_verdict(tmp_path, capsys):
    argv = [
        "study",
        str(DECKS / "impact_wall.inp"),
        "--tmax",
        "1e-5",
        "--dt",
        "2e-9,8e-9",
        "--out",
        str(tmp_path / "s"),
        "--workers",
        "1",
        "--tol",
        "1%",
    ]
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 0 and "verdict: " in capsys.readouterr().out
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2 and "--overwrite" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        main(argv + ["--overwrite", "--tol", "150%"])
    assert e.value.code == 2


def test_the_printed_appendix_a_deck_is_refused(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        main(
            [
                "study",
                str(DECKS / "appendix_a.inp"),
                "--tmax",
                "1e-4",
                "--workers",
                "1",
                "--out",
                str(tmp_path / "a"),
            ]
        )
    assert e.value.code == 2
    assert not (tmp_path / "a" / "study.csv").exists()


def test_a_driven_many_particle_deck_is_called_chaotic_and_compared_with_its_spread(tmp_path):
    res = run_study(
        str(DECKS / "beam_64.inp"),
        tmp_path / "b",
        tmax=0.004,
        dts=[2.5e-7, 5e-7, 1e-6],
        fidelity=False,
    )
    assert res.scene.kind == "driven" and res.scene.chaotic and res.scene.node == 9
    assert "chaotic" in res.verdict and res.spread >= 0
    assert sum(1 for r in res.rows if r["setting"].repeat) == 3
    for r in res.rows:
        assert r["status"] == "complete" and r["amplitude"] > 0


def test_the_step_chosen_by_accuracy_shows_as_auto(tmp_path):
    res = run_study(
        str(DECKS / "beam_1.inp"),
        tmp_path / "a",
        tmax=0.02,
        dts=[2.5e-7, 5e-7, "auto"],
        fidelity=False,
    )
    auto = [r for r in res.rows if r["setting"].auto]
    assert len(auto) == 1 and auto[0]["status"] == "complete"
    assert auto[0]["error"] < 0.01  # within the 1 % the study accepts by default
    with open(tmp_path / "a" / "study.csv") as f:
        assert [r["dt"] for r in csv.DictReader(f)][-1] == "auto"


def test_a_window_too_short_to_measure_says_so(tmp_path):
    res = run_study(str(DECKS / "beam_1.inp"), None, tmax=2e-6, dts=[2.5e-7, 5e-7], fidelity=False)
    assert "longer --tmax" in res.verdict or "within" in res.verdict


def test_wall_choices_run_the_library_material_on_every_cavity(tmp_path):
    """``walls=("rigid", "acrylic")`` on the rigid-walled impact deck adds one run, its cavity
    acrylic (x3dpd.materials: E 3.1 GPa, nu 0.37, in the deck's psi): its peak force is Hertz's
    with the mixed modulus 1/E* = (1 - nu_s^2)/E_s + (1 - nu_w^2)/E_w, to 1e-3 (the rigid
    deck's peak is Hertz's to 1e-4 at this step, above), and "rigid" is the deck's own walls,
    not run twice."""
    res = run_study(
        str(DECKS / "impact_wall.inp"),
        tmp_path / "out",
        tmax=6e-5,
        dts=[1e-9],
        walls=("rigid", "acrylic"),
        fidelity=False,
    )
    assert [r["setting"].walls for r in res.rows] == ["deck", "acrylic"]
    e_wall, nu_wall = 3.1e9 / 6894.757293168361, 0.37  # Pa -> psi
    e_star = 1.0 / ((1 - 0.33**2) / 30e6 + (1 - nu_wall**2) / e_wall)
    soft = res.rows[1]
    assert soft["setting"].label == "dt 1e-09 walls acrylic"
    assert soft["peak_force"] == pytest.approx(hertz_peak_force(e=e_star * (1 - 0.33**2)), rel=1e-3)
    assert soft["cpu_s_per_sim_s"] > 0
    with open(tmp_path / "out" / "study.csv") as f:
        assert [r["walls"] for r in csv.DictReader(f)] == ["deck", "acrylic"]


def test_wall_choices_refuse_an_unknown_material_and_a_hooke_deck(tmp_path):
    argv = [
        "study",
        str(DECKS / "impact_wall.inp"),
        "--tmax",
        "1e-5",
        "--dt",
        "2e-9",
        "--out",
        str(tmp_path / "s"),
        "--workers",
        "1",
        "--walls",
        "rigid,unobtainium",
    ]
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2 and not (tmp_path / "s").exists()
    argv = [
        "study",
        str(DECKS / "hooke_wall.inp"),
        "--tmax",
        "1e-5",
        "--dt",
        "2e-8",
        "--out",
        str(tmp_path / "h"),
        "--workers",
        "1",
        "--walls",
        "acrylic",
    ]
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2 and not (tmp_path / "h").exists()
