"""The options of a run, each resolved to its value and checked (x3dpd.api.config builds a
:class:`~x3dpd.api.config.RunConfig` from them): the deck and its model, the output files, the
time step, the trace interval and nodes, the step counts, the tangential law and the state a run
continues from. Each function raises :class:`~x3dpd.errors.InputError` with the message the
user sees."""

from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass

import numpy as np

from x3dpd.api.loop import step_count
from x3dpd.api.outputs import check_writable, default_paths, require_dump
from x3dpd.api.results import FinalState
from x3dpd.api.stepping import wants_auto
from x3dpd.errors import InputError
from x3dpd.physics.tangential_laws import DEFAULT_LAW, TANGENTIAL_LAWS

#: The tangential law of a run whose deck has no FRICTION card and that asks for none
#: (x3dpd.physics.tangential_laws names it).
DEFAULT_FRICTION = DEFAULT_LAW


@dataclass(frozen=True)
class Step:
    """A run's time step: a fixed ``dt`` [s], or (``auto``) one chosen by accuracy between
    ``dtmin`` and ``dt`` = DTMAX, no longer than ``dt_structure``, the structure's stability
    limit (x3dpd.solver.variable_step; docs/running.md, "A step chosen by accuracy")."""

    dt: float
    auto: bool = False
    dtmin: float = 0.0
    dt_structure: float = math.inf


@dataclass(frozen=True)
class Files:
    """The files of a run that writes them (``trace=``): the trace (with its sidecar
    ``.json``), the energy file and the restart dump; ``resume`` continues from the dump
    (``restart`` asked for it, or the deck's IREST = 1), ``overwrite`` replaces existing
    files (keeping ``.bak`` copies); ``command`` is the command line the sidecar records."""

    trace: str
    energy: str
    dump: str
    overwrite: bool = False
    restart: bool = False
    resume: bool = False
    command: str | None = None

    @property
    def asked_by(self) -> str:
        """What asked to resume, as the messages name it."""
        return "--restart" if self.restart else "the deck's IREST = 1"


def read_deck_file(deck_path: str):
    """The deck at ``deck_path`` read into typed cards (x3dpd.deck); an InputError when there is
    no such file, a DeckError at its first bad token."""
    from x3dpd.deck import read_deck

    if not os.path.isfile(deck_path):
        raise InputError(f"deck {deck_path} does not exist")
    return read_deck(deck_path)


def build_scene(deck, usrfrc: tuple, motion: tuple, mode: str) -> tuple[object, tuple[str, ...]]:
    """The model of ``deck`` with the run's forces and motions (x3dpd.model.build), the deck's
    USRFRC card dropped when ``usrfrc`` replaces it; and the specs it dropped."""
    from x3dpd.model.build import build_model

    model = build_model(deck, usrfrc=usrfrc, motion=motion)
    if usrfrc and mode == "replace" and model.usrfrc:
        return dataclasses.replace(model, usrfrc=()), tuple(model.usrfrc)
    return model, ()


def output_files(deck_path: str, model, o: dict) -> Files | None:
    """The run's files (``trace`` given), their folders checked, the dump to resume from
    required; None for a run that writes nothing."""
    if o["trace"] is None:
        if o["restart"]:
            raise InputError("restart=True needs the trace path of the run to resume (trace=...)")
        return None
    energy = os.fspath(o["energy"]) if o["energy"] is not None else None
    trace, energy, dump = default_paths(deck_path, os.fspath(o["trace"]), energy)
    for path, what in ((trace, "trace file"), (energy, "energy file")):
        check_writable(path, what)
    restart = bool(o["restart"])
    files = Files(
        trace,
        energy,
        dump,
        overwrite=bool(o["overwrite"]),
        restart=restart,
        resume=restart or model.irest == 1,
        command=o["command"],
    )
    if files.resume:
        require_dump(dump, files.asked_by)
    return files


