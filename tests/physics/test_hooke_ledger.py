"""The energy ledger of a linear (HOOKE) impact closes to round-off at any step.

Velocity Verlet (x3dpd/solver/_advance_template.py) satisfies, for *any* sequence of forces,

    KE(n+1) - KE(n) = 1/2 (f(n) + f(n+1)) . (x(n+1) - x(n)) + dt^2/8 (|f(n+1)|^2 - |f(n)|^2)/m,

so KE - S plus the trapezoidal work of the forces is constant to round-off (S = dt^2/8 sum f^2/m,
the ledger's Verlet term). The ledger books the contact's work as that trapezoid, so its residual
closes to round-off whatever the law -- provided every step of a contact is booked, including the
one on which it opens: the force jumps from 0 (the particle was a gap g < 0 away) to
F = k_n a + c_n da/dt, and that step's work is 1/2 F (a - g), not 1/2 F a. The unclamped dashpot
makes F about c_n v at the onset, so the difference, 1/2 F (-g), is up to 1/2 c_n v^2 dt per
contact: decks/hooke_wall.inp, whose onset falls on a step (the gap is 5000 steps of 10 in/s),
ended at exactly -1/2 c_n v^2 dt = -6.134e-9 lbf in before the onset was booked from the gap.

The tolerance: the identity holds in exact arithmetic; in floating point every step rounds the
position update (ulp(x) ~ 7e-18 in at x ~ 0.06 in) under a force of at most k_n a_max + c_n v ~ 3
lbf, so each contact step may misbook ~2e-17 lbf in; a contact of 2727 steps (dt = 1e-8 s) adds
at most ~6e-14, 1.6e-9 of the 3.7e-5 lbf in the sphere brings. We allow 1e-8 of that energy:
6000 times below the defect at this step (1.64e-4), and far below it at every other step.
"""

from __future__ import annotations

import dataclasses
import math
import pathlib

import numpy as np
import pytest


from factories import STEEL_R, pair_deck, sphere_mass

from x3dpd.deck import read_deck
from x3dpd.deck.cards import Hooke
from x3dpd.model.build import build_model
from x3dpd.physics.hooke import damping_ratio
from x3dpd.solver.simulation import Simulation

DECK = pathlib.Path(__file__).resolve().parents[2] / "decks" / "hooke_wall.inp"
#: Residual allowed, as a fraction of the impact's kinetic energy (module docstring).
ROUND_OFF = 1e-8
RESIDUAL = 11  # ledger column (x3dpd.solver.simulation.ENERGY_COLUMNS)
D_VISC = 6


def _run(model, dt: float, seconds: float):
    sim = Simulation(model, dt=dt, itrac=1)
    first = sim.snapshot()
    block = sim.advance(int(round(seconds / dt)))
    return sim, np.r_[first.energy, block.energy]


@pytest.mark.parametrize("dt", [1e-8, 5e-7, 3.3e-7, 1.7e-6])
def test_a_hooke_wall_impact_books_all_its_work(dt):
    """decks/hooke_wall.inp at its own step (onset on a step), at the report's 5e-7 s (55
    steps per contact), and at two steps whose onset falls inside a step (3.3e-7 s, and 1.7e-6
    s: 16 steps per contact): every row's residual is round-off, and the viscous dissipation
    after the rebound is the kinetic energy the sphere lost."""
    model = build_model(read_deck(DECK))
    sim, energy = _run(model, dt, model.tmax)
    m = model.mass[-1]
    ke0 = 0.5 * m * float(np.sum(model.v0[-1, :3] ** 2))
    worst = float(np.max(np.abs(energy[:, RESIDUAL])))
    assert worst <= ROUND_OFF * ke0, f"residual {worst:.4g} of an impact of {ke0:.4g}"
    v_out = float(np.linalg.norm(sim.state.vel[-1, :3]))
    assert energy[-1, D_VISC] == pytest.approx(0.5 * m * (10.0**2 - v_out**2), rel=1e-6)


def _hooke(deck, kn: float, e: float):
    return dataclasses.replace(deck, hooke=(Hooke(deck.pdmp[0].nodlim, kn, e),))


def _pair(dt: float, offset: float = 0.0):
    """Two spheres (k_n = 1e4 lbf/in, e = 0.5) flying at each other at 10 in/s each along x,
    their centres ``offset`` R apart in y, a gap of 0.001 in between them along x."""
    r = STEEL_R
    x = math.sqrt(4.0 - offset**2) * r + 0.001
    return build_model(
        _hooke(
            pair_deck(
                [(0.0, 0.0, 0.0), (x, offset * r, 0.0)],
                [(10.0, 0.0, 0.0), (-10.0, 0.0, 0.0)],
                dt=dt,
            ),
            1e4,
            0.5,
        )
    )


def _pair_contact_time() -> float:
    """pi/omega_d, omega_d = sqrt(k_n/m*) sqrt(1 - zeta^2), m* = m/2: 2.0e-5 s."""
    zeta = damping_ratio(0.5)
    return math.pi / (math.sqrt(1e4 / (sphere_mass() / 2)) * math.sqrt(1 - zeta**2))


@pytest.mark.parametrize("dt", [1e-7, 7.7e-7])
def test_a_hooke_pair_impact_books_all_its_work(dt):
    """Two spheres head-on: the pair pass books the onset step from the gap too."""
    model = _pair(dt)
    m = sphere_mass()
    t_meet = 0.001 / 20.0  # the gap closes at 20 in/s
    sim, energy = _run(model, dt, t_meet + _pair_contact_time() + 2e-5)
    ke0 = 2 * 0.5 * m * 10.0**2
    worst = float(np.max(np.abs(energy[:, RESIDUAL])))
    assert worst <= ROUND_OFF * ke0, f"residual {worst:.4g} of an impact of {ke0:.4g}"
    ke1 = 0.5 * m * float(np.sum(sim.state.vel[:, :3] ** 2))
    assert energy[-1, D_VISC] == pytest.approx(ke0 - ke1, rel=1e-6)


def test_an_oblique_pair_impacts_ledger_closes_at_any_step():
    """An oblique pair impact (centres R apart across the line of flight): the contact normal
    turns during every step. Booked along the approach, 1/2 (F_old + F) (a - a_old), the work
    differed from what velocity Verlet does with the forces, which act along normals that
    turn, by (a - a_old) |dx_t|^2 / (4 d^2) per step -- second order over a contact (4.0000 +-
    2e-4 the ratio of the residuals at 50 and 100 steps per contact). The pair response books
    the vector trapezoid 1/2 (F_old n_old + F n) . (-dt dv) (docs/physics.md, "Energy
    ledger"): round-off at both steps."""
    dt = _pair_contact_time() / 50.0
    ke0 = 2 * 0.5 * sphere_mass() * 10.0**2
    for step in (dt, dt / 2.0):
        _, energy = _run(_pair(step, offset=1.0), step, 1.5e-4)
        worst = float(np.max(np.abs(energy[:, RESIDUAL])))
        assert worst <= ROUND_OFF * ke0, f"residual {worst:.4g} of an impact of {ke0:.4g}"
