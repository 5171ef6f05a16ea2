"""``x3dpd study --motion``: a base-driven deck is studied under its shaker, as ``x3dpd run
--motion`` runs it. The scene is driven at the motion's frequency and measured where the deck
traces it (the structure, not the shaker), along the motion's direction; a bad motion spec is a
clear error before anything runs or is written."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import x3dpd
from x3dpd.cli import main
from x3dpd.study.scene import classify, measure

DECK = Path(__file__).resolve().parents[2] / "decks" / "shaker_fig9.inp"
SHAKE = "node=4,dof=2,amp=0.02,hz=36.75"


def test_a_shaken_base_makes_a_driven_scene_measured_on_the_structure_along_the_motion():
    deck = x3dpd.load_deck(DECK)
    still = classify(x3dpd.build(deck))
    shaken = classify(x3dpd.build(deck, motion=[SHAKE]), motion=[SHAKE])
    assert still.kind == "free"  # without its shaker the table stands still
    assert shaken.kind == "driven" and shaken.drive_hz == 36.75
    assert shaken.node == deck.trace.nodes[0] == 1  # the beam's master node, not the base (4)
    assert shaken.axis == 1  # dof=2: y
    # a USRFRC force along x keeps the measured direction x
    beam = x3dpd.load_deck(DECK.with_name("beam_1.inp"))
    assert classify(x3dpd.build(beam)).axis == 0


def test_the_study_runs_under_the_motion_and_measures_the_motion_direction(tmp_path, capsys):
    """Ten drive cycles' worth of steps would be long; 400 steps (0.2 ms) of the shaken deck
    against the same window without its shaker: the base's motion moves the beam in y only
    when the study applies it (amplitude > 0), and the still run measures nothing."""
    out = tmp_path / "s"
    dt = x3dpd.load_deck(DECK).parameters.dtmax
    argv = ["study", str(DECK), "--tmax", repr(400 * dt), "--dt", repr(dt), "--no-fidelity"]
    argv += ["--workers", "1", "--out", str(out), "-q", "--motion", SHAKE]
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 0, capsys.readouterr().err
    import csv

    rows = list(csv.DictReader(open(out / "study.csv")))
    assert float(rows[0]["amplitude"]) > 0.0
    # the same measurement by hand on an x3dpd.run of the same window: y of node 1
    res = x3dpd.run(DECK, tmax=400 * dt, motion=[SHAKE], trace_nodes=[1])
    scene = classify(x3dpd.build(x3dpd.load_deck(DECK), motion=[SHAKE]), motion=[SHAKE])
    y = res.trace.position[:, 0, 1]
    third = res.trace.time >= res.trace.time[0] + (res.trace.time[-1] - res.trace.time[0]) * 2 / 3
    assert measure(res, scene)["amplitude"] == pytest.approx((y[third].max() - y[third].min()) / 2)
    assert not math.isnan(float(rows[0]["amplitude"]))


def test_a_bad_motion_spec_is_refused_before_anything_is_written(tmp_path, capsys):
    out = tmp_path / "s"
    with pytest.raises(SystemExit) as e:
        main(["study", str(DECK), "--out", str(out), "--motion", "node=4,dof=2,amp=0.02", "-q"])
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert "motion" in err and "Traceback" not in err
    assert not out.exists()
