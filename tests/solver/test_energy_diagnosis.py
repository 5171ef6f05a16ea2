"""An energy-residual failure names the right cause: a step too coarse for a contact or spring, or
energy that entered through a channel the ledger does not count (bookkeeping)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest


from factories import STEEL_R, floor_deck
from test_instability import sdof_deck

from x3dpd.deck.cards import Hooke
from x3dpd.errors import UnstableRunError
from x3dpd.model.build import build_model
from x3dpd.solver.diagnosis import structure_omega_bound
from x3dpd.solver.simulation import Simulation


def test_energy_put_in_behind_the_ledgers_back_is_called_bookkeeping():
    """A well-resolved SDOF (omega dt = 0.1) whose velocity is changed from outside the step loop
    -- the way the old prescribed motion set a velocity at t0 without counting its work."""
    k, m = 100.0, 1.0
    sim = Simulation(build_model(sdof_deck(k, m, 0.1 / math.sqrt(k / m))))
    sim.advance(100)
    sim.state.vel[0, 0] += 3.0  # kinetic energy from nowhere: 0.5 (3^2 + 2*3*v) >> 5 %
    with pytest.raises(UnstableRunError) as err:
        sim.advance(100)
    text = str(err.value)
    assert "without a source" in text
    assert "not the likely cause" in text and "bookkeeping" in text
    assert "too large" not in text


def test_a_contact_resolved_in_too_few_steps_is_called_a_step_problem():
    """Figure 28's impact (62.8 in/s, t_c = 7.6 us) at dt = 2 us: under 4 steps per contact."""
    sim = Simulation(
        build_model(floor_deck(dt=2e-6, height=STEEL_R * 1.001, spectator=False)),
        penetration_limit=10.0,
    )
    with pytest.raises(UnstableRunError) as err:
        sim.advance(50)
    text = str(err.value)
    assert "without a source" in text and "time step 2e-06 s is too large" in text
    assert "steps (at least 6" in text and "bookkeeping" not in text


def test_structure_bound_is_an_upper_bound_of_the_highest_frequency():
    """Gershgorin's bound against the exact eigenvalues of a two-node spring chain."""
    from x3dpd.deck.cards import Boundary, Deck, Element, Mass, Material, Node, Parameters
    from x3dpd.solver.state import build_setup

    k1, k2, m1, m2 = 100.0, 300.0, 1.0, 2.0
    deck = Deck(
        parameters=Parameters(0.0, 1.0, 0.0, 1e-3, 1e-3, 0, 1e9, 0, 5, 0, 10),
        materials=(
            Material(1, 1, 0.0, 1.0, k1, 0.0, 0.0, 0.0),
            Material(2, 1, 0.0, 1.0, k2, 0.0, 0.0, 0.0),
        ),
        nodes=(Node(1, 0.0, 0.0, 0.0), Node(2, 1.0, 0.0, 0.0)),
        elements=(Element(1, 1, (1,)), Element(2, 2, (1, 2))),
        masses=(Mass(1, m1, 0.0, 0.0, 0.0), Mass(2, m2, 0.0, 0.0, 0.0)),
        boundaries=(Boundary(1, 2, 1, (2, 3, 4, 5, 6)),),
    )
    model = build_model(deck)
    bound = structure_omega_bound(build_setup(model, 1e-3))
    stiffness = np.array([[k1 + k2, -k2], [-k2, k2]])
    exact = math.sqrt(np.linalg.eigvals(np.diag([1 / m1, 1 / m2]) @ stiffness).real.max())
    assert exact <= bound <= 2.0 * exact


