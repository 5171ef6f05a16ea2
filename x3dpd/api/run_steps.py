"""The steps of :func:`x3dpd.api.run`, in the order it takes them (docs/running.md):

1. :func:`prepare` -- check the arguments, read the deck, build the model, choose the output
   paths, refuse a deck whose particles start inside a wall deeper than the penetration limit;
2. :func:`make_step_loop` -- compile or load the step loop (:class:`Simulation` or the variable
   step driver), count the steps to TMAX and between restart dumps, continue from an
   ``initial_state``;
3. :func:`open_files` -- with a trace path: the trace, its sidecar and the energy file (or, on a
   restart, the dump they resume from);
4-6. recording, stepping and the result: :mod:`x3dpd.api.run_record`.

What the steps share is a :class:`RunPlan`.
"""

from __future__ import annotations

import dataclasses
import math
import os

import numpy as np

from x3dpd.api.loop import (
    Stats,
    step_count,
)
from x3dpd.api.outputs import (
    check_writable,
    deck_key,
    default_paths,
    load_dump,
    open_outputs,
    require_dump,
    user_file_hashes,
)
from x3dpd.api.results import FinalState
from x3dpd.api.safety import initial_penetration_error
from x3dpd.api.stepping import is_auto, make_stepper
from x3dpd.errors import InputError
from x3dpd.physics.motion import motion_count
from x3dpd.solver.compile_log import expected_compile_seconds


@dataclasses.dataclass
class RunPlan:
    """What the steps of one run share: the deck and its model, the output paths, and -- as the
    steps fill them in -- the step loop, its step counts and the open output files."""

    deck: object  # the Deck
    deck_path: str
    model: object  # the Model (the deck's USRFRC card dropped when replaced)
    usrfrc: tuple  # the run's extra forces and motions (specs)
    motion: tuple
    replaced: list  # the deck's USRFRC specs the run's replaced
    tmax: float  # [s]
    writes: bool  # a trace path was given
    resume: bool  # continue from the restart dump
    trace_path: str | None
    energy_path: str | None
    dump_path: str | None
    stats: Stats
    sim: object = None  # the step loop (make_step_loop)
    auto: bool = False  # its step is chosen by accuracy
    dt: float = 0.0  # [s] (auto: DTMAX), as the run started
    itrac: int = 1
    t0: float = 0.0  # the deck's start time [s]
    n_end: int = 0  # steps of dt from t0 to TMAX
    trest_steps: int = 0  # steps between restart dumps (0: none)
    key: str = ""  # the deck's identity (x3dpd.api.outputs.deck_key)
    applied: list = dataclasses.field(default_factory=list)  # forces applied (specs)
    options: dict = dataclasses.field(default_factory=dict)  # recorded in restart dumps
    deck_sha: str | None = None
    meta: dict | None = None  # the restart dump resumed from
    writer: object = None  # trace and energy writers (open_files)
    ewriter: object = None
    steps_before: int = 0  # variable step: steps taken before this run


def prepare(
    deck,
    stats: Stats,
    *,
    tmax,
    usrfrc,
    usrfrc_mode,
    motion,
    trace,
    energy,
    restart,
    initial_state,
    penetration_limit,
    energy_tolerance,
    temperature=None,
) -> RunPlan:
    """Step 1: check the arguments, read the deck (a path or a Deck), build its model (the
    deck's USRFRC card dropped when ``usrfrc`` replaces it), choose the output paths and refuse
    existing ones that cannot be written, and -- on a fresh start -- refuse particles that
    start inside a wall deeper than ``penetration_limit`` radii; ``temperature`` (not None)
    replaces the TEMPERATURE card's operating temperature. Raises InputError/DeckError before
    anything is written."""
    from x3dpd.deck import Deck, read_deck
    from x3dpd.deck.temperature_card import with_temperature
    from x3dpd.model.build import build_model

    if not energy_tolerance > 0.0:
        raise InputError(
            f"energy_tolerance must be a positive fraction of the energy scale, "
            f"got {energy_tolerance!r}"
        )
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
    if temperature is not None:
        deck_obj = with_temperature(deck_obj, temperature)
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
            deck_path, os.fspath(trace), os.fspath(energy) if energy is not None else None
        )
        for path, what in ((trace_path, "trace file"), (energy_path, "energy file")):
            check_writable(path, what)
    resume = writes and (restart or model.irest == 1)
    if resume:
        require_dump(dump_path, "--restart" if restart else "the deck's IREST = 1")
    if tmax is not None and not math.isfinite(tmax):
        raise InputError(f"--tmax must be a finite number of seconds, got {tmax}")
    tmax = float(tmax if tmax is not None else model.tmax)
    if not resume and initial_state is None:
        err = initial_penetration_error(model, penetration_limit, deck_path)
        if err is not None:
            raise err
    return RunPlan(
        deck=deck_obj,
        deck_path=deck_path,
        model=model,
        usrfrc=usrfrc,
        motion=motion,
        replaced=replaced,
        tmax=tmax,
        writes=writes,
        resume=resume,
        trace_path=trace_path,
        energy_path=energy_path,
        dump_path=dump_path,
        stats=stats,
    )


