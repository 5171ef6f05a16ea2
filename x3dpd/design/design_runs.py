"""How a design's evaluations run (x3dpd.design.explore.run_design): every configuration's
points -- a fixed grid's chains, peak searches (x3dpd.design.auto_sweep) or ring-downs -- on
one executor, resuming what is stored, with a progress line per finished point.
"""

from __future__ import annotations

import json
import math
import os
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

from x3dpd.api.decks import Deck
from x3dpd.design.auto_sweep import AutoJob, run_auto, visited, write_peaks
from x3dpd.design.configs import Made
from x3dpd.design.design_file import DesignFile
from x3dpd.design.spec import SweepSpec
from x3dpd.design.steady_state import cap_flag, run_point
from x3dpd.design.sweep import (
    Executor,
    SweepDir,
    configurations,
    deck_hash,
    finish_auto_rows,
    pending,
    plan,
    run_chains,
)


@dataclass(frozen=True)
class RingdownTask:
    """One ring-down of a configuration's deck: driven by ``drive`` specs (empty: the deck's
    USRFRC card) until ``drive_until``, then ``ring`` seconds free."""

    deck: Deck
    node: int
    dof: int
    drive: tuple[str, ...]
    level: float
    drive_until: float
    ring: float
    key: str = field(default="")


def run_ringdown(task: RingdownTask, previous=None) -> tuple[dict, None]:
    """A ring-down's columns (x3dpd.analysis.ringdown.Ringdown.columns) as lists."""
    from x3dpd.design.ringdown import ringdown_of_deck

    rd = ringdown_of_deck(
        task.deck,
        task.node,
        task.dof,
        drive_until=task.drive_until,
        ring=task.ring,
        drive=task.drive,
    )
    return {k: [float(x) for x in v] for k, v in rd.columns().items()}, None


@dataclass
class Config:
    """A configuration at run time: its made deck, sweep spec and store, rows collected."""

    made: Made
    folder: Path
    spec: SweepSpec | None = None
    store: SweepDir | None = None
    rows: list = field(default_factory=list)
    ringdowns: dict = field(default_factory=dict)
    total: int = 0
    left: int = 0
    node: int = 0
    dof: int = 0
    #: a peak search's (config, deck, closed form) parts (x3dpd.design.sweep.configurations)
    parts: list = field(default_factory=list)


def _run_fixed_design(configs, made, ev, workers, scheduler, echo, design, out) -> _Progress:
    """Every configuration's points of a fixed grid (or its ring-downs) on one executor."""
    todo = []
    for c, m in zip(configs, made):
        c.made = m
        mine = _pending(design, c)
        c.left = sum(len(chain) for _, chain, _, _ in mine)
        todo.extend((c, entry) for entry in mine)
    total = sum(c.total for c in configs)
    left = sum(c.left for c in configs)
    echo(
        f"design {design.path}: {len(configs)} configurations, {ev.kind}, {total} points "
        f"({total - left} stored before), into {out}"
    )
    progress = _Progress(configs, total, total - left, echo)
    # the costliest configurations first (particles per step x steps per second): their
    # chains set the critical path; the order does not change any number
    todo.sort(key=lambda item: -item[0].made.values["count"] / item[0].made.values["dt"])
    todo = [
        (fn, chain, previous, progress.wrap(c, finished))
        for c, (fn, chain, previous, finished) in todo
    ]
    try:
        run_chains(todo, workers, scheduler)
    except KeyboardInterrupt:
        echo(
            f"interrupted: {progress.computed} point(s) finished in this call are kept in "
            f"{out}; the same command resumes the design"
        )
        raise
    return progress


def _run_auto_design(configs, made, ev, workers, scheduler, echo, design) -> _Progress:
    """Every configuration's peak searches (x3dpd.design.auto_sweep), their rounds together on
    one executor; each configuration's peaks in its sweep/peaks.csv."""
    band = ev.auto
    chains = 2 if ev.direction == "both" else 1
    per_config = band.max_points * len(ev.drives) * chains
    echo(
        f"design {design.path}: {len(configs)} configurations, the peak in {band.lo:g}-"
        f"{band.hi:g} Hz to {band.resolution:g} Hz, at most {per_config} points each"
    )
    progress = _Progress(configs, per_config * len(configs), 0, echo)
    jobs, found = [], []
    for c, m in zip(configs, made):
        c.made, c.left = m, per_config
        c.spec = replace(c.spec, deck=m.deck, deck_text_hash=deck_hash(m.path))
        c.store = SweepDir(c.folder / "sweep", c.spec, overwrite=_changed(c.folder, c.spec))
        c.parts = configurations(c.spec)
        simulated = [(name, deck) for name, deck, closed in c.parts if closed is None]

        def finished_row(row: dict, computed: bool, c=c) -> None:
            c.rows.append(row)
            if computed:
                progress.tick(c, _label(None, row))

        jobs.append(AutoJob(c.spec, c.store, simulated, finished_row))
    with Executor(workers, scheduler) as executor:
        found = run_auto(jobs, executor)
    for c, groups in zip(configs, found):
        c.rows = finish_auto_rows(c.spec, c.parts, groups, c.rows)
        # the band the search visited: what the closed-form curves are drawn over
        c.spec = visited(c.spec, groups)
        write_peaks(c.folder / "sweep" / "peaks.csv", groups)
    return progress