def _advice_at(dt: float, speed: float, hooke=None, **material) -> str:
    """(advice, the wall contact time it used) for the floor deck's sphere at ``speed``; with
    ``hooke`` = (k_n, e) under the HOOKE law."""
    from x3dpd.solver.diagnosis import energy_source_advice, wall_contact_time
    from x3dpd.solver.state import build_setup

    deck = floor_deck(dt=dt, spectator=False, **material)
    if hooke is not None:
        deck = dataclasses.replace(deck, hooke=(Hooke(deck.pdmp[0].nodlim, *hooke),))
    model = build_model(deck)
    setup = build_setup(model, dt)
    vel = np.zeros((model.n_nodes, 6))
    vel[setup.p0 :, 1] = -speed
    return (energy_source_advice(model, setup, vel, dt, []), wall_contact_time(model, speed))


@pytest.mark.parametrize(
    "steps, cause", [(3.0, "too large"), (20.0, "coarsely"), (200.0, "bookkeeping")]
)
def test_the_advice_follows_the_steps_per_contact(steps, cause):
    """Below 6 steps per contact: too large; 6-50 (x3dpd check's recommendation): coarse, with
    the half-step test; above: the step is not the cause. The contact time is Hertz's closed
    form at the top speed (FIG28_V), so the step is chosen from it."""
    from factories import FIG28_V

    _, t_c = _advice_at(1e-7, FIG28_V)
    text, _ = _advice_at(t_c / steps, FIG28_V)
    assert cause in text
    if cause == "coarsely":
        assert "half the step" in text and f"{steps:.3g} steps (50 recommended)" in text


def test_the_hertz_contact_time_is_the_closed_form():
    """The advice's contact time for the report's law: 2.868 (m^2/(R E*^2 v))^(1/5), E* =
    E/(1-nu^2) on the wall (x3dpd.physics.hertz.hertz_contact_time's docstring), written out
    here; 2.868 is rounded to 4 digits."""
    from factories import FIG28_V, STEEL_E, STEEL_NU, sphere_mass

    _, t_c = _advice_at(1e-7, FIG28_V)
    e_star = STEEL_E / (1 - STEEL_NU**2)
    want = 2.868 * (sphere_mass() ** 2 / (STEEL_R * e_star**2 * FIG28_V)) ** 0.2
    assert t_c == pytest.approx(want, rel=2e-4)


@pytest.mark.parametrize(
    "steps, cause", [(3.0, "too large"), (44.0, "coarsely"), (53.0, "bookkeeping")]
)
def test_a_hooke_contact_is_counted_by_its_own_period(steps, cause):
    """Under the HOOKE law (k_n = 1e4 lbf/in, e = 0.8: decks/hooke_wall.inp's) the advice
    counts the steps of its own contact, half a damped period pi/omega_d, omega_d =
    sqrt(k_n/m) sqrt(1 - zeta^2), zeta = -ln e / sqrt(pi^2 + ln^2 e) -- at any speed -- not
    those of a Hertz contact from the unused E0 (4x shorter at 62.8 in/s: a step of 44 HOOKE
    steps per contact was called 10 Hertz steps)."""
    from factories import FIG28_V, sphere_mass

    zeta = -math.log(0.8) / math.sqrt(math.pi**2 + math.log(0.8) ** 2)
    t_c = math.pi / (math.sqrt(1e4 / sphere_mass()) * math.sqrt(1.0 - zeta**2))
    text, used = _advice_at(t_c / steps, FIG28_V, hooke=(1e4, 0.8))
    assert used == pytest.approx(t_c, rel=1e-12)
    assert cause in text
    if cause == "coarsely":
        assert f"{steps:.3g} steps (50 recommended)" in text


def test_a_maxwell_term_relaxing_within_two_steps_is_coarse():
    """tau1 = 2 dt: the Lee & Radok update is coarse even when the contact has 200 steps."""
    from factories import FIG28_V

    _, t_c = _advice_at(1e-7, FIG28_V, e1=5e6, tau1=1e-6)
    dt = t_c / 200.0
    text, _ = _advice_at(dt, FIG28_V, e1=5e6, tau1=2.0 * dt)
    assert "coarsely" in text and "Maxwell term relaxes in 2 steps" in text
    text, _ = _advice_at(dt, FIG28_V, e1=5e6, tau1=10.0 * dt)
    assert "bookkeeping" in text
