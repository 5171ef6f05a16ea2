"""``x3dpd.run``: run a deck from Python exactly as ``x3dpd run`` does.

What a run does, in order (docs/running.md, docs/python-api.md):

1. read the deck (or take a :class:`~x3dpd.deck.Deck`), build the model, resolve and check
   every option, refuse a deck whose particles start inside a wall deeper than the penetration
   limit: its :class:`~x3dpd.api.config.RunConfig` (:func:`~x3dpd.api.config.run_config`);
2. compile or load the step loop for the scene's effects (:class:`Simulation`);
3. with ``trace=PATH``: open the trace, its sidecar and the energy file, refusing to replace
   existing ones unless ``overwrite`` (which keeps ``.bak`` copies);
4. step in chunks of about 0.3 s of wall time, recording every ITRAC-th step, taking a restart
   dump every TREST of simulated time and at the end;
5. return a :class:`RunResult` (trace, energy ledger, summary, final state).

Steps 2-5 are named steps of :mod:`x3dpd.api.run_steps` and :mod:`x3dpd.api.run_record`.
Bad input raises :class:`~x3dpd.errors.InputError` / :class:`~x3dpd.errors.DeckError`; a
diagnosed instability raises :class:`~x3dpd.errors.UnstableRunError` after the rows computed
before it were written (its ``result`` attribute holds the partial :class:`RunResult`).
"""

from __future__ import annotations

import inspect
import shlex
from collections.abc import Sequence

from x3dpd.api.config import ENERGY_TOLERANCE, RunConfig, run_config
from x3dpd.api.loop import Stats
from x3dpd.api.results import RunResult
from x3dpd.api.run_record import start_recording, step, summarise
from x3dpd.api.run_steps import RunPlan, make_step_loop, open_files, record_options
from x3dpd.errors import InputError, UnstableRunError
from x3dpd.solver.threads import thread_count  # noqa: F401  (the CLI's --threads check)

__all__ = ["ENERGY_TOLERANCE", "RunConfig", "command_line", "run", "run_config"]


def run(deck, **options) -> RunResult:
    """Run a deck; return its trace, energy ledger, summary and final state.

    ``deck`` is a deck file, a deck read by :func:`x3dpd.load_deck`, or a
    :class:`~x3dpd.api.config.RunConfig` (:func:`x3dpd.run_config`); ``options`` are the
    keywords of :func:`~x3dpd.api.config.run_config` (docs/python-api.md lists them: ``tmax``,
    ``dt``, ``usrfrc``, ``usrfrc_mode``, ``motion``, ``friction``, ``temperature``, ``trace``,
    ``energy``, ``overwrite``, ``restart``, ``itrac``, ``trace_nodes``, ``keep_trace``,
    ``initial_state``, ``stop``, ``stop_every``, ``progress``, ``on_compile``,
    ``usrfrc_python``, ``penetration_limit``, ``energy_tolerance``, ``threads``,
    ``handle_signals``, ``command``); given with a RunConfig they change it
    (:meth:`RunConfig.replace`).

    Raises
    ------
    DeckError, InputError
        Bad deck or arguments; nothing is written.
    UnstableRunError
        The run became unstable; what was computed before is written and ``exc.result`` holds
        it.
    """
    stats = Stats()  # the run's wall time counts reading the deck and building the model
    if isinstance(deck, RunConfig):
        config = deck.replace(**options) if options else deck
    else:
        config = run_config(deck, **options)
    plan = RunPlan(config, stats)
    make_step_loop(plan)
    record_options(plan)
    open_files(plan)
    if config.initial_state is not None and plan.sim.clock >= config.steps:
        raise InputError(
            f"the initial state is at t = {plan.sim.time:.9g} s, not before TMAX "
            f"{config.tmax:.9g} s: nothing to run (give a larger tmax)"
        )
    ids, recorder, sink = start_recording(plan)
    try:
        status, intr = step(plan, sink, ids)
    except UnstableRunError as exc:
        exc.result = summarise(plan, recorder, "unstable")
        raise
    out = summarise(plan, recorder, status)
    if status == "interrupted":
        out.summary["exit_status"] = intr.exit_status
    return out


run.__signature__ = inspect.signature(run_config)


def command_line(argv: Sequence[str]) -> str | None:
    """The sidecar's ``command`` for the arguments of an ``x3dpd`` command."""
    return "x3dpd " + shlex.join(argv) if argv else None
