"""``x3dpd DECK --dt auto``: a SIGKILL in the middle of a run with a step chosen by accuracy,
then ``--restart``, gives the uninterrupted run's trace and energy file byte for byte (the dump
keeps the driver's level); the summary and the sidecar say the step was auto and which steps
were used.

The scene: a 0.03125 in steel sphere dropped at 62.8 in/s onto a floor (gravity on) beside one
resting on it, DTMAX 2e-6 s: the resting sphere keeps the step at the contact step (level > 0),
so a resumed run that lost its level would step differently.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

from factories import G, floor_deck
from processes import kill_after_first_dump, x3dpd

from x3dpd.deck.writer import format_deck
from x3dpd.io.restart import load_restart

TMAX = 0.006  # 3,000 output intervals of 2e-6 s, three restart dumps: about a second of CPU time
TREST = 0.002


def write_deck(path: Path) -> None:
    deck = floor_deck(
        dt=2e-6, height=0.03125 + 0.003, velocity=(0.0, -62.8, 0.0), gravity=G, radius=0.03125
    )
    deck = replace(deck, parameters=replace(deck.parameters, tmax=TMAX, trest=TREST))
    path.write_text(format_deck(deck))  # DTMIN = DTMAX: auto only when asked


def test_sigkill_during_an_auto_step_run_then_restart_loses_nothing(tmp_path):
    ref, part = tmp_path / "ref", tmp_path / "part"
    for d in (ref, part):
        d.mkdir()
        write_deck(d / "drop.inp")
    args = ("drop.inp", "--dt", "auto", "--trace", "drop.trace.txt")
    res = x3dpd(*args, cwd=ref)
    assert res.returncode == 0, res.stderr
    assert "step chosen by accuracy" in res.stdout
    side = json.loads((ref / "drop.trace.txt.json").read_text())
    step = side["step"]
    assert side["dt"] == "auto" and step["mode"] == "auto"
    assert 2e-6 / 1024 <= step["min"] <= step["mean"] <= step["max"] <= 2e-6
    dump = part / "drop.trace.txt.restart.npz"
    kill_after_first_dump(*args, "--quiet", cwd=part, dump=dump)
    _, meta = load_restart(dump)
    assert 0 < meta["step"] < round(TMAX / 2e-6)
    assert meta["variable_step"]["level"] > 0
    # resuming at a fixed step is refused: the dump says auto
    res = x3dpd("drop.inp", "--trace", "drop.trace.txt", "--restart", "--quiet", cwd=part)
    assert res.returncode == 2 and "the step" in res.stderr
    res = x3dpd(*args, "--restart", "--quiet", cwd=part)
    assert res.returncode == 0, res.stderr
    for name in ("drop.trace.txt", "drop.energy.csv"):
        assert (part / name).read_bytes() == (ref / name).read_bytes()


def test_a_bad_step_word_is_a_clear_error(tmp_path):
    write_deck(tmp_path / "drop.inp")
    res = x3dpd("drop.inp", "--dt", "quick", "--quiet", cwd=tmp_path)
    assert res.returncode == 2 and "--dt" in res.stderr and "Traceback" not in res.stderr
