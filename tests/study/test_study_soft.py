"""Softer contacts as a measured fidelity choice (`x3dpd study --stiffness-scale`, issue 21
item 4): every modulus of the particles scaled, the step lengthened to match, the error against
the full-stiffness reference reported beside the run-to-run spread and the time saved."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from x3dpd.cli import main
from x3dpd.study import run_study
from x3dpd.study.settings import Setting, deck_for, ladder, soft_step

DECKS = Path(__file__).resolve().parents[2] / "decks"


def hertz_contact_time(e, v=62.832, r=0.0625, nu=0.33, rho=0.283 / 386.1):
    """Hertz (report 7.2.2): a sphere on a rigid wall, K = 4/3 E/(1 - nu^2) sqrt(R), a_max =
    (5 m v^2 / (4 K))^(2/5), t_c = 2.94 a_max / v (Timoshenko & Goodier)."""
    m = rho * 4 / 3 * math.pi * r**3
    k = 4 / 3 * e / (1 - nu**2) * math.sqrt(r)
    return 2.9432 * (5 * m * v * v / (4 * k)) ** 0.4 / v


def test_a_soft_setting_scales_every_modulus_and_lengthens_the_step():
    s = ladder(5e-7, viscoelastic=True, friction=False, chaotic=False, stiffness=(0.1, 0.01))
    soft = [x for x in s if x.stiffness != 1.0]
    assert [x.stiffness for x in soft] == [0.1, 0.01]
    assert soft[1].dt == pytest.approx(5e-7 * 100**0.4, rel=1e-12)
    assert "E x 0.01" in soft[1].label
    import x3dpd

    deck = x3dpd.load_deck(DECKS / "beam_64.inp")
    p0, p1 = deck.pdmp[0], deck_for(deck, Setting(soft_step(5e-7, 0.1), stiffness=0.1)).pdmp[0]
    assert (p1.e0, p1.e1, p1.t1) == (p0.e0 * 0.1, p0.e1 * 0.1, p0.t1)


def test_an_elastic_impact_at_e_over_100_lasts_100_to_the_2_5_longer_and_bounces_the_same(tmp_path):
    # Hertz: t_c ~ (m^2 / (R E*^2 v))^(1/5), so E/100 lasts 100^(2/5) = 6.31x longer; an
    # elastic law gives back all the energy whatever its stiffness (restitution 1)
    t_full = hertz_contact_time(3e7)
    assert hertz_contact_time(3e5) / t_full == pytest.approx(100**0.4, rel=1e-12)
    res = run_study(
        str(DECKS / "impact_wall.inp"),
        tmp_path / "s",
        tmax=1.2 * 100**0.4 * t_full,
        dts=[1e-9, 4e-9],
        stiffness=(0.01,),
    )
    ref = res.reference
    soft = next(r for r in res.rows if r["setting"].stiffness == 0.01)
    assert soft["setting"].dt == pytest.approx(1e-9 * 100**0.4)
    # contact time: the finest run resolves it to one step in ~7500, the soft one (at
    # 6.3e-9 s) to one in ~7500 as well: 1e-3 covers both
    assert ref["contact_time"] == pytest.approx(t_full, rel=1e-3)
    assert soft["contact_time"] / ref["contact_time"] == pytest.approx(100**0.4, rel=1e-3)
    assert soft["restitution"] == pytest.approx(ref["restitution"], abs=1e-4)
    # the peak force drops as E^(2/5) (F = K a^(3/2), K ~ E, a ~ E^(-2/5))
    assert soft["peak_force"] / ref["peak_force"] == pytest.approx(0.01**0.4, rel=1e-2)


def test_the_soft_rows_errors_are_against_the_full_stiffness_reference_beside_the_spread(
    tmp_path, capsys
):
    out = tmp_path / "b"
    with pytest.raises(SystemExit) as e:
        main(
            [
                "study",
                str(DECKS / "beam_64.inp"),
                "--tmax",
                "0.004",
                "--dt",
                "2.5e-7,5e-7",
                "--no-fidelity",
                "--stiffness-scale",
                "0.1",
                "--workers",
                "1",
                "--out",
                str(out),
                "-q",
            ]
        )
    assert e.value.code == 0
    with open(out / "study.csv") as f:
        rows = list(csv.DictReader(f))
    ref = rows[0]
    assert float(ref["dt"]) == 2.5e-7 and float(ref["stiffness_scale"]) == 1.0
    soft = [r for r in rows if float(r["stiffness_scale"]) == 0.1]
    assert len(soft) == 1 and float(soft[0]["dt"]) == pytest.approx(5e-7 * 10**0.4)
    own = next(r for r in rows if r["own"] == "1")
    for r in rows:
        assert float(r["spread"]) == float(ref["spread"]) >= 0  # the chaotic repeats' spread
        for q in ("amplitude", "power_per_cycle"):
            want = abs(float(r[q]) - float(ref[q])) / abs(float(ref[q]))
            assert float(r[f"{q}_error"]) == pytest.approx(want, rel=1e-9, abs=1e-15)
        assert float(r["speedup"]) == pytest.approx(
            float(own["wall_s_per_sim_s"]) / float(r["wall_s_per_sim_s"]), rel=1e-9
        )


def test_a_bad_stiffness_scale_is_refused(tmp_path, capsys):
    for bad in ("0", "2", "x"):
        with pytest.raises(SystemExit) as e:
            main(
                [
                    "study",
                    str(DECKS / "impact_wall.inp"),
                    "--stiffness-scale",
                    bad,
                    "--out",
                    str(tmp_path / "x"),
                    "--workers",
                    "1",
                ]
            )
        assert e.value.code == 2
        assert "--stiffness-scale" in capsys.readouterr().err
    # a HOOKE law's stiffness is its own card's, not the particles' moduli
    with pytest.raises(SystemExit) as e:
        main(
            [
                "study",
                str(DECKS / "hooke_wall.inp"),
                "--stiffness-scale",
                "0.1",
                "--out",
                str(tmp_path / "x"),
                "--workers",
                "1",
            ]
        )
    assert e.value.code == 2 and "HOOKE" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()