def make_step_loop(
    plan: RunPlan,
    *,
    dt,
    itrac,
    friction,
    penetration_limit,
    usrfrc_python,
    energy_tolerance,
    trace_nodes,
    on_compile,
    initial_state,
    threads=1,
) -> None:
    """Step 2: the step loop (fixed ``dt`` or chosen by accuracy, x3dpd.api.stepping), the nodes
    it records, ``on_compile`` told when it must be compiled; the steps to TMAX and between
    restart dumps (TREST); continued from ``initial_state`` when given."""
    model = plan.model
    sim = make_stepper(
        model,
        dt=dt,
        parameters=plan.deck.parameters,
        itrac=itrac,
        usrfrc=plan.usrfrc,
        motion=plan.motion,
        friction=friction,
        penetration_limit=penetration_limit,
        allow_python_usrfrc=usrfrc_python,
        energy_tolerance=float(energy_tolerance),
        threads=threads,
    )
    plan.sim, plan.auto = sim, is_auto(sim)
    if trace_nodes is not None:
        sim.trace_nodes = _node_indices(model, trace_nodes, sim.trace_nodes)
    sim.compiled_here = not _kernels_cached(sim)
    if on_compile is not None and sim.compiled_here:
        on_compile(CompileNotice.now())
    plan.dt, plan.itrac, plan.t0 = sim.dt, sim.itrac, model.t0
    tmax, t0 = plan.tmax, plan.t0
    plan.n_end = step_count((tmax - t0) / plan.dt, f"TMAX {tmax:g} s from the start time {t0:g} s")
    if plan.n_end < 0:
        raise InputError(f"TMAX {tmax:g} s is before the start time {t0:g} s")
    plan.trest_steps = (
        step_count(model.trest / plan.dt, f"TREST {model.trest:g} s") if model.trest > 0 else 0
    )
    plan.key = deck_key(plan.deck)
    if initial_state is not None:
        _continue_from(sim, initial_state, plan.key, model)


def record_options(plan: RunPlan, *, friction, usrfrc_python) -> None:
    """The forces applied (the deck's card, () when replaced, then the run's) and the options
    a restart dump records, so that a resumed run can be refused if they differ."""
    plan.applied = list(plan.model.usrfrc) + list(plan.usrfrc)
    plan.options = {
        "usrfrc": list(plan.usrfrc),
        "motion": list(plan.motion),
        "friction": friction,
        "tmax": plan.tmax,
        "usrfrc_python": usrfrc_python,
        "usrfrc_files": user_file_hashes(plan.applied),
        "usrfrc_mode": "replace" if plan.replaced else "add",
        "step": "auto" if plan.auto else "fixed",
    }


