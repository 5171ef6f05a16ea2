"""The step-stability check: no false alarm below the limit, a diagnosis above it.

Closed form: velocity Verlet on an oscillator of frequency omega is stable for omega dt < 2; under
a constant load F from rest the mass oscillates between 0 and 2F/k (the discrete orbit's extreme
differs from 2F/k by O((omega dt)^2), bounded here by a factor 1/(1 - (omega dt)^2/4)).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from factories import sdof_deck

from x3dpd.deck.cards import Usrfrc
from x3dpd.errors import UnstableRunError
from x3dpd.model.build import build_model
from x3dpd.model.timestep import recommended_time_step
from x3dpd.solver.simulation import Simulation

K, M, LOAD = 100.0, 1.0, 5.0
OMEGA = math.sqrt(K / M)


def oscillator(omega_dt, *, itrac, load=False, v0=1.0):
    deck = sdof_deck(
        dt=omega_dt / OMEGA,
        hz=1.0,
        mass=M,
        k=K,
        c=0.0,
        drive=0.0,
        itrac=itrac,
        v0=0.0 if load else v0,
    )
    if load:
        deck = replace(deck, usrfrc=(Usrfrc((f"constant:node=1,dof=1,amp={LOAD}",)),))
    return Simulation(build_model(deck))


@pytest.mark.parametrize("omega_dt", [1.0, 1.9, 1.99])
def test_a_constant_load_on_a_linear_spring_is_no_false_alarm(omega_dt):
    """Rows one period apart land where the spring energy and the load's work are ~0."""
    per_period = max(1, round(2 * math.pi / omega_dt))
    sim = oscillator(omega_dt, itrac=per_period, load=True)
    block = sim.advance(3000)
    x = block.data[:, 0, 0]
    assert np.all(np.isfinite(x))
    assert np.max(np.abs(x)) <= 2 * LOAD / K / (1 - omega_dt**2 / 4) + 1e-12


@pytest.mark.parametrize("omega_dt, itrac", [(2.05, 10), (2.5, 1), (4.0, 50), (4.5, 50), (20.0, 5)])
def test_a_step_beyond_the_limit_stops_naming_the_limit_and_a_safe_step(omega_dt, itrac):
    """Including omega dt >= 4, which the earlier S > KE + U test missed (S = KE + U exactly
    on the growing mode): such a run ended 'complete' with positions of 1e71."""
    sim = oscillator(omega_dt, itrac=itrac)
    with pytest.raises(UnstableRunError) as err:
        sim.advance(100)
    text = str(err.value)
    crit = 2.0 / OMEGA
    got = float(text.split("stability limit 2/omega = ")[1].split(" s")[0])
    assert got == pytest.approx(crit, rel=1e-2)  # the message's 3 digits
    safe = float(text.split("a safe step is <= ")[1].split(" s")[0])
    assert safe == pytest.approx(0.2 * crit, rel=1e-2)
    assert err.value.step <= 100


def test_just_below_the_limit_check_names_runs_and_just_above_stops():
    """`x3dpd check` names the structure's critical step 2/omega (Gershgorin bound, exact for
    one DOF); 0.99 of it runs, 1.01 of it stops."""
    sim = oscillator(1.0, itrac=10)
    crit = recommended_time_step(sim.model).dt_structure / 0.2
    assert crit == pytest.approx(2.0 / OMEGA, rel=1e-12)
    below = oscillator(0.99 * crit * OMEGA, itrac=10)
    assert np.all(np.isfinite(below.advance(5000).data))
    above = oscillator(1.01 * crit * OMEGA, itrac=10)
    with pytest.raises(UnstableRunError, match="stability limit"):
        above.advance(5000)
