"""The time step of a run: a fixed one, or one chosen by accuracy (``dt="auto"``).

``dt`` is a number [s], ``"auto"``, or None: the deck's DTMAX as a fixed step, or -- when the
deck's PARAMETERS give DTMIN < DTMAX -- the step chosen by accuracy in DTMIN ... DTMAX
(:mod:`x3dpd.solver.variable_step`; docs/running.md, "A step chosen by accuracy"). Without a
usable DTMIN (0, or equal to DTMAX with an explicit ``"auto"``) the finest step is DTMAX/1024.
"""

from __future__ import annotations

from x3dpd.errors import InputError


def wants_auto(dt, parameters) -> bool:
    """Whether a run with ``dt`` on a deck with these PARAMETERS chooses its step by accuracy."""
    if isinstance(dt, str):
        if dt.strip().lower() != "auto":
            raise InputError(f"dt must be a number of seconds or 'auto', got {dt!r}")
        return True
    return dt is None and parameters is not None and parameters.dtmin < parameters.dtmax


def make_stepper(config):
    """The object that advances the run of ``config`` (x3dpd.api.config.RunConfig): a
    :class:`Simulation` at its fixed step or a :class:`VariableStep` driver between DTMIN and
    DTMAX (trace every ITRAC x DTMAX)."""
    from x3dpd.solver.simulation import Simulation

    step = config.step
    options = dict(
        itrac=config.itrac,
        usrfrc=config.usrfrc,
        motion=config.motion,
        friction=config.friction,
        penetration_limit=config.penetration_limit,
        allow_python_usrfrc=config.usrfrc_python,
        energy_tolerance=config.energy_tolerance,
        threads=config.threads,
    )
    if not step.auto:
        return Simulation(config.model, dt=step.dt, **options)
    from x3dpd.solver.variable_step import VariableStep

    return VariableStep(
        config.model,
        dtmin=step.dtmin,
        dtmax=step.dt,
        dt_structure=step.dt_structure,
        **options,
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