def open_files(plan: RunPlan, *, friction, restart, overwrite, command) -> None:
    """Step 3 (with a trace path): the sidecar's record of the run, the restart dump resumed
    from (``restart`` or the deck's IREST = 1; refused when it is at TMAX already), the trace
    and energy files opened (``overwrite`` keeps ``.bak`` copies), a stale dump removed."""
    if not plan.writes:
        return
    from x3dpd.io.trace import sha256_file

    sim, model, tmax = plan.sim, plan.model, plan.tmax
    plan.deck_sha = sha256_file(plan.deck_path) if os.path.isfile(plan.deck_path) else None
    sidecar = {
        "deck_path": plan.deck_path,
        "deck_sha256": plan.deck_sha,
        "dt": plan.dt,
        "itrac": plan.itrac,
        "effects": sorted(sim.effects),
        "title": model.title,
        "t0": plan.t0,
        "tmax": tmax,
        "usrfrc": plan.applied,
        "motion": list(plan.motion),
        "friction": friction,
        "energy_file": plan.energy_path,
        "restart_file": plan.dump_path,
        "command": command,
    }
    if plan.auto:
        sidecar["dt"] = "auto"
        sidecar["step"] = sim.step_record()
    if plan.replaced:
        sidecar["usrfrc_replaced"] = plan.replaced
    units = getattr(model, "units", None)
    if units is not None:
        sidecar["units"] = dict(units) if isinstance(units, dict) else units
    if plan.resume:
        asked = "--restart" if restart else "the deck's IREST = 1"
        plan.meta = meta = load_dump(
            plan.dump_path, asked_by=asked, sim=sim, key=plan.key, options=plan.options, model=model
        )
        sidecar["resumed_at"] = meta["time"]
        if plan.auto:
            sidecar["step"] = sim.step_record()
        if meta["step"] >= plan.n_end:
            raise InputError(
                f"{plan.dump_path}: the restart dump is at t = "
                f"{meta['time']:.9g} s, not before TMAX {tmax:.9g} s: nothing to "
                "run (give a larger --tmax)"
            )
    plan.writer, plan.ewriter = open_outputs(
        plan.trace_path,
        plan.energy_path,
        sim,
        sidecar,
        plan.meta,
        sim.energy_columns,
        overwrite=overwrite,
    )
    if not plan.resume:
        try:  # a stale dump of an earlier run must not be resumed against this trace
            os.unlink(plan.dump_path)
        except FileNotFoundError:
            pass


def _continue_from(sim, initial: FinalState, key: str, model) -> None:
    if not isinstance(initial, FinalState):
        raise InputError("initial_state must be the final_state of an earlier x3dpd.run result")
    if initial.deck_key != key:
        raise InputError(
            "initial_state belongs to another deck (its cards differ; only TMAX, "
            "TREST and IREST may change)"
        )
    auto = is_auto(sim)
    if initial.dt != sim.dt or (initial.checkpoint is not None) != auto:

        def what(a, d):
            return f"a step chosen by accuracy up to {d!r} s" if a else f"dt {d!r} s"

        raise InputError(
            f"initial_state was computed at "
            f"{what(initial.checkpoint is not None, initial.dt)}; continue it at "
            f"the same step (this run's is {what(auto, sim.dt)})"
        )
    state = initial.state.copy()
    n_motion = motion_count(sim.motion)
    if state.motion_prev.shape[0] != n_motion:
        state.motion_prev = np.zeros(n_motion)
    if auto:
        sim.restore(state, initial.checkpoint)
    else:
        sim.restore(state)


def _node_indices(model, node_ids, traced: np.ndarray) -> np.ndarray:
    """Indices of the nodes to record: ``node_ids`` (user ids), or ``"structure"``: the
    structure's nodes among ``traced`` (the TRACE card's), its particles left out."""
    if isinstance(node_ids, str):
        if node_ids != "structure":
            raise InputError(
                f"trace_nodes {node_ids!r}: expected 'structure' or a list of node ids"
            )
        idx = traced[traced < model.particle_start]
        if idx.size == 0:
            raise InputError(
                "trace nodes 'structure': the deck's TRACE card names particles only; give "
                "the node ids to trace"
            )
        return np.array(idx, dtype=np.int64)  # writable, as the kernels were compiled for
    ids = np.asarray(list(node_ids), dtype=np.int64)
    if ids.ndim != 1 or ids.size == 0:
        raise InputError("trace_nodes must be a non-empty list of node ids")
    idx = np.searchsorted(model.node_ids, ids)
    bad = [int(i) for i, j in zip(ids, idx) if j >= model.n_nodes or model.node_ids[j] != i]
    if bad:
        raise InputError(f"trace_nodes: node(s) {', '.join(map(str, bad))} are not in the deck")
    return np.array(idx, dtype=np.int64)  # writable, as the kernels were compiled for


class CompileNotice(str):
    """What ``on_compile`` receives: the message to show (a ``str``), with the compile time
    expected on this machine as ``expected_s`` [s] (x3dpd.solver.compile_log), for a progress
    line that counts up to it."""

    expected_s: float

    @classmethod
    def now(cls) -> CompileNotice:
        expected = expected_compile_seconds()
        notice = cls(
            "compiling the step loop for this scene's effects: the first run of a "
            f"scene after installing or changing x3dpd, about {expected:.0f} s here; "
            "later runs load it from the cache in about a second"
        )
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
