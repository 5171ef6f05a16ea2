"""``--freq auto:LO:HI`` through the sweep (x3dpd.design.auto_sweep): simulated structures whose
peaks are known in closed form, chains that honour their direction, resuming, Dask, bad input
(issue 30, item 3)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from cli_helpers import refused
from modal_decks import modal_deck
from test_sweep import TABLE4_C, TABLE4_DRIVE, TABLE4_K, TABLE4_MASS, sdof_file, spec_for

from x3dpd.deck.parser import read_deck
from x3dpd.design.spec import AutoBand, SweepSpec
from x3dpd.design.steady_state import Criterion
from x3dpd.design.sweep import deck_hash, read_csv, run_sweep


def _sdof_peak():
    """The Table 4 SDOF's displacement peak: f = f_n sqrt(1 - 2 zeta^2), X = F / (c w_d)."""
    wn = math.sqrt(TABLE4_K / TABLE4_MASS)
    zeta = TABLE4_C / (2 * math.sqrt(TABLE4_K * TABLE4_MASS))
    f = wn / (2 * math.pi) * math.sqrt(1 - 2 * zeta**2)
    x = TABLE4_DRIVE / TABLE4_K / (2 * zeta * math.sqrt(1 - zeta**2))
    return f, x


def test_a_particle_free_sdofs_peak_is_found_to_a_tenth_of_a_percent(tmp_path):
    """Simulated (the deck's own configuration), to the criterion's 1e-3: the peak's frequency
    and amplitude within 0.1 % of the closed form, with the coarse pass and one refinement
    point; a rerun finds every point stored."""
    spec = replace(
        spec_for(sdof_file(tmp_path), ()), auto=AutoBand(35.0, 40.0, 0.01, 7), frequencies=()
    )
    seen = []
    rows = run_sweep(spec, tmp_path / "out", workers=1, on_point=seen.append)
    (peak,) = read_csv(tmp_path / "out" / "peaks.csv")
    f, x = _sdof_peak()
    assert peak["converged"] == 1 and peak["at_edge"] == 0
    assert peak["peak_hz"] == pytest.approx(f, rel=1e-3)
    assert peak["peak_amplitude"] == pytest.approx(x, rel=1e-3)
    assert peak["band_lo_hz"] < f < peak["band_hi_hz"]
    assert len(rows) == len(seen) == peak["points"] == 5
    again = []
    run_sweep(spec, tmp_path / "out", workers=1, on_point=again.append)
    assert again == []  # resumed: nothing computed


TWO = [(1, 6.0, 0.01), (2, 8.0, 0.02)]
PHI = {1: (20.0, 14.0), 2: (9.0, -25.0)}


def test_two_modes_peak_is_found_to_a_tenth_of_a_percent(tmp_path):
    """A two-mode modal deck (no particles): the larger peak of its FRF, computed here."""
    path = tmp_path / "two.inp"
    path.write_text(
        modal_deck(
            dt=1e-4,
            tmax=100.0,
            modes=TWO,
            shapes=[(n, 1, v) for n, v in PHI.items()],
            drive="sine:node=1,dof=1,amp=0.002,hz=6.0",
        )
    )
    spec = SweepSpec(
        deck=read_deck(path),
        deck_text_hash=deck_hash(path),
        frequencies=(),
        drives=(0.002,),
        node=1,
        dof=1,
        criterion=Criterion(tol=1e-4),
        auto=AutoBand(4.5, 9.5, 0.005, 12),
    )
    run_sweep(spec, tmp_path / "out", workers=1)
    (peak,) = read_csv(tmp_path / "out" / "peaks.csv")
    f = np.linspace(4.5, 9.5, 200_001)
    w = 2 * np.pi * f
    h = 0.002 * sum(
        PHI[1][k] ** 2 / ((2 * np.pi * fk) ** 2 - w * w + 2j * z * 2 * np.pi * fk * w)
        for k, (_, fk, z) in enumerate(TWO)
    )
    k = int(np.argmax(np.abs(h)))
    assert peak["converged"] == 1
    assert peak["peak_hz"] == pytest.approx(f[k], rel=1e-3)
    assert peak["peak_amplitude"] == pytest.approx(abs(h[k]), rel=1e-3)


def test_a_down_chain_sweeps_down_and_refines_from_above(tmp_path):
    """direction down: the coarse points run 40 -> 35 Hz as one chain; each refinement point
    continues from the state of the computed point just above it."""
    spec = replace(
        spec_for(sdof_file(tmp_path), (), direction="down"),
        auto=AutoBand(35.0, 40.0, 0.01, 7),
        frequencies=(),
    )
    rows = run_sweep(spec, tmp_path / "out", workers=1)
    coarse = sorted(
        (
            r
            for r in rows
            if r["frequency_hz"] in (35.0, 40.0)
            or abs(r["frequency_hz"] - 36.666666666666664) < 1e-9
            or abs(r["frequency_hz"] - 38.333333333333336) < 1e-9
        ),
        key=lambda r: -r["frequency_hz"],
    )
    assert len(coarse) == 4 and coarse[0]["t_start"] == 0.0
    for before, after in zip(coarse, coarse[1:]):
        assert after["t_start"] == before["t_end"]  # one chain, downwards
    refined = [r for r in rows if r not in coarse]
    assert refined
    for r in refined:
        above = min(
            (
                c
                for c in rows
                if c["frequency_hz"] > r["frequency_hz"] and c["t_end"] <= r["t_start"]
            ),
            key=lambda c: c["frequency_hz"],
        )
        assert r["t_start"] == above["t_end"]


def test_dask_finds_the_same_peak_bit_for_bit(tmp_path):
    spec = replace(
        spec_for(sdof_file(tmp_path), ()), auto=AutoBand(35.0, 40.0, 0.01, 7), frequencies=()
    )
    run_sweep(spec, tmp_path / "serial", workers=1)
    run_sweep(spec, tmp_path / "dask", workers=2)
    assert (tmp_path / "serial" / "peaks.csv").read_bytes() == (
        tmp_path / "dask" / "peaks.csv"
    ).read_bytes()


@pytest.mark.parametrize(
    "freq", ["auto:40:35", "auto:35", "auto:35:40:0", "auto:35:40:0.1:3", "auto:a:b"]
)
def test_a_bad_auto_band_is_one_line(freq, tmp_path, capsys):
    path = sdof_file(tmp_path)
    refused(
        capsys,
        "sweep",
        str(path),
        "--freq",
        freq,
        "--amp",
        "0.001",
        "--node",
        "1",
        "--dof",
        "1",
        "--out",
        str(tmp_path / "out"),
        message="auto:LO:HI",
        folder=tmp_path,
        silent=True,
    )
