"""The documented ``--motion`` examples (docs/usrfrc.md) run on the shipped decks and their energy
ledger closes as well as the force-driven runs' do."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from x3dpd.deck import read_deck
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import ENERGY_COLUMNS, Simulation

DECKS = Path(__file__).resolve().parents[2] / "decks"
RESIDUAL = ENERGY_COLUMNS.index("residual")


@pytest.mark.parametrize(
    "deck, master",
    [
        ("appendix_a_cube.inp", 25),
        # a step loop of its own (external force + motion): ~40 s to compile on a cold cache
        pytest.param("beam_64.inp", 9, marks=pytest.mark.validate),
    ],
)
def test_documented_motion_example_runs_and_its_ledger_closes(deck, master):
    model = build_model(read_deck(DECKS / deck))
    amp, w = 0.01, 2 * np.pi * 37.21
    sim = Simulation(model, motion=[f"node={master},dof=1,amp={amp},hz=37.21"], itrac=200)
    first = sim.snapshot()
    energy = np.concatenate([first.energy, sim.advance(6000).energy])  # 3 ms
    mass = sim.setup.kin_mass[np.searchsorted(model.node_ids, master)]
    # the start's impulse is counted: 1/2 M (A w)^2 of work and of kinetic energy at t0
    work0 = 0.5 * mass * (amp * w) ** 2
    assert first.energy[0, ENERGY_COLUMNS.index("external_work")] == pytest.approx(work0, rel=1e-12)
    scale = np.abs(energy[:, 1:11]).max()
    assert scale >= work0
    # force-driven runs of these decks close to ~1e-3 of their scale after 50 ms; the old
    # bookkeeping left a residual equal to work0, 100 % of the scale
    assert np.abs(energy[:, RESIDUAL]).max() < 1e-3 * scale
