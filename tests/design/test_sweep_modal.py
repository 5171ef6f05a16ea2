"""Sweeps of modal structures (MODAL card): the closed-form baselines come from the modes (the
particles' mass coupled in like the housing's), a particle-free modal deck's simulated sweep
equals its FRF, and the predicted start puts the modes on their steady state."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from modal_decks import modal_deck

from x3dpd.deck.parser import read_deck
from x3dpd.design.baselines import (
    linear_modal,
    linear_structure,
    particle_mass,
    with_added_mass,
    without_particles,
)
from x3dpd.design.spec import SweepSpec
from x3dpd.design.steady_state import Criterion
from x3dpd.design.sweep import deck_hash, plan, run_sweep
from x3dpd.model.build import build_model

DECKS = Path(__file__).resolve().parents[2] / "decks"
TWO = [(1, 6.0, 0.04), (2, 17.0, 0.05)]
PHI = {1: (20.0, 14.0), 2: (9.0, -25.0)}


def _frf(hz, node_out, node_in=1):
    w = 2 * math.pi * hz
    return sum(
        PHI[node_out][k]
        * PHI[node_in][k]
        / ((2 * math.pi * f) ** 2 - w * w + 2j * z * (2 * math.pi * f) * w)
        for k, (_, f, z) in enumerate(TWO)
    )


def test_a_modal_decks_sweep_equals_its_frf(tmp_path):
    """Two modes, no particles: every point (each from its predicted start) within the
    criterion's 1e-3 plus the integrator's error of the two-mode FRF, and its ledger's input
    work per cycle is pi F |X| sin(-phi)."""
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
        frequencies=(5.0, 6.0, 11.0, 17.0),
        drives=(0.002,),
        node=1,
        dof=1,
        criterion=Criterion(tol=1e-3),
    )
    rows = run_sweep(spec, tmp_path / "out", workers=1)
    for r in rows:
        h = 0.002 * _frf(r["frequency_hz"], 1)
        assert r["converged"]
        assert r["start"] == "predicted"
        assert r["amplitude"] == pytest.approx(abs(h), rel=2e-3)
        assert math.radians(r["phase"]) == pytest.approx(np.angle(h), abs=2e-3)
        assert r["cycles"] <= 5 * 4  # on the steady state from the start: few windows


def test_modal_baselines_are_closed_form_rows(tmp_path):
    """decks/beam_64_modal.inp: both baselines are linear modal structures, so the sweep plans
    only the deck's own points; the undamped one is the modes with the cavity, the added-mass
    one has the particles' mass coupled in too (the reduced eigenproblem, computed here)."""
    deck = read_deck(DECKS / "beam_64_modal.inp")
    spec = SweepSpec(
        deck=deck,
        deck_text_hash="x",
        frequencies=(36.0, 37.5),
        drives=(4.8404e-3,),
        node=9,
        dof=1,
        baselines=("undamped", "added-mass"),
    )
    chains, closed = plan(spec)
    assert {p.config for chain in chains for p in chain} == {"deck"}
    assert sorted({r["config"] for r in closed}) == ["added-mass", "undamped"]
    bare = build_model(without_particles(deck))
    mp = particle_mass(build_model(deck))
    added = build_model(with_added_mass(deck, 9, mp))
    # coupling the particles' mass into the bare modes by hand
    ms = bare.modal
    j = int(np.flatnonzero(ms.nodes == bare.index_of(9))[0])
    phi = ms.shape[j, 0]
    lam = scipy.linalg.eigh(
        np.diag(ms.omega**2), np.eye(ms.n_modes) + mp * np.outer(phi, phi), eigvals_only=True
    )
    assert np.allclose(added.modal.omega, np.sqrt(lam), rtol=1e-10)
    lin = linear_structure(added, 9, 1)
    for r in (r for r in closed if r["config"] == "added-mass"):
        w = 2 * math.pi * r["frequency_hz"]
        assert r["amplitude"] == pytest.approx(abs(4.8404e-3 * lin.receptance(w)), rel=1e-12)
    assert linear_modal(build_model(deck), 9, 1) is None  # particles: not linear


