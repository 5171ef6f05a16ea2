"""The solver's placement operations (x3dpd/solver/placement.py, through x3dpd.api.stepper): a
tool above the API puts a structure on a motion it predicted and books the energy that adds,
without touching the step loop's kernels or state arrays itself (x3dpd/design/predict.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from modal_decks import modal_deck

import x3dpd
from x3dpd.api.stepper import book_energy_change, place_modes, stepper, total_energy

#: Two mass-normalised modes (number, Hz, zeta) and their x shapes at nodes 1 and 2.
MODES = [(1, 6.0, 0.04), (2, 17.0, 0.05)]
PHI = {1: (20.0, 14.0), 2: (9.0, -25.0)}
DRIVE = 0.002  # [force] of the deck's sine at 6 Hz on node 1, x
DT = 1e-4  # [s]


@pytest.fixture()
def two_modes(tmp_path):
    path = tmp_path / "two.inp"
    path.write_text(
        modal_deck(
            dt=DT,
            tmax=1.0,
            modes=MODES,
            shapes=[(n, 1, v) for n, v in PHI.items()],
            drive=f"sine:node=1,dof=1,amp={DRIVE},hz=6.0",
        )
    )
    return x3dpd.build(path)


def test_a_modal_structure_placed_on_its_coordinates_books_their_energy(two_modes):
    """From rest, q and p (modal displacements and velocities of mass-normalised modes) put node
    n at x0 + sum_k phi_nk q_k moving at sum_k phi_nk p_k; the forces are those at the time
    placed (the drive F sin(2 pi 6 t)) and the modal forces their projection f = phi^T F, what
    the first step starts from; the energy booked is what the ledger counts of it
    (docs/physics.md, "Energy ledger"): the modes' 1/2 sum_k (p_k^2 + w_k^2 q_k^2) (the nodes
    carry no mass of their own) less the Verlet term h^2/8 sum_k f_k^2."""
    model = two_modes
    sim = stepper(model)
    e_before, ref_before = total_energy(sim), sim.state.e_ref
    q, p = np.array([1e-3, -2e-4]), np.array([0.05, 0.01])
    t = 0.3
    place_modes(sim, q, p)
    book_energy_change(sim, e_before, t)
    s = sim.state
    for node, phi in PHI.items():
        i = model.index_of(node)
        assert s.x[i, 0] - model.x0[i, 0] == pytest.approx(np.dot(phi, q), rel=1e-12)
        assert s.vel[i, 0] == pytest.approx(np.dot(phi, p), rel=1e-12)
    force = np.array([s.force[model.index_of(n), 0] for n in PHI])
    assert force[0] == pytest.approx(DRIVE * math.sin(2 * math.pi * 6.0 * t), rel=1e-12)
    assert force[1] == 0.0
    f = np.array([PHI[n] for n in PHI]).T @ force  # phi^T F, (modes,)
    assert np.allclose(s.mf, f, rtol=1e-12, atol=0.0)
    w = np.array([2 * math.pi * hz for _, hz, _ in MODES])
    booked = 0.5 * np.sum(p**2 + (w * q) ** 2) - DT**2 / 8 * np.sum(f**2)
    assert s.e_ref - ref_before == pytest.approx(booked, rel=1e-12)