def _changed(folder: Path, spec: SweepSpec) -> bool:
    """Whether ``folder``/sweep holds points computed with other settings or another deck."""
    stored = folder / "sweep" / "sweep.json"
    return stored.exists() and json.loads(stored.read_text()) != json.loads(
        json.dumps(spec.settings())
    )


def _pending(design: DesignFile, c: Config) -> list:
    """The chains of ``c`` still to compute; fills ``c.rows`` / ``c.ringdowns`` with what is
    stored and ``c.total`` with its number of points."""
    if c.spec is None:
        return _pending_ringdowns(design, c)
    c.spec = replace(c.spec, deck=c.made.deck, deck_text_hash=deck_hash(c.made.path))
    chains, closed = plan(c.spec)
    c.store = SweepDir(c.folder / "sweep", c.spec, overwrite=_changed(c.folder, c.spec))
    done, todo = pending(chains, c.store)
    c.rows = closed + done
    c.total = sum(len(chain) for chain in chains)

    def finished(point, chain_len: int, result) -> None:
        row, state = result
        c.store.save(point, row, state, keep_state=chain_len > 1)
        c.rows.append(row)

    return [(run_point, chain, previous, finished) for chain, previous in todo]


def _pending_ringdowns(design: DesignFile, c: Config) -> list:
    ev = design.evaluation
    node, dof = c.made.drive
    c.node, c.dof = node, dof
    store = c.folder / "ringdown"
    store.mkdir(parents=True, exist_ok=True)
    digest = deck_hash(c.made.path)[:16]
    tasks = []
    if ev.drives and ev.frequencies:
        for level in ev.drives:
            hz = float(ev.frequencies[0])
            spec = f"sine:node={node},dof={dof},amp={float(level)!r},hz={hz!r}"
            tasks.append(
                RingdownTask(
                    c.made.deck,
                    node,
                    dof,
                    (spec,),
                    level,
                    ev.drive_until,
                    ev.ring,
                    key=f"F{level:.6e}_{digest}",
                )
            )
    else:
        tasks.append(
            RingdownTask(
                c.made.deck, node, dof, (), math.nan, ev.drive_until, ev.ring, key=f"deck_{digest}"
            )
        )
    c.total = len(tasks)
    todo = []
    for task in tasks:
        path = store / f"{task.key}_{task.drive_until:g}_{task.ring:g}.json"
        if path.exists():
            c.ringdowns[task.level] = json.loads(path.read_text())
            continue

        def finished(task, chain_len, result, path=path) -> None:
            tmp = path.with_name(path.name + ".tmp")
            tmp.write_text(json.dumps(result[0]))
            os.replace(tmp, path)
            c.ringdowns[task.level] = result[0]

        todo.append((run_ringdown, [task], None, finished))
    return todo


class _Progress:
    """Prints, as each point finishes, the points and configurations done and an ETA (from the
    mean wall time of the points computed so far in this call)."""

    def __init__(self, configs: list[Config], total: int, done: int, echo):
        self.total, self.done, self.computed, self.echo = total, done, 0, echo
        self.start = time.perf_counter()
        self.configs = configs

    def wrap(self, c: Config, finished):
        def call(point, chain_len: int, result) -> None:
            finished(point, chain_len, result)
            self.tick(c, _label(point, result[0]))

        return call

    def tick(self, c: Config, label: str) -> None:
        self.done += 1
        self.computed += 1
        c.left -= 1
        elapsed = time.perf_counter() - self.start
        eta = elapsed / self.computed * (self.total - self.done)
        configs_done = sum(1 for k in self.configs if k.left <= 0)
        self.echo(
            f"  [{self.done}/{self.total} points, {configs_done}/{len(self.configs)} "
            f"configurations, ETA {_duration(eta)}] {c.made.config.name}: {label}"
        )


def _label(point, row: dict) -> str:
    """How the progress line names a finished point (``point`` None: a peak search's)."""
    if isinstance(point, RingdownTask):
        return f"ring-down, zeta up to {max(row['zeta_percent'], default=math.nan):.3g} %"
    flag = cap_flag(row)
    return (
        f"{row['config']} F={row['drive']:.5g} {row['direction'] or '-'} "
        f"{row['frequency_hz']:.4f} Hz X={row['amplitude']:.5e} {row['cycles']} cycles"
        f"{flag}"
    )


def _duration(seconds: float) -> str:
    seconds = round(seconds)
    if seconds < 60:
        return f"{seconds} s"
    if seconds < 3600:
        return f"{seconds // 60} min {seconds % 60:02d} s"
    return f"{seconds // 3600} h {seconds % 3600 // 60:02d} min"