def test_a_response_elsewhere_is_the_cross_frf(tmp_path):
    """Force at node 1, ``--response 2:1``: the response rows are the two-mode structure's cross
    FRF H_21 (computed here) within the criterion, and the undamped baseline's closed-form rows
    give it exactly; the CSV has a row per point and measured node."""
    from x3dpd.design.commands import sweep_command
    from x3dpd.design.sweep import read_csv

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
    rows = sweep_command(
        str(path),
        freq="6.0,11.0",
        amps=["0.002"],
        node=1,
        dof=1,
        responses=["2:1"],
        baselines=["undamped"],
        out=str(tmp_path / "o"),
        workers=1,
        echo=lambda s: None,
        criterion=Criterion(tol=1e-3),
    )
    for r in rows:
        (m,) = r["responses"]
        h = 0.002 * _frf(r["frequency_hz"], 2)
        rel = 2e-3 if r["method"] == "simulated" else 1e-12
        assert (m["response_node"], m["response_dof"]) == (2, 1)
        assert m["amplitude"] == pytest.approx(abs(h), rel=rel)
        assert math.radians(m["phase"]) == pytest.approx(np.angle(h), abs=max(rel, 1e-12))
        w = 2 * math.pi * r["frequency_hz"]
        assert m["accelerance"] == pytest.approx(w * w * abs(h) / 0.002, rel=rel)
    csv = read_csv(tmp_path / "o" / "sweep.csv")
    assert len(csv) == 2 * len(rows)
    assert sorted({(c["response_node"], c["response_dof"]) for c in csv}) == [
        (1.0, 1.0),
        (2.0, 1.0),
    ]
    assert (tmp_path / "o" / "sweep_responses.png").stat().st_size > 10000


def test_bad_responses_are_refused_before_anything_runs(tmp_path):
    from x3dpd.design.commands import sweep_command
    from x3dpd.errors import InputError

    path = tmp_path / "two.inp"
    path.write_text(
        modal_deck(dt=1e-4, tmax=1.0, modes=TWO, shapes=[(n, 1, v) for n, v in PHI.items()])
    )
    for bad, says in (("7:1", "not a node"), ("2:5", "DOF 1, 2 or 3"), ("2", "NODE:DOF")):
        with pytest.raises(InputError, match=says):
            sweep_command(
                str(path),
                freq="6",
                amps=["1"],
                node=1,
                dof=1,
                responses=[bad],
                out=str(tmp_path / "o"),
                workers=1,
                echo=lambda s: None,
            )
        assert not (tmp_path / "o").exists()


def test_ringdown_of_a_modal_structure_gives_its_modal_damping(tmp_path):
    """One mode (8 Hz, zeta 2 %), driven at resonance then released: `x3dpd ringdown`'s
    damping ratio is the mode's, within 3 % of it (the analysis's own error on an exact linear
    ring-down is below 1 %, tests/analysis/test_ringdown.py; the integrator adds 1e-5)."""
    from x3dpd.deck.parser import read_deck
    from x3dpd.design.ringdown import ringdown_of_deck

    path = tmp_path / "one.inp"
    path.write_text(
        modal_deck(
            dt=1e-4,
            tmax=10.0,
            modes=[(1, 8.0, 0.02)],
            shapes=[(1, 1, (30.0,))],
            drive="sine:node=1,dof=1,amp=0.01,hz=8.0",
        )
    )
    rd = ringdown_of_deck(read_deck(path), 1, 1, drive_until=3.0, ring=4.0)
    middle = rd.zeta[len(rd.zeta) // 4 : 3 * len(rd.zeta) // 4]
    assert np.median(middle) == pytest.approx(0.02, rel=0.03)


def test_a_particle_free_response_is_never_irregular(tmp_path):
    """Issue 33, item 14: from rest (no predicted start) the modes' start-up transient beats
    slowly and decays; without particles nothing scatters from cycle to cycle, so no point may
    be taken for chaos and let through a statistical test: each converges deterministically
    (extrapolated or window by window) within the tolerance of the two-mode FRF, or is
    flagged at the cap."""
    path = tmp_path / "two.inp"
    path.write_text(
        modal_deck(
            dt=1e-4,
            tmax=100.0,
            modes=[(1, 6.0, 0.004), (2, 17.0, 0.005)],
            shapes=[(n, 1, v) for n, v in PHI.items()],
            drive="sine:node=1,dof=1,amp=0.002,hz=6.0",
        )
    )
    spec = SweepSpec(
        deck=read_deck(path),
        deck_text_hash=deck_hash(path),
        frequencies=(9.0, 13.0),
        drives=(0.002,),
        node=1,
        dof=1,
        criterion=Criterion(tol=1e-3, predict=False, max_cycles=300),
    )
    rows = run_sweep(spec, tmp_path / "out", workers=1)
    for r in rows:
        w = 2 * math.pi * r["frequency_hz"]
        h = 0.002 * sum(
            PHI[1][k] ** 2 / ((2 * math.pi * f) ** 2 - w * w + 2j * z * (2 * math.pi * f) * w)
            for k, (f, z) in enumerate([(6.0, 0.004), (17.0, 0.005)])
        )
        assert not r["irregular"], r
        assert r["stopped_by"] in ("extrapolated", "window", "cap")
        if r["converged"]:
            assert r["amplitude"] == pytest.approx(abs(h), rel=2e-3)
            assert r["amplitude_ci"] <= 2e-3 * abs(h)
