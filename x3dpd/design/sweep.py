"""Frequency sweeps of a damper design (report Section 7.5; Figures 45-48, 52).

A sweep is a set of *chains* of :class:`~x3dpd.design.steady_state.SweepPoint`: without a
direction every point is a chain of its own, started from the deck's initial state, and all run
in parallel; with ``direction`` up or down the points of one drive level form one chain whose
points continue from the previous point's final state (particles already settled, the structure
already moving), so jumps and hysteresis show as in the report's up/down experiments; ``both``
runs the two chains side by side. Baselines whose structure is a linear SDOF are computed in
closed form (``x3dpd/design/baselines.py``); otherwise they are simulated like the deck.

A point is driven by a force on its node, or, in a base drive (``SweepSpec.quantity`` not
"force", x3dpd.design.drive), by moving its node on a prescribed sine: the deck's USRFRC card is
then dropped, and each measured response has a ``transmissibility`` (its acceleration amplitude
over the base's) where a force drive has an ``accelerance``.

Execution goes through ``dask.distributed``: ``workers`` local worker processes (a LocalCluster),
or an existing cluster at ``scheduler``; ``workers=1`` runs serially in this process. The same
function computes every point in every mode, so the results are identical bit for bit. A point
of a chain is submitted with the future of its predecessor as argument: the chain runs in order,
different chains at once.

Every finished point is written at once to ``DIR/points/KEY.json`` (its row) and, for chains,
``DIR/points/KEY.state`` (its final state, pickled). A rerun with the same settings loads them
and computes only the missing points, a chain resuming from its last finished point.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import pickle
import signal
import threading
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path


from x3dpd.api.cluster import connect_scheduler
from x3dpd.api.decks import build_model
from x3dpd.design.baselines import baseline_decks
from x3dpd.design.closed_form import (
    base_closed_form_rows,
    base_response_structure,
    baseline_curves,  # noqa: F401  (re-exported)
    closed_form_rows,
    force_structure,
    mass_node,
)
from x3dpd.design.spec import SweepSpec
from x3dpd.design.replicas import pooled
from x3dpd.design.steady_state import SweepPoint, has_particles, run_point
from x3dpd.design.sweep_table import (  # noqa: F401  (re-exported: the sweep's public names)
    COLUMNS,
    RESPONSE_COLUMNS,
    expand_responses,
    label_branches,
    read_csv,
    sort_rows,
    write_atomic,
    write_csv,
)
from x3dpd.errors import InputError

DIRECTIONS = ("up", "down", "both")


def deck_hash(path: str | os.PathLike) -> str:
    """SHA-256 of a deck file's bytes (a changed deck invalidates stored points)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def configurations(spec: SweepSpec) -> list[tuple[str, object, list | None]]:
    """(config, deck, closed-form structures or None) of the deck and its baselines: a
    baseline whose structure has a closed form (x3dpd.design.closed_form) is computed, not
    simulated; None marks a configuration to simulate."""
    configs = {"deck": spec.deck, **baseline_decks(spec.deck, spec.baselines, mass_node(spec))}
    if spec.base:  # the base's motion drives it: no USRFRC force besides
        configs = {name: replace(deck, usrfrc=()) for name, deck in configs.items()}
    out = []
    for config, deck in configs.items():
        closed = None
        if config != "deck" and spec.base:
            model = build_model(deck)
            structures = [
                base_response_structure(model, spec.node, spec.dof, r) for r in spec.responses
            ]
            if structures and all(s is not None for s in structures):
                closed = ("base", structures)
        elif config != "deck":
            model = build_model(deck)
            sdof = force_structure(model, spec.node, spec.dof)
            structures = [force_structure(model, spec.node, spec.dof, r) for r in spec.responses]
            if sdof is not None and all(s is not None for s in structures):
                closed = ("force", (sdof, structures))
        out.append((config, deck, closed))
    return out


def closed_rows(config: str, closed, spec: SweepSpec) -> list[dict]:
    """The rows of a closed-form configuration at ``spec.frequencies``."""
    kind, what = closed
    if kind == "base":
        return base_closed_form_rows(config, spec, what)
    return closed_form_rows(config, what[0], spec, what[1])


def point_maker(spec: SweepSpec, config: str, deck, drive: float):
    """A function ``(f, direction="", replica=0) -> SweepPoint`` of one configuration and
    drive."""

    def point(f: float, direction: str = "", replica: int = 0) -> SweepPoint:
        return SweepPoint(
            config=config,
            deck=deck,
            frequency_hz=f,
            drive=drive,
            node=spec.node,
            dof=spec.dof,
            direction=direction,
            dt=spec.dt,
            criterion=spec.criterion,
            responses=spec.responses,
            quantity=spec.quantity,
            replica=replica,
        )

    return point


