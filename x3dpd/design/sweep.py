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
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from x3dpd.api.decks import build_model
from x3dpd.design.baselines import baseline_decks
from x3dpd.design.closed_form import (
    base_closed_form_rows,
    base_response_structure,
    baseline_curves,
    closed_form_rows,  # noqa: F401
    force_structure,
    mass_node,
)
from x3dpd.design.spec import SweepSpec
from x3dpd.design.steady_state import SweepPoint, run_point
from x3dpd.errors import InputError

#: sweep.csv columns, in order.
COLUMNS = (
    "config",
    "frequency_hz",
    "drive",
    "drive_quantity",
    "direction",
    "amplitude",
    "phase",
    "velocity",
    "acceleration",
    "accelerance",
    "transmissibility",
    "peak",
    "mean",
    "spread",
    "dissipated_per_cycle",
    "dissipated_particles_per_cycle",
    "input_work_per_cycle",
    "cycles",
    "converged",
    "extrapolated",
    "irregular",
    "branch",
    "measured_amplitude",
    "change",
    "method",
    "start",
    "t_start",
    "t_end",
    "steps",
    "compile_s",
    "wall_s",
    "response_node",
    "response_dof",
)
#: Columns a measured response (``--response``) has of its own; the rest are its point's.
RESPONSE_COLUMNS = (
    "response_node",
    "response_dof",
    "amplitude",
    "phase",
    "velocity",
    "acceleration",
    "accelerance",
    "transmissibility",
    "peak",
    "mean",
    "spread",
    "measured_amplitude",
    "change",
    "converged",
)
DIRECTIONS = ("up", "down", "both")


