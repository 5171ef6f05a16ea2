"""``x3dpd sweep`` and ``x3dpd ringdown`` end to end: files, exit statuses, one-line errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from factories import TABLE4_C, TABLE4_K, TABLE4_MASS, sdof_deck

from test_run import x3dpd  # noqa: E402  (tests/cli/test_run.py: run the CLI in-process)

from x3dpd.api import run
from x3dpd.deck.writer import write_deck
from x3dpd.design.sweep import read_csv


@pytest.fixture
def sdof(tmp_path):
    path = tmp_path / "sdof.inp"
    write_deck(sdof_deck(dt=1e-5, hz=37.0), path)
    return path


def test_sweep_writes_csv_and_png(capsys, sdof, tmp_path):
    out = tmp_path / "out"
    code, stdout, err = x3dpd(
        capsys,
        "sweep",
        sdof,
        "--freq",
        "38:39:0.5",
        "--amp",
        "4.8404e-3",
        "--out",
        out,
        "--workers",
        "1",
        "--baseline",
        "added-mass",
    )
    assert code == 0, err
    rows = read_csv(out / "sweep.csv")
    assert [(r["config"], r["frequency_hz"]) for r in rows] == [
        ("deck", 38.0),
        ("deck", 38.5),
        ("deck", 39.0),
        ("added-mass", 38.0),
        ("added-mass", 38.5),
        ("added-mass", 39.0),
    ]
    assert (out / "sweep.png").stat().st_size > 0
    assert "peak attenuation" in stdout


@pytest.mark.parametrize(
    "args, message",
    [
        (("--freq", "40:35:1"), "--freq '40:35:1': expected START:STOP:STEP"),
        (("--freq", "36", "--amp", "x"), "--amp 'x': expected a drive amplitude"),
        (("--freq", "36", "--baseline", "nothing"), "unknown baseline 'nothing'"),
        (("--freq", "36", "--dof", "5"), "dof 1, 2 or 3"),
        (("--freq", "36", "--node", "7"), "node 7 is not a node of"),
    ],
)
def test_sweep_bad_input_is_one_line_and_exit_2(capsys, sdof, tmp_path, args, message):
    full = ["sweep", sdof, "--out", tmp_path / "out", "--workers", "1", *args]
    if "--amp" not in args:
        full += ["--amp", "1e-3"]
    code, _, err = x3dpd(capsys, *full)
    assert code == 2
    assert message in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_ringdown_of_a_solver_trace_gives_the_structures_zeta(capsys, tmp_path):
    # Table 4 beam released with an initial velocity: a free linear ring-down whose damping
    # ratio is c / (2 sqrt(k m)) exactly
    deck = tmp_path / "free.inp"
    write_deck(sdof_deck(dt=1e-5, hz=37.0, drive=0.0, v0=5.0, itrac=10), deck)
    trace = tmp_path / "free.trace.txt"
    run(deck, tmax=3.0, trace=trace)
    code, stdout, err = x3dpd(
        capsys, "ringdown", trace, "--node", 1, "--dof", 1, "--out", tmp_path / "rd"
    )
    assert code == 0, err
    lines = (tmp_path / "rd" / "ringdown.csv").read_text().splitlines()
    head = lines[0].split(",")
    zeta = np.array([float(line.split(",")[head.index("zeta")]) for line in lines[1:]])
    exact = TABLE4_C / (2 * math.sqrt(TABLE4_K * TABLE4_MASS))
    # the method's own error on an exact exponential is < 0.2 % (tests/analysis), the
    # integrator's O((w dt)^2) = 6e-6
    np.testing.assert_allclose(zeta, exact, rtol=2e-3)
    assert (tmp_path / "rd" / "ringdown.png").stat().st_size > 0
    # an existing result is not replaced without --overwrite
    code, _, err = x3dpd(capsys, "ringdown", trace, "--node", 1, "--out", tmp_path / "rd")
    assert code == 2 and "--overwrite" in err
    code, _, err = x3dpd(capsys, "ringdown", trace, "--node", 7, "--out", tmp_path / "rd2")
    assert code == 2 and "node 7 is not in the trace" in err
    code, _, err = x3dpd(capsys, "ringdown", trace, "--out", tmp_path / "rd3")
    assert code == 2 and "give --node N" in err


def test_a_ring_too_short_for_the_analysis_is_refused_before_any_step(capsys, tmp_path):
    """beam_1 is one rigid body on one spring along x: f = sqrt(k / m) / (2 pi) before the run,
    and its particle only lowers it. --ring 0.3 s holds at most 0.3 f = 11.3 cycles, fewer than
    the 2 x 3 trimmed + 2 x 4 spline cycles the analysis needs: refused at once (it used to
    run the drive, the ring and the baseline, then fail), nothing written."""
    from x3dpd.api import load_deck
    from x3dpd.model.build import build_model

    deck = Path(__file__).resolve().parents[2] / "decks" / "beam_1.inp"
    model = build_model(load_deck(deck))
    k = float(model.spring_k[model.spring_k[:, 0] != 0, 0][0])
    f = math.sqrt(k / float(model.rigid_mass[0])) / (2.0 * math.pi)
    out = tmp_path / "rd"
    code, _, err = x3dpd(
        capsys, "ringdown", deck, "--drive-until", 0.1, "--ring", 0.3, "--out", out
    )
    assert code == 2, err
    assert f"at most {0.3 * f:.1f} cycles of the structure's {f:.4g} Hz" in err
    assert "needs at least 14: give " in err and "Traceback" not in err
    assert not out.exists()


def test_an_unreachable_scheduler_is_refused_before_anything_is_written(
    capsys, tmp_path, monkeypatch
):
    """--scheduler naming an address where no scheduler answers (port 1 of this machine) used
    to end a sweep in a Dask traceback after 30 s, with sweep.json and points/ written; sweep,
    study and design now refuse it in one line naming the address and how to start one, and
    write no output folder. (The wait is shortened here; it is 10 s by default.)"""
    import x3dpd.api.cluster

    from cli_helpers import refused

    monkeypatch.setattr(x3dpd.api.cluster, "CONNECT_TIMEOUT", 1.0)
    beam_1 = Path(__file__).resolve().parents[2] / "decks" / "beam_1.inp"
    spec = tmp_path / "d.toml"
    spec.write_text(
        f'structure = "{beam_1}"\n[evaluate]\nkind = "sweep"\ndrives = [1e-3]\nfrequencies = [37]\n'
    )
    address = "tcp://127.0.0.1:1"
    message = f"--scheduler {address}: no Dask scheduler answers there ("
    for args in (
        ("sweep", beam_1, "--freq", 37, "--amp", 1e-3, "--out", tmp_path / "sw"),
        ("study", beam_1, "--tmax", 0.01, "--out", tmp_path / "st"),
        ("design", spec, "--out", tmp_path / "ds"),
    ):
        line = refused(capsys, *args, "--scheduler", address, message=message, folder=tmp_path)
        assert "`dask scheduler`" in line


def test_ringdown_reads_one_g_in_the_deck_s_units(capsys, tmp_path):
    """dB re 1 g divides the acceleration amplitude A w^2 by one standard gravity in the deck's
    units. A metric deck's (UNITS m N s) was divided by 386.1 -- inches per s^2 -- unless --g
    was given: 32 dB off. Now the trace's sidecar units choose it (9.80665 m/s^2), and --g
    still overrides; --g 0 (an infinite dB column) is refused."""
    import dataclasses

    from x3dpd.deck.cards import Units

    deck = tmp_path / "metric.inp"
    cards = sdof_deck(dt=1e-5, hz=37.0, drive=0.0, v0=5.0, itrac=10)
    write_deck(dataclasses.replace(cards, units=Units("m", "N", "s")), deck)
    trace = tmp_path / "metric.trace.txt"
    run(deck, tmax=3.0, trace=trace)

    def ratio(out, *g):
        code, _, err = x3dpd(capsys, "ringdown", trace, "--node", 1, "--out", out, *g)
        assert code == 0, err
        lines = (out / "ringdown.csv").read_text().splitlines()
        head = lines[0].split(",")
        col = {k: np.array([float(r.split(",")[head.index(k)]) for r in lines[1:]])
               for k in ("amplitude", "frequency_hz", "amplitude_g")}  # fmt: skip
        return col["amplitude_g"] / (col["amplitude"] * (2 * math.pi * col["frequency_hz"]) ** 2)

    np.testing.assert_allclose(ratio(tmp_path / "own"), 1 / 9.80665, rtol=1e-12)
    np.testing.assert_allclose(ratio(tmp_path / "given", "--g", 2.0), 0.5, rtol=1e-12)
    code, _, err = x3dpd(capsys, "ringdown", trace, "--node", 1, "--out", tmp_path / "z", "--g", 0)
    assert code == 2 and "--g" in err