def replica_count(spec: SweepSpec, deck) -> int:
    """How many replicas each point of ``deck`` runs: the criterion's, one without particles
    (a deterministic answer has nothing to pool)."""
    return spec.criterion.replicas if has_particles(deck) else 1


def plan(spec: SweepSpec) -> tuple[list[list[SweepPoint]], list[dict]]:
    """The chains to simulate and the closed-form rows, for the deck and its baselines."""
    chains: list[list[SweepPoint]] = []
    closed: list[dict] = []
    for config, deck, structures in configurations(spec):
        if structures is not None:
            closed.extend(closed_rows(config, structures, spec))
            continue
        for drive in spec.drives:
            point = point_maker(spec, config, deck, drive)
            freqs = sorted(spec.frequencies)
            for r in range(replica_count(spec, deck)):
                if spec.direction is None:
                    chains.extend([point(f, "", r)] for f in freqs)
                if spec.direction in ("up", "both"):
                    chains.append([point(f, "up", r) for f in freqs])
                if spec.direction in ("down", "both"):
                    chains.append([point(f, "down", r) for f in reversed(freqs)])
    return chains, closed


class SweepDir:
    """The output folder: settings, finished points (rows and chain states), sweep.csv."""

    def __init__(self, out: str | os.PathLike, spec: SweepSpec, overwrite: bool = False):
        self.out = Path(out)
        self.points = self.out / "points"
        settings = spec.settings()
        stored = self.out / "sweep.json"
        if stored.exists() and not overwrite:
            old = json.loads(stored.read_text())
            if old != json.loads(json.dumps(settings)):
                raise InputError(
                    f"{self.out}: holds a sweep with other settings ({stored}); "
                    f"give another --out, or --overwrite to discard it"
                )
        elif overwrite and self.points.exists():
            for p in self.points.iterdir():
                p.unlink()
        self.points.mkdir(parents=True, exist_ok=True)
        write_atomic(stored, json.dumps(settings, indent=1).encode())

    def load(self, point: SweepPoint, need_state: bool):
        """The stored (row, state) of a finished point, or None."""
        row_path = self.points / f"{point.key}.json"
        if not row_path.exists():
            return None
        row = json.loads(row_path.read_text())
        state = None
        if need_state:
            state_path = self.points / f"{point.key}.state"
            if not state_path.exists():
                return None
            state = pickle.loads(state_path.read_bytes())
        return row, state

    def save(self, point: SweepPoint, row: dict, state, keep_state: bool) -> None:
        """Store a finished point (state first: a row without its state is not finished)."""
        if keep_state:
            write_atomic(self.points / f"{point.key}.state", pickle.dumps(state))
        write_atomic(self.points / f"{point.key}.json", json.dumps(row).encode())


def run_sweep(
    spec: SweepSpec,
    out: str | os.PathLike,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    overwrite: bool = False,
    on_point: Callable[[dict], None] | None = None,
) -> list[dict]:
    """Run (or resume) a sweep into ``out``; returns all rows, sorted, and writes sweep.csv
    (and, with ``spec.auto``, peaks.csv: x3dpd.design.auto_sweep).

    ``workers``: local worker processes (default: all cores; 1 = serial in this process);
    ``scheduler``: address of an existing Dask scheduler (overrides ``workers``);
    ``on_point(row)`` is called as each point finishes (progress).
    """
    if spec.auto is not None:
        return _run_auto_sweep(spec, out, workers, scheduler, overwrite, on_point)
    chains, rows = plan(spec)  # first: a bad baseline or structure writes nothing
    store = SweepDir(out, spec, overwrite)
    done, todo = pending(chains, store)
    rows.extend(done)

    def finished(point: SweepPoint, chain_len: int, result) -> None:
        row, state = result
        store.save(point, row, state, keep_state=chain_len > 1)
        rows.append(row)
        if on_point:
            on_point(row)

    run_chains(
        [(run_point, chain, previous, finished) for chain, previous in todo], workers, scheduler
    )
    rows = sort_rows(pooled(rows, spec.criterion.tol))
    label_branches(rows)
    write_csv(Path(out) / "sweep.csv", rows)
    return rows


def _run_auto_sweep(spec, out, workers, scheduler, overwrite, on_point) -> list[dict]:
    """``run_sweep`` of a peak search (x3dpd.design.auto_sweep)."""
    from x3dpd.design.auto_sweep import AutoJob, run_auto, write_peaks

    configs = configurations(spec)  # first: a bad baseline or structure writes nothing
    store = SweepDir(out, spec, overwrite)
    rows: list[dict] = []
    simulated = [(config, deck) for config, deck, closed in configs if closed is None]

    def finished_row(row: dict, computed: bool) -> None:
        rows.append(row)
        if computed and on_point:
            on_point(row)

    with Executor(workers, scheduler) as executor:
        (groups,) = run_auto([AutoJob(spec, store, simulated, finished_row)], executor)
    rows = finish_auto_rows(spec, configs, groups, rows)
    write_csv(Path(out) / "sweep.csv", rows)
    write_peaks(Path(out) / "peaks.csv", groups)
    return rows