def deck_hash(path: str | os.PathLike) -> str:
    """SHA-256 of a deck file's bytes (a changed deck invalidates stored points)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def plan(spec: SweepSpec) -> tuple[list[list[SweepPoint]], list[dict]]:
    """The chains to simulate and the closed-form rows, for the deck and its baselines."""
    configs = {"deck": spec.deck, **baseline_decks(spec.deck, spec.baselines, mass_node(spec))}
    if spec.base:  # the base's motion drives it: no USRFRC force besides
        configs = {name: replace(deck, usrfrc=()) for name, deck in configs.items()}
    chains: list[list[SweepPoint]] = []
    closed: list[dict] = []
    for config, deck in configs.items():
        sdof = structures = None
        if config != "deck" and spec.base:
            model = build_model(deck)
            structures = [
                base_response_structure(model, spec.node, spec.dof, r) for r in spec.responses
            ]
            if structures and all(s is not None for s in structures):
                closed.extend(base_closed_form_rows(config, spec, structures))
                continue
        elif config != "deck":
            model = build_model(deck)
            sdof = force_structure(model, spec.node, spec.dof)
            structures = [force_structure(model, spec.node, spec.dof, r) for r in spec.responses]
        if sdof is not None and all(s is not None for s in structures):
            closed.extend(closed_form_rows(config, sdof, spec, structures))
            continue
        for drive in spec.drives:
            # called only within this iteration; the defaults bind this iteration's values
            def point(
                f: float, direction: str = "", *, config=config, deck=deck, drive=drive
            ) -> SweepPoint:
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
                )

            freqs = sorted(spec.frequencies)
            if spec.direction is None:
                chains.extend([point(f)] for f in freqs)
            if spec.direction in ("up", "both"):
                chains.append([point(f, "up") for f in freqs])
            if spec.direction in ("down", "both"):
                chains.append([point(f, "down") for f in reversed(freqs)])
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
        _write_atomic(stored, json.dumps(settings, indent=1).encode())

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
            _write_atomic(self.points / f"{point.key}.state", pickle.dumps(state))
        _write_atomic(self.points / f"{point.key}.json", json.dumps(row).encode())


def _write_atomic(path: Path, data: bytes) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def run_sweep(
    spec: SweepSpec,
    out: str | os.PathLike,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    overwrite: bool = False,
    on_point: Callable[[dict], None] | None = None,
) -> list[dict]:
    """Run (or resume) a sweep into ``out``; returns all rows, sorted, and writes sweep.csv.

    ``workers``: local worker processes (default: all cores; 1 = serial in this process);
    ``scheduler``: address of an existing Dask scheduler (overrides ``workers``);
    ``on_point(row)`` is called as each point finishes (progress).
    """
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
    rows = sort_rows(rows)
    label_branches(rows)
    write_csv(Path(out) / "sweep.csv", rows)
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
    workers = workers or os.cpu_count() or 1
    if scheduler is None and workers == 1:
        for fn, chain, previous, finished in todo:
            for point in chain:
                previous = fn(point, previous)
                finished(point, len(chain), previous)
    elif todo:
        _run_dask(todo, workers, scheduler)


def _run_dask(todo, workers: int, scheduler: str | None) -> None:
    from dask.distributed import Client, LocalCluster, as_completed

    if scheduler is not None:
        client, cluster = Client(scheduler), None
    else:
        # the worker processes start with SIGINT ignored (a process inherits that, and Python
        # then installs no KeyboardInterrupt of its own): Ctrl-C reaches the whole process
        # group, and this process, not each worker, decides what happens
        main = threading.current_thread() is threading.main_thread()
        old = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
        try:
            cluster = LocalCluster(
                n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0"
            )
        finally:
            if main:
                signal.signal(signal.SIGINT, old)
        client = Client(cluster)
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
    finally:
        client.close(timeout=10)
        if cluster is not None:
            cluster.close(timeout=10)


def sort_rows(rows: Sequence[dict]) -> list[dict]:
    """Rows ordered by config (deck first), drive, direction, frequency."""
    order = {"deck": 0, "undamped": 1, "added-mass": 2}
    return sorted(
        rows,
        key=lambda r: (
            order.get(r["config"], 9),
            r["config"],
            r["drive"],
            r["direction"],
            r["frequency_hz"],
        ),
    )


def label_branches(rows: list[dict]) -> None:
    """Say which branch each point is on (``branch`` column).

    Where an up and a down chain of the same config and drive disagree at a frequency by more
    than their tolerance (hysteresis), the larger amplitude is on the ``high`` branch and the
    smaller on the ``low`` one; elsewhere the response is ``single``-valued. Points run from the
    initial state (no direction) or in closed form are ``single``; an irregular point is
    ``irregular`` whatever its neighbours.
    """
    by = {}
    for r in rows:
        by.setdefault((r["config"], r["drive"], r["frequency_hz"]), {})[r["direction"]] = r
    for group in by.values():
        up, down = group.get("up"), group.get("down")
        for r in group.values():
            r["branch"] = "single"
        if up and down:
            tol = 3.0 * max(abs(up["change"]), abs(down["change"]), 0.01)
            if abs(up["amplitude"] - down["amplitude"]) > tol * max(
                up["amplitude"], down["amplitude"]
            ):
                hi, lo = (up, down) if up["amplitude"] > down["amplitude"] else (down, up)
                hi["branch"], lo["branch"] = "high", "low"
        for r in group.values():
            if r.get("irregular"):
                r["branch"] = "irregular"


def write_csv(path: Path, rows: Sequence[dict]) -> None:
    """sweep.csv: one row per point and measured node, columns :data:`COLUMNS` (full precision,
    repr floats): the driven node's row (``response_node``, ``response_dof`` the drive's), then
    a row per ``--response`` with that node's :data:`RESPONSE_COLUMNS` and the point's others."""
    lines = [",".join(COLUMNS)]
    for r in expand_responses(rows):
        lines.append(",".join(_cell(r.get(c, "")) for c in COLUMNS))
    _write_atomic(path, ("\n".join(lines) + "\n").encode())


def expand_responses(rows: Sequence[dict]) -> list[dict]:
    """One row per point and measured node (see :func:`write_csv`)."""
    out = []
    for r in rows:
        point = {k: v for k, v in r.items() if k != "responses"}
        out.append(point)
        out.extend({**point, **m} for m in r.get("responses", ()))
    return out


def _cell(v) -> str:
    if isinstance(v, bool) or isinstance(v, np.bool_):
        return "1" if v else "0"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def read_csv(path: str | os.PathLike) -> list[dict]:
    """Rows of a sweep.csv, numbers as floats (for plots and comparisons)."""
    text = Path(path).read_text().splitlines()
    head = text[0].split(",")
    out = []
    for line in text[1:]:
        row = {}
        for k, v in zip(head, line.split(",")):
            try:
                row[k] = float(v)
            except ValueError:
                row[k] = v
        out.append(row)
    return out
