"""``x3dpd.run``: run a deck from Python exactly as ``x3dpd run`` does.

What a run does, in order (docs/running.md, docs/python-api.md):

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

import dataclasses
import math
import os
import shlex
import time
from collections.abc import Callable, Sequence

import numpy as np

from x3dpd import __version__
from x3dpd.api.loop import (
    STOP_CHECK_ROWS,
    Interrupts,
    Sink,
    Stats,
    note_energy,
    relative_residual,
    step_count,
    step_loop,
)
from x3dpd.api.outputs import (
    check_writable,
    deck_key,
    default_paths,
    load_dump,
    open_outputs,
    user_file_hashes,
)
from x3dpd.api.results import Chunk, FinalState, Recorder, RunResult
from x3dpd.api.safety import initial_penetration_error
from x3dpd.api.stepping import auto_summary, is_auto, make_stepper
from x3dpd.errors import InputError, UnstableRunError
from x3dpd.physics.motion import motion_count
from x3dpd.physics.usrfrc import is_user_file
from x3dpd.solver.compile_log import expected_compile_seconds, record_compile_seconds

#: The energy audit's default tolerance, a fraction of the energy scale (run(energy_tolerance=)).
ENERGY_TOLERANCE = 0.05


def run(deck, *, tmax: float | None = None, dt: float | str | None = None,
        usrfrc: Sequence[str] = (), usrfrc_mode: str = "replace", motion: Sequence[str] = (),
        friction: str | None = None, trace: str | os.PathLike | None = None,
        energy: str | os.PathLike | None = None, overwrite: bool = False, restart: bool = False,
        itrac: int | None = None, trace_nodes: Sequence[int] | None = None,
        keep_trace: bool = True, initial_state: FinalState | None = None,
        stop: Callable[[Chunk], bool] | None = None, stop_every: int = STOP_CHECK_ROWS,
        progress: Callable[[float, float, float, float, float], None] | None = None,
        on_compile: Callable[[str], None] | None = None,
        usrfrc_python: bool = False, penetration_limit: float = 0.25,
        energy_tolerance: float = ENERGY_TOLERANCE,
        handle_signals: bool = False, command: str | None = None) -> RunResult:
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
    friction : "regularized", "coulomb" or "mindlin", optional
        The tangential contact law for the whole run (docs/physics.md), over the deck's
        FRICTION card; default the card's law, else "regularized".
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
    trace_nodes : sequence of int, optional
        User node ids to record (default the deck's TRACE card).
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
    from x3dpd.deck import Deck, read_deck
    from x3dpd.model.build import build_model
    from x3dpd.solver.simulation import ENERGY_COLUMNS

    stats = Stats()
    if not energy_tolerance > 0.0:
        raise InputError(f"energy_tolerance must be a positive fraction of the energy scale, "
                         f"got {energy_tolerance!r}")
    if usrfrc_mode not in ("replace", "add"):
        raise InputError(f"usrfrc_mode must be 'replace' or 'add', got {usrfrc_mode!r}")
    if isinstance(deck, Deck):
        deck_obj = deck
        deck_path = str(deck.path)
    else:
        deck_path = os.fspath(deck)
        if not os.path.isfile(deck_path):
            raise InputError(f"deck {deck_path} does not exist")
        deck_obj = read_deck(deck_path)
    usrfrc, motion = tuple(usrfrc), tuple(motion)
    model = build_model(deck_obj, usrfrc=usrfrc, motion=motion)
    replaced: list[str] = []
    if usrfrc and usrfrc_mode == "replace" and model.usrfrc:
        replaced = list(model.usrfrc)
        model = dataclasses.replace(model, usrfrc=())
    writes = trace is not None
    if restart and not writes:
        raise InputError("restart=True needs the trace path of the run to resume (trace=...)")
    trace_path = energy_path = dump_path = None
    if writes:
        trace_path, energy_path, dump_path = default_paths(
            deck_path, os.fspath(trace), os.fspath(energy) if energy is not None else None)
        for path, what in ((trace_path, "trace file"), (energy_path, "energy file")):
            check_writable(path, what)
    resume = writes and (restart or model.irest == 1)
    if tmax is not None and not math.isfinite(tmax):
        raise InputError(f"--tmax must be a finite number of seconds, got {tmax}")
    tmax = float(tmax if tmax is not None else model.tmax)
    if not resume and initial_state is None:
        err = initial_penetration_error(model, penetration_limit, deck_path)
        if err is not None:
            raise err

    # the run's tangential law: the option, else the deck's FRICTION card's (x3dpd.physics)
    friction = friction or model.friction_law or "regularized"
    sim = make_stepper(model, dt=dt, parameters=deck_obj.parameters, itrac=itrac,
                       usrfrc=usrfrc, motion=motion, friction=friction,
                       penetration_limit=penetration_limit, allow_python_usrfrc=usrfrc_python,
                       energy_tolerance=float(energy_tolerance))
    auto = is_auto(sim)
    if trace_nodes is not None:
        sim.trace_nodes = _node_indices(model, trace_nodes)
    sim.compiled_here = not _kernels_cached(sim)
    if on_compile is not None and sim.compiled_here:
        on_compile(CompileNotice.now())
    dt, itrac, t0 = sim.dt, sim.itrac, model.t0
    n_end = step_count((tmax - t0) / dt, f"TMAX {tmax:g} s from the start time {t0:g} s")
    if n_end < 0:
        raise InputError(f"TMAX {tmax:g} s is before the start time {t0:g} s")
    trest_steps = (step_count(model.trest / dt, f"TREST {model.trest:g} s")
                   if model.trest > 0 else 0)
    key = deck_key(deck_obj)
    if initial_state is not None:
        _continue_from(sim, initial_state, key, model)

    applied = list(model.usrfrc) + list(usrfrc)   # the deck's card is () when replaced
    options = {"usrfrc": list(usrfrc), "motion": list(motion), "friction": friction,
               "tmax": tmax, "usrfrc_python": usrfrc_python,
               "usrfrc_files": user_file_hashes(applied),
               "usrfrc_mode": "replace" if replaced else "add",
               "step": "auto" if auto else "fixed"}
    meta = None
    writer = ewriter = None
    if writes:
        from x3dpd.io.trace import sha256_file

        deck_sha = sha256_file(deck_path) if os.path.isfile(deck_path) else None
        sidecar = {
            "deck_path": deck_path, "deck_sha256": deck_sha, "dt": dt, "itrac": itrac,
            "effects": sorted(sim.effects), "title": model.title, "t0": t0, "tmax": tmax,
            "usrfrc": applied, "motion": list(motion), "friction": friction,
            "energy_file": energy_path, "restart_file": dump_path, "command": command,
        }
        if auto:
            sidecar["dt"] = "auto"
            sidecar["step"] = sim.step_record()
        if replaced:
            sidecar["usrfrc_replaced"] = replaced
        units = getattr(model, "units", None)
        if units is not None:
            sidecar["units"] = dict(units) if isinstance(units, dict) else units
        if resume:
            asked = "--restart" if restart else "the deck's IREST = 1"
            meta = load_dump(dump_path, asked_by=asked, sim=sim, key=key, options=options,
                             model=model)
            sidecar["resumed_at"] = meta["time"]
            if auto:
                sidecar["step"] = sim.step_record()
            if meta["step"] >= n_end:
                raise InputError(f"{dump_path}: the restart dump is at t = {meta['time']:.9g} "
                                 f"s, not before TMAX {tmax:.9g} s: nothing to run (give a "
                                 "larger --tmax)")
        writer, ewriter = open_outputs(trace_path, energy_path, sim, sidecar, meta,
                                       ENERGY_COLUMNS, overwrite=overwrite)
        if not resume:
            try:  # a stale dump of an earlier run must not be resumed against this trace
                os.unlink(dump_path)
            except FileNotFoundError:
                pass

    if initial_state is not None and sim.clock >= n_end:
        raise InputError(f"the initial state is at t = {sim.time:.9g} s, not before TMAX "
                         f"{tmax:.9g} s: nothing to run (give a larger tmax)")

    def dump(reason: str) -> None:
        if not writes:
            return
        if auto:
            writer.describe(step=sim.step_record())
        writer.flush()
        ewriter.flush()
        from x3dpd.io.restart import save_restart

        extra = {"variable_step": sim.checkpoint()} if auto else {}
        save_restart(dump_path, sim.state.to_arrays(), {**extra,
            "reason": reason, "x3dpd_version": __version__,
            "deck_path": deck_path, "deck_abspath": os.path.abspath(deck_path),
            "deck_sha256": deck_sha, "deck_key": key, "dt": dt, "itrac": itrac, "t0": t0,
            "step": int(sim.clock), "time": sim.time,
            "trace": {"path": trace_path, "bytes": writer.tell(),
                      "blocks": writer.blocks_written},
            "energy": {"path": energy_path, "bytes": ewriter.tell(),
                       "rows": ewriter.rows_written},
            "options": options, "energy_scale": sim.state.scale,
            "effects": sorted(sim.effects),
        })
        stats.dumps += 1

    ids = model.node_ids[sim.trace_nodes]
    recorder = Recorder(ids, ENERGY_COLUMNS, keep_trace)
    sink = Sink(writer, ewriter, recorder)
    if auto and writes:  # the sidecar's record of the steps used, as of the last row
        sink.on_close = lambda: writer.describe(step=sim.step_record())
    status = "complete"
    if (meta is None and initial_state is None):
        snap = sim.snapshot()
        sink.write(snap.times, snap.data, snap.energy)
        note_energy(stats, snap.energy)
    stats.setup_seconds = time.perf_counter() - stats.wall_start
    stats.t_start = sim.time
    steps_before = sim.steps_taken if auto else 0

    def result(st: str) -> RunResult:
        summary = _summary(sim, stats, st, applied, replaced, trace_path, energy_path,
                           dump_path if writes else None, ENERGY_COLUMNS)
        if auto:
            auto_summary(summary, sim, steps_before)
        final = FinalState(state=sim.state.copy(), deck_key=key, dt=dt, time=sim.time,
                           checkpoint=sim.checkpoint() if auto else None)
        return RunResult(trace=recorder.trace({"status": st, "dt": dt, "itrac": itrac}),
                         energy=recorder.energy(), summary=summary, final_state=final,
                         model=model)

    try:
        with sink, Interrupts(handle_signals) as intr:
            stopped = step_loop(sim, sink, n_end, trest_steps, stats, progress, dump,
                                 intr, stop, ids, stop_every)
            if intr.signum:
                dump("interrupted")
                status = "interrupted"
                sink.close("interrupted")
            else:
                status = "stopped" if stopped else "complete"
                dump("stopped" if stopped else "end")
    except UnstableRunError as exc:
        exc.result = result("unstable")
        raise
    out = result(status)
    if status == "interrupted":
        out.summary["exit_status"] = intr.exit_status
    return out


def _summary(sim, stats, status, applied, replaced, trace_path, energy_path, dump_path,
             columns) -> dict:
    wall = time.perf_counter() - stats.wall_start
    compile_s = float(sim.compile_seconds) + float(getattr(sim, "_load_seconds", 0.0))
    if getattr(sim, "compiled_here", False) and not getattr(sim, "compile_logged", False):
        record_compile_seconds(compile_s)   # the estimate of the next first run's progress line
        sim.compile_logged = True
    rate = stats.timed_steps / stats.timed_seconds if stats.timed_seconds > 0 else float("nan")
    e = stats.last_energy
    return {
        "status": status, "t_start": stats.t_start, "t_end": sim.time, "steps": stats.steps,
        "dt": sim.dt, "itrac": sim.itrac, "wall_s": wall, "step_wall_s": stats.timed_seconds,
        "compile_s": compile_s, "steps_per_s": rate, "effects": sorted(sim.effects),
        "energy_scale": float(sim.state.scale), "residual": relative_residual(stats, sim),
        "relative_residual": relative_residual(stats, sim),
        "residual_energy": float(e[11]) if e is not None else 0.0,
        "energy_tolerance": float(sim.energy_tolerance),
        "last_energy": dict(zip(columns, map(float, e))) if e is not None else None,
        "usrfrc": list(applied), "usrfrc_replaced": list(replaced), "trace_file": trace_path,
        "code_files": [spec for spec in applied if is_user_file(spec)],
        "energy_file": energy_path, "restart_file": dump_path, "dumps": stats.dumps,
        "units": list(getattr(sim.model, "units", ("in", "lbf", "s"))),
    }


def _continue_from(sim, initial: FinalState, key: str, model) -> None:
    if not isinstance(initial, FinalState):
        raise InputError("initial_state must be the final_state of an earlier x3dpd.run result")
    if initial.deck_key != key:
        raise InputError("initial_state belongs to another deck (its cards differ; only TMAX, "
                         "TREST and IREST may change)")
    auto = is_auto(sim)
    if initial.dt != sim.dt or (initial.checkpoint is not None) != auto:
        what = lambda a, d: f"a step chosen by accuracy up to {d!r} s" if a else f"dt {d!r} s"
        raise InputError(f"initial_state was computed at "
                         f"{what(initial.checkpoint is not None, initial.dt)}; continue it at "
                         f"the same step (this run's is {what(auto, sim.dt)})")
    state = initial.state.copy()
    n_motion = motion_count(sim.motion)
    if state.motion_prev.shape[0] != n_motion:
        state.motion_prev = np.zeros(n_motion)
    if auto:
        sim.restore(state, initial.checkpoint)
    else:
        sim.restore(state)


def _node_indices(model, node_ids) -> np.ndarray:
    ids = np.asarray(list(node_ids), dtype=np.int64)
    if ids.ndim != 1 or ids.size == 0:
        raise InputError("trace_nodes must be a non-empty list of node ids")
    idx = np.searchsorted(model.node_ids, ids)
    bad = [int(i) for i, j in zip(ids, idx) if j >= model.n_nodes or model.node_ids[j] != i]
    if bad:
        raise InputError(f"trace_nodes: node(s) {', '.join(map(str, bad))} are not in the deck")
    return np.ascontiguousarray(idx, dtype=np.int64)


class CompileNotice(str):
    """What ``on_compile`` receives: the message to show (a ``str``), with the compile time
    expected on this machine as ``expected_s`` [s] (x3dpd.solver.compile_log), for a progress
    line that counts up to it."""

    expected_s: float

    @classmethod
    def now(cls) -> "CompileNotice":
        expected = expected_compile_seconds()
        notice = cls("compiling the step loop for this scene's effects: the first run of a "
                     f"scene after installing or changing x3dpd, about {expected:.0f} s here; "
                     "later runs load it from the cache in about a second")
        notice.expected_s = expected
        return notice


def _kernels_cached(sim) -> bool:
    """Whether numba's disk cache already holds this scene's step loop."""
    path = getattr(sim.kernels, "__file__", None)
    if not path:
        return True
    folder = os.path.join(os.path.dirname(path), "__pycache__")
    stem = os.path.splitext(os.path.basename(path))[0]
    try:
        return any(f.startswith(stem + ".") and f.endswith(".nbi") for f in os.listdir(folder))
    except OSError:
        return False


def command_line(argv: Sequence[str]) -> str | None:
    """The sidecar's ``command`` for the arguments of an ``x3dpd`` command."""
    return "x3dpd " + shlex.join(argv) if argv else None
