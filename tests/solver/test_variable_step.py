"""The step chosen by accuracy (x3dpd.study.variable_step): it reproduces the fine fixed-step
answer within the error it claims, sees a contact coming, keeps the ledger continuous across
step changes, and continues from a saved state bit for bit.

Claimed error: 50 steps per contact, for which velocity Verlet's peak-force error is at most
1.35 % (10/50)^2 = 0.054 % (x3dpd.model.timestep.peak_force_error, re-measured in
tests/model/test_model_timestep.py); restitution errs less than peak force.
"""

from __future__ import annotations

import pickle
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests/: shared helpers
from dataclasses import replace  # noqa: E402

from factories import FIG30_E0, FIG30_E1, FIG30_TAU1, floor_deck, sdof_deck  # noqa: E402

from x3dpd.deck.cards import Usrfrc  # noqa: E402

from x3dpd.errors import UnstableRunError  # noqa: E402
from x3dpd.model.build import build_model  # noqa: E402
from x3dpd.model.timestep import peak_force_error  # noqa: E402
from x3dpd.solver.simulation import Simulation  # noqa: E402
from x3dpd.study.variable_step import VariableStep  # noqa: E402

R, V, T = 0.03125, 62.8, 8e-5
VISCO = dict(e0=FIG30_E0, e1=FIG30_E1, tau1=FIG30_TAU1, radius=R)


def lee_radok_model(**material):
    """A 0.03125 in sphere 0.003 in above a wall, flying at it at 62.8 in/s (contact ~3.8 us)."""
    deck = floor_deck(dt=2e-6, height=R + 0.003, velocity=(0.0, -V, 0.0), **(material or VISCO))
    return build_model(deck)


def variable(model, t_end=T):
    return VariableStep(model, dtmin=1e-10, dtmax=2e-6, interval=2e-6).run(t_end)


def test_the_lee_radok_wall_impact_gets_its_restitution_right():
    res = variable(lee_radok_model())
    fine = Simulation(lee_radok_model(), dt=1e-9, itrac=2000).advance(int(round(T / 1e-9)))
    e_var, e_fine = res.data[-1, 0, 4] / V, fine.data[-1, 0, 4] / V
    assert 0.5 < e_fine < 1.0
    assert e_var == pytest.approx(e_fine, rel=peak_force_error(50) / 100)
    # the step was refined before the contact began (seen coming), not after
    assert res.steps[1][0] == 0.0 and res.steps[1][1] <= 3.8e-6 / 50
    # the same deck at its fixed DTMAX of 2e-6 s cannot: a diagnosed stop
    with pytest.raises(UnstableRunError):
        Simulation(lee_radok_model(), itrac=1).advance(int(T / 2e-6))


def test_the_ledger_stays_continuous_across_step_changes():
    """A spring (omega = 10 rad/s) under a constant load from rest, DTMAX = 0.1 s: the structure
    asks for 0.2 x 2/omega = 0.04 s, so the run switches to DTMAX/4 at t = 0, where the load's
    force makes the Verlet term S = dt^2/8 F^2/m jump by 6 % of the energy scale. For a linear
    system the ledger balances to round-off, before and after the switch."""
    deck = replace(sdof_deck(dt=0.1, hz=1.0, mass=1.0, k=100.0, c=0.0, drive=0.0, itrac=1),
                   usrfrc=(Usrfrc(("constant:node=1,dof=1,amp=5.0",)),))
    res = VariableStep(build_model(deck), dtmin=1e-3, dtmax=0.1, interval=0.1).run(5.0)
    assert [dt for _, dt in res.steps] == [0.1, 0.025]
    scale = np.max(np.abs(res.energy[:, 1:11]))
    assert np.max(np.abs(res.energy[:, 11])) < 1e-12 * scale
    assert np.allclose(res.times, np.arange(res.times.size) * 0.1, rtol=0, atol=1e-12)


def test_a_continued_run_repeats_the_uninterrupted_one_bit_for_bit():
    model = lee_radok_model()
    whole = variable(model)
    half = variable(model, T / 2)
    state, level = pickle.loads(pickle.dumps((half.state, half.level)))
    rest = VariableStep(model, dtmin=1e-10, dtmax=2e-6, interval=2e-6).run(T, state=state,
                                                                           level=level)
    assert np.array_equal(np.concatenate([half.data, rest.data]), whole.data)
    assert np.array_equal(np.concatenate([half.energy, rest.energy]), whole.energy)


def test_free_flight_runs_at_dtmax_and_the_step_is_refined_before_the_contact():
    """A lone elastic sphere (no other particle: nothing else in contact) flies 0.003 in to a
    wall at 62.8 in/s (contact from t = 4.8e-5 s): DTMAX until the wall is within reach, the
    contact step through the impact, DTMAX again once it has left."""
    def model():
        return build_model(floor_deck(dt=2e-6, height=R + 0.003, velocity=(0.0, -V, 0.0),
                                      spectator=False, radius=R))
    t_end = 1.6e-4
    res = VariableStep(model(), dtmin=1e-10, dtmax=2e-6, interval=2e-6).run(t_end)
    steps = [dt for _, dt in res.steps]
    assert steps[0] == steps[-1] == 2e-6 and min(steps) <= 3.8e-6 / 50
    refined_at = next(t for t, dt in res.steps if dt < 2e-6)
    assert refined_at < 0.003 / V                       # before the sphere touches the wall
    fine = Simulation(model(), dt=1e-9, itrac=2000).advance(int(round(t_end / 1e-9)))
    assert res.data[-1, 0, 4] == pytest.approx(fine.data[-1, 0, 4],
                                               rel=peak_force_error(50) / 100)
    assert res.n_steps < 0.01 * round(t_end / 1e-9)
