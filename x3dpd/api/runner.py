"""``x3dpd.run``: run a deck from Python exactly as ``x3dpd run`` does.

What a run does, in order (docs/running.md, docs/python-api.md; each a named step in
:mod:`x3dpd.api.run_steps`):

1. read the deck (or take a :class:`~x3dpd.deck.Deck`), build the model, refuse a deck whose
   particles start inside a wall deeper than the penetration limit;
2. compile or load the step loop for the scene's effects (:class:`Simulation`);
3. with ``trace=PATH``: open the trace, its sidecar and the energy file, refusing to replace
   existing ones unless ``overwrite`` (which keeps ``.bak`` copies);
4. step in chunks of about 0.3 s of wall time, recording every ITRAC-th step, taking a restart
   dump every TREST of simulated time and at the end;
5. return a :class:`RunResult` (trace, energy ledger, summary, final state).

Bad input raises :class:`~x3dpd.errors.InputError` / :class:`~x3dpd.errors.DeckError`; a
diagnosed instability raises :class:`~x3dpd.errors.UnstableRunError` after the rows computed
before it were written (its ``result`` attribute holds the partial :class:`RunResult`).
"""

from __future__ import annotations

import os
import shlex
from collections.abc import Callable, Sequence

from x3dpd.api.loop import STOP_CHECK_ROWS, Stats
from x3dpd.api.results import Chunk, FinalState, RunResult
from x3dpd.api.run_record import start_recording, step, summarise
from x3dpd.api.run_steps import make_step_loop, open_files, prepare, record_options
from x3dpd.errors import InputError, UnstableRunError
from x3dpd.solver.threads import thread_count

#: The energy audit's default tolerance, a fraction of the energy scale (run(energy_tolerance=)).
ENERGY_TOLERANCE = 0.05