def time_step(dt, parameters, model) -> Step:
    """The step: ``dt`` [s] fixed, or "auto" (or None on a deck whose DTMIN < DTMAX): chosen by
    accuracy in DTMIN ... DTMAX (without a usable DTMIN down to DTMAX/1024)."""
    from x3dpd.model.timestep import recommended_time_step
    from x3dpd.solver.variable_step import auto_floor

    if not wants_auto(dt, parameters):
        step = float(dt if dt is not None else model.dt)
        if not (step > 0 and math.isfinite(step)):
            raise InputError(f"time step must be a positive number, got {step!r}")
        return Step(step)
    dtmax = float(model.dt)
    floor = auto_floor(parameters.dtmin if parameters is not None else 0.0, dtmax)
    if not (0.0 < floor <= dtmax and math.isfinite(dtmax)):
        raise InputError(
            f"a step chosen by accuracy needs 0 < DTMIN <= DTMAX, got {floor!r}, {dtmax!r}"
        )
    limit = recommended_time_step(model).dt_structure
    structure = limit if math.isfinite(limit) and limit > 0 else math.inf
    return Step(dtmax, auto=True, dtmin=floor, dt_structure=structure)


def trace_interval(itrac, model) -> int:
    out = int(itrac if itrac is not None else model.itrac)
    if out < 1:
        raise InputError(f"trace interval ITRAC must be >= 1 step, got {out}")
    return out


def step_counts(model, tmax: float, dt: float) -> tuple[int, int]:
    """Steps of ``dt`` from the deck's start time to ``tmax``, and between restart dumps
    (TREST; 0: none)."""
    t0 = model.t0
    steps = step_count((tmax - t0) / dt, f"TMAX {tmax:g} s from the start time {t0:g} s")
    if steps < 0:
        raise InputError(f"TMAX {tmax:g} s is before the start time {t0:g} s")
    trest = step_count(model.trest / dt, f"TREST {model.trest:g} s") if model.trest > 0 else 0
    return steps, trest


def tangential_law(option: str | None, model) -> str:
    """The run's tangential law: the option, else the deck's FRICTION card's, else the
    default; one of the registry's (x3dpd.physics.tangential_laws)."""
    law = option or model.friction_law or DEFAULT_FRICTION
    if law not in TANGENTIAL_LAWS:
        raise InputError(
            f"friction {law!r}: expected one of the tangential laws {', '.join(TANGENTIAL_LAWS)}"
        )
    return law


def traced_nodes(model, node_ids) -> tuple[int, ...]:
    """Indices of the nodes to record: the deck's TRACE card's (None), ``node_ids`` (user
    ids), or ``"structure"``: the TRACE card's nodes without its particles."""
    traced = np.asarray(model.trace_nodes, dtype=np.int64)
    if node_ids is None:
        return tuple(int(i) for i in traced)
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
        return tuple(int(i) for i in idx)
    ids = np.asarray(list(node_ids), dtype=np.int64)
    if ids.ndim != 1 or ids.size == 0:
        raise InputError("trace_nodes must be a non-empty list of node ids")
    idx = np.searchsorted(model.node_ids, ids)
    bad = [int(i) for i, j in zip(ids, idx) if j >= model.n_nodes or model.node_ids[j] != i]
    if bad:
        raise InputError(f"trace_nodes: node(s) {', '.join(map(str, bad))} are not in the deck")
    return tuple(int(i) for i in idx)


def check_initial_state(initial, key: str, step: Step) -> None:
    """An ``initial_state`` must be an earlier run's final state of the same deck at the same
    step (fixed at the same ``dt``, or chosen by accuracy up to the same DTMAX)."""
    if initial is None:
        return
    if not isinstance(initial, FinalState):
        raise InputError("initial_state must be the final_state of an earlier x3dpd.run result")
    if initial.deck_key != key:
        raise InputError(
            "initial_state belongs to another deck (its cards differ; only TMAX, "
            "TREST and IREST may change)"
        )
    if initial.dt != step.dt or (initial.checkpoint is not None) != step.auto:

        def what(a, d):
            return f"a step chosen by accuracy up to {d!r} s" if a else f"dt {d!r} s"

        raise InputError(
            f"initial_state was computed at "
            f"{what(initial.checkpoint is not None, initial.dt)}; continue it at "
            f"the same step (this run's is {what(step.auto, step.dt)})"
        )