def finish_auto_rows(spec: SweepSpec, configs, groups, rows: list[dict]) -> list[dict]:
    """A peak search's rows with the closed-form baselines' at the frequencies it visited,
    sorted and their branches labelled."""
    from x3dpd.design.auto_sweep import visited

    at = visited(spec, groups)
    rows = pooled(rows, spec.criterion.tol)
    for config, _, closed in configs:
        if closed is not None:
            rows.extend(closed_rows(config, closed, at))
    rows = sort_rows(rows)
    label_branches(rows)
    return rows


def pending(
    chains: list[list[SweepPoint]], store: SweepDir
) -> tuple[list[dict], list[tuple[list[SweepPoint], object]]]:
    """(rows of the points already in ``store``, [(rest of a chain, the (row, state) its first
    point continues from, or None)]): what is left to compute."""
    rows, todo = [], []
    for chain in chains:
        keep_state = len(chain) > 1
        previous = None
        for k, point in enumerate(chain):
            done = store.load(point, need_state=keep_state and k < len(chain) - 1)
            if done is None:
                later = [p for p in chain[k + 1 :] if store.load(p, need_state=False)]
                if later:
                    raise InputError(
                        f"{store.out}: a point inserted before {later[0].frequency_hz:g} Hz in "
                        f"the {point.direction} chain would change the history of points "
                        "already computed; give another --out, or --overwrite to recompute"
                    )
                todo.append((chain[k:], previous))
                break
            rows.append(done[0])
            previous = done
    return rows, todo


def run_chains(todo, workers: int | None = None, scheduler: str | None = None) -> None:
    """Run chains of tasks: ``todo`` = [(fn, chain, previous, finished)], each task computed as
    ``result = fn(point, previous)`` (``previous`` the result of the point before in its chain,
    or the given one for its first), then ``finished(point, len(chain), result)`` in this
    process. ``workers`` local processes (default: all cores; 1: serially here) or an existing
    cluster at ``scheduler``; the same ``fn`` computes each task in every mode."""
    with Executor(workers, scheduler) as executor:
        executor.run(todo)


class Executor:
    """Where chains of tasks run (:func:`run_chains`), kept open across several calls of
    :meth:`run` (an adaptive sweep's rounds): serially in this process (``workers`` 1), on a
    local cluster of ``workers`` processes (default: all cores), or on the cluster at
    ``scheduler``. The cluster starts at the first task."""

    def __init__(self, workers: int | None = None, scheduler: str | None = None):
        self.workers = workers or os.cpu_count() or 1
        self.scheduler = scheduler
        self.client = self.cluster = None

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc) -> None:
        if self.client is not None:
            self.client.close(timeout=10)
        if self.cluster is not None:
            self.cluster.close(timeout=10)

    def run(self, todo) -> None:
        """Run ``todo`` (as :func:`run_chains` does) to its end."""
        if self.scheduler is None and self.workers == 1:
            for fn, chain, previous, finished in todo:
                for point in chain:
                    previous = fn(point, previous)
                    finished(point, len(chain), previous)
        elif todo:
            if self.client is None:
                self.client, self.cluster = _dask_client(self.workers, self.scheduler)
            _run_dask(self.client, todo)


def _dask_client(workers: int, scheduler: str | None):
    from dask.distributed import Client, LocalCluster

    if scheduler is not None:
        return connect_scheduler(scheduler), None
    # the worker processes start with SIGINT ignored (a process inherits that, and Python
    # then installs no KeyboardInterrupt of its own): Ctrl-C reaches the whole process group,
    # and this process, not each worker, decides what happens
    main = threading.current_thread() is threading.main_thread()
    old = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0"
        )
    finally:
        if main:
            signal.signal(signal.SIGINT, old)
    return Client(cluster), cluster


def _run_dask(client, todo) -> None:
    from dask.distributed import as_completed

    futures = {}
    try:
        for fn, chain, previous, finished in todo:
            for point in chain:
                previous = client.submit(fn, point, previous, pure=False)
                futures[previous] = (point, len(chain), finished)
        for future in as_completed(list(futures)):
            point, n, finished = futures[future]
            finished(point, n, future.result())
    except KeyboardInterrupt:
        # Ctrl-C: finished points are already on disk; closing the cluster drops the queued
        # ones, and a worker inside a compiled step loop (which cannot be interrupted) is
        # killed by its nanny after a few seconds. The nannies live in this process and
        # narrate the shutdown at length.
        logging.getLogger("distributed").setLevel(logging.CRITICAL)
        raise
