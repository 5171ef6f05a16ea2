"""The variable-step driver itself (x3dpd.solver.variable_step): it switches to the contact step
before a contact begins and back to DTMAX in free flight, and its levels are the ones DTMIN and
DTMAX allow. Accuracy, penetration, the ledger and restarts through ``x3dpd.run(dt="auto")``:
tests/api/test_auto_step.py; through the command line: tests/cli/test_auto_step_cli.py.

Claimed error: 50 steps per contact, for which velocity Verlet's peak-force error is at most
1.35 % (10/50)^2 = 0.054 % (x3dpd.model.timestep.peak_force_error, re-measured in
tests/model/test_model_timestep.py); restitution errs less than peak force.
"""

from __future__ import annotations


import pytest

from factories import floor_deck

from x3dpd.errors import InputError
from x3dpd.model.build import build_model
from x3dpd.model.timestep import peak_force_error
from x3dpd.solver.simulation import Simulation
from x3dpd.solver.variable_step import VariableStep, auto_floor

R, V = 0.03125, 62.8


def test_the_levels_halve_dtmax_down_to_dtmin():
    model = build_model(floor_deck(dt=2e-6, radius=R))
    vs = VariableStep(model, dtmin=2.4e-7, dtmax=2e-6, itrac=1)
    assert vs.levels == [2e-6, 1e-6, 5e-7, 2.5e-7]
    assert auto_floor(0.0, 2e-6) == auto_floor(2e-6, 2e-6) == 2e-6 / 1024
    assert auto_floor(1e-7, 2e-6) == 1e-7
    with pytest.raises(InputError):
        VariableStep(model, dtmin=1e-6, dtmax=2e-6, interval=3e-6)


def test_free_flight_runs_at_dtmax_and_the_step_is_refined_before_the_contact():
    """A lone elastic sphere (no other particle: nothing else in contact) flies 0.003 in to a
    wall at 62.8 in/s (contact from t = 4.8e-5 s): DTMAX until the wall is within reach, the
    contact step through the impact, DTMAX again once it has left."""

    def model():
        return build_model(
            floor_deck(
                dt=2e-6, height=R + 0.003, velocity=(0.0, -V, 0.0), spectator=False, radius=R
            )
        )

    t_end = 1.6e-4
    res = VariableStep(model(), dtmin=1e-10, dtmax=2e-6, interval=2e-6).run(t_end)
    steps = [dt for _, dt in res.steps]
    assert steps[0] == steps[-1] == 2e-6 and min(steps) <= 3.8e-6 / 50
    refined_at = next(t for t, dt in res.steps if dt < 2e-6)
    assert refined_at < 0.003 / V  # before the sphere touches the wall
    fine = Simulation(model(), dt=1e-9, itrac=2000).advance(int(round(t_end / 1e-9)))
    assert res.data[-1, 0, 4] == pytest.approx(fine.data[-1, 0, 4], rel=peak_force_error(50) / 100)
    assert res.n_steps < 0.01 * round(t_end / 1e-9)
