"""The time step of a run: a fixed one, or one chosen by accuracy (``dt="auto"``).

``dt`` is a number [s], ``"auto"``, or None: the deck's DTMAX as a fixed step, or -- when the
deck's PARAMETERS give DTMIN < DTMAX -- the step chosen by accuracy in DTMIN ... DTMAX
(:mod:`x3dpd.solver.variable_step`; docs/running.md, "A step chosen by accuracy"). Without a
usable DTMIN (0, or equal to DTMAX with an explicit ``"auto"``) the finest step is DTMAX/1024.
"""

from __future__ import annotations

import math

from x3dpd.errors import InputError


def wants_auto(dt, parameters) -> bool:
    """Whether a run with ``dt`` on a deck with these PARAMETERS chooses its step by accuracy."""
    if isinstance(dt, str):
        if dt.strip().lower() != "auto":
            raise InputError(f"dt must be a number of seconds or 'auto', got {dt!r}")
        return True
    return dt is None and parameters is not None and parameters.dtmin < parameters.dtmax


def make_stepper(model, *, dt, parameters, itrac, **sim_options):
    """The object that advances the run: a :class:`Simulation` at a fixed ``dt`` or a
    :class:`VariableStep` driver between DTMIN and DTMAX (trace every ITRAC x DTMAX)."""
    from x3dpd.solver.simulation import Simulation

    if not wants_auto(dt, parameters):
        return Simulation(model, dt=dt, itrac=itrac, **sim_options)
    from x3dpd.model.timestep import recommended_time_step
    from x3dpd.solver.variable_step import VariableStep, auto_floor

    dtmax = float(model.dt)
    floor = auto_floor(parameters.dtmin if parameters is not None else 0.0, dtmax)
    limit = recommended_time_step(model).dt_structure
    return VariableStep(
        model,
        dtmin=floor,
        dtmax=dtmax,
        itrac=itrac,
        dt_structure=limit if math.isfinite(limit) and limit > 0 else math.inf,
        **sim_options,
    )


def is_auto(sim) -> bool:
    """Whether ``sim`` chooses its own step (a :class:`VariableStep` driver)."""
    from x3dpd.solver.variable_step import VariableStep

    return isinstance(sim, VariableStep)


def auto_summary(summary: dict, sim, steps_before: int) -> None:
    """A run with a step chosen by accuracy: ``steps`` counts steps of every size, ``itrac``
    stays in DTMAX steps, ``step`` records the steps used (min, max, mean [s])."""
    ticks, steps = summary["steps"], sim.steps_taken - steps_before
    summary["steps"] = steps
    if ticks:
        summary["steps_per_s"] *= steps / ticks
    summary["step"] = sim.step_record()