def run(
    deck,
    *,
    tmax: float | None = None,
    dt: float | str | None = None,
    usrfrc: Sequence[str] = (),
    usrfrc_mode: str = "replace",
    motion: Sequence[str] = (),
    friction: str | None = None,
    temperature: str | float | None = None,
    trace: str | os.PathLike | None = None,
    energy: str | os.PathLike | None = None,
    overwrite: bool = False,
    restart: bool = False,
    itrac: int | None = None,
    trace_nodes: Sequence[int] | str | None = None,
    keep_trace: bool = True,
    initial_state: FinalState | None = None,
    stop: Callable[[Chunk], bool] | None = None,
    stop_every: int = STOP_CHECK_ROWS,
    progress: Callable[[float, float, float, float, float], None] | None = None,
    on_compile: Callable[[str], None] | None = None,
    usrfrc_python: bool = False,
    penetration_limit: float = 0.25,
    energy_tolerance: float = ENERGY_TOLERANCE,
    threads: int | str = 1,
    handle_signals: bool = False,
    command: str | None = None,
) -> RunResult:
    """Run a deck; return its trace, energy ledger, summary and final state.

    Parameters
    ----------
    deck : str, PathLike or Deck
        A deck file, or a deck read by :func:`x3dpd.load_deck`.
    tmax : float, optional
        End time [s]; default the deck's TMAX.
    dt : float or "auto", optional
        Time step [s], or ``"auto"``: a step chosen by accuracy in DTMIN ... DTMAX
        (docs/running.md). Default: the deck's DTMAX, or ``"auto"`` when its DTMIN < DTMAX.
    usrfrc : sequence of str
        External forces (built-in laws such as ``"sine:node=9,dof=1,amp=4.84e-3,hz=37.21"`` or
        user force files, docs/usrfrc.md).
    usrfrc_mode : "replace" or "add"
        Whether ``usrfrc`` replaces the deck's USRFRC card (default: a run at another drive is
        driven once, not twice) or adds to it. Without ``usrfrc`` the deck's card applies.
    motion : sequence of str
        Prescribed motions (``"node=25,dof=1,amp=0.01,hz=37.21"``).
    friction : a name of ``x3dpd.api.FRICTION_LAWS`` ("regularized", "coulomb" ...), optional
        The tangential contact law for the whole run (docs/physics.md), over the deck's
        FRICTION card; default the card's law, else "regularized".
    temperature : str or float, optional
        The operating temperature over the deck's TEMPERATURE card's (``"850F"``, ``"455C"``,
        ``"728K"``, or a number on the scale of the deck's UNITS card: docs/deck-reference.md,
        "TEMPERATURE"); a deck without the card is refused. As ``x3dpd run --temperature``.
    trace : path, optional
        Write the trace (and its sidecar), the energy file and restart dumps here, the same bytes
        as ``x3dpd run --trace``. None: write nothing.
    energy : path, optional
        The energy file (default: beside the trace, ``.energy.csv``).
    overwrite : bool
        Replace existing output files (keeping ``.bak`` copies).
    restart : bool
        Resume from ``<trace>.restart.npz`` (as IREST = 1).
    itrac : int, optional
        Record every ``itrac`` steps (default the deck's ITRAC; with ``dt="auto"``, every
        ``itrac`` x DTMAX of simulated time).
    trace_nodes : sequence of int or "structure", optional
        User node ids to record (default the deck's TRACE card); ``"structure"``: the TRACE
        card's structure nodes, its particles left out (a trace a fraction of the size, for
        a sweep's or an FRF's response; ``x3dpd run --trace-nodes structure``).
    keep_trace : bool
        Keep the recorded rows in memory (``result.trace``, ``result.energy``).
    initial_state : FinalState, optional
        ``result.final_state`` of an earlier run of the same deck at the same ``dt``: continue
        from it (its time, particles, structure and ledger).
    stop : callable, optional
        ``stop(chunk) -> bool`` after every ``stop_every`` trace rows (:class:`Chunk`); True
        ends the run there (summary status ``"stopped"``).
    stop_every : int
        Trace rows between calls of ``stop`` (default 20). A fixed step count, so that where a
        run stops -- and the state a chained run continues from -- does not depend on the
        machine's speed.
    progress : callable, optional
        ``progress(time, steps_per_s, eta_s, relative_residual, t_end)`` after each chunk.
    on_compile : callable, optional
        ``on_compile(message)`` before the scene's step loop is compiled (not when cached).
    usrfrc_python, penetration_limit : as ``x3dpd run``'s options.
    energy_tolerance : float
        Stop the run (UnstableRunError) when a ledger row's residual exceeds this fraction of
        the energy scale (plus the contact energy stored at that moment), or a dissipation
        column falls below minus that much: default 0.05 (docs/physics.md, "Stopping a run
        that goes unstable"); ``math.inf`` audits nothing. As ``x3dpd run --energy-tolerance``.
    threads : int or "auto"
        Threads of one run's pair contacts (docs/engine.md, "Threads"): 1 (default), up to the
        cores numba sees (``NUMBA_NUM_THREADS``), or ``"auto"`` for all of them. The trace and
        ledger are the same bytes whatever the count; more than 1 compiles a loop of its own.
        As ``x3dpd run --threads``.
    handle_signals : bool
        Turn SIGINT/SIGTERM into a clean stop after the current chunk (restart dump written,
        status "interrupted"), as the CLI does.
    command : str, optional
        The command line recorded in the sidecar.

    Raises
    ------
    DeckError, InputError
        Bad deck or arguments; nothing is written.
    UnstableRunError
        The run became unstable; what was computed before is written and ``exc.result`` holds
        it.
    """
    threads = thread_count(threads)
    stats = Stats()
    plan = prepare(
        deck,
        stats,
        tmax=tmax,
        usrfrc=usrfrc,
        usrfrc_mode=usrfrc_mode,
        motion=motion,
        temperature=temperature,
        trace=trace,
        energy=energy,
        restart=restart,
        initial_state=initial_state,
        penetration_limit=penetration_limit,
        energy_tolerance=energy_tolerance,
    )
    # the run's tangential law: the option, else the deck's FRICTION card's (x3dpd.physics)
    friction = friction or plan.model.friction_law or "regularized"
    make_step_loop(
        plan,
        dt=dt,
        itrac=itrac,
        friction=friction,
        penetration_limit=penetration_limit,
        usrfrc_python=usrfrc_python,
        energy_tolerance=energy_tolerance,
        trace_nodes=trace_nodes,
        on_compile=on_compile,
        initial_state=initial_state,
        threads=threads,
    )
    record_options(plan, friction=friction, usrfrc_python=usrfrc_python)
    open_files(plan, friction=friction, restart=restart, overwrite=overwrite, command=command)
    if initial_state is not None and plan.sim.clock >= plan.n_end:
        raise InputError(
            f"the initial state is at t = {plan.sim.time:.9g} s, not before TMAX "
            f"{plan.tmax:.9g} s: nothing to run (give a larger tmax)"
        )
    ids, recorder, sink = start_recording(plan, keep_trace=keep_trace, fresh=initial_state is None)
    try:
        status, intr = step(
            plan,
            sink,
            ids,
            progress=progress,
            stop=stop,
            stop_every=stop_every,
            handle_signals=handle_signals,
        )
    except UnstableRunError as exc:
        exc.result = summarise(plan, recorder, "unstable")
        raise
    out = summarise(plan, recorder, status)
    if status == "interrupted":
        out.summary["exit_status"] = intr.exit_status
    return out


def command_line(argv: Sequence[str]) -> str | None:
    """The sidecar's ``command`` for the arguments of an ``x3dpd`` command."""
    return "x3dpd " + shlex.join(argv) if argv else None
