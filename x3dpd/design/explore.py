"""``x3dpd design SPEC --out DIR``: every configuration of a design file evaluated (report
Section 7.5, steps 3-6), on Dask, resumable.

Each configuration's deck is made and written first (x3dpd.design.configs). Its evaluation is
a sweep -- a frequency band, or a dwell (one frequency, the drive levels) -- or a ring-down:

* sweep and dwell: a :class:`~x3dpd.design.spec.SweepSpec` per configuration, planned by
  :func:`x3dpd.design.sweep.plan` (baselines in closed form where the structure is linear) and
  stored in ``DIR/configs/NAME/sweep/`` exactly as ``x3dpd sweep DECK --out`` stores it, so a
  configuration's points are the numbers ``x3dpd sweep`` gives for its deck;
* ring-down: the deck driven (its USRFRC card, or a sine at each drive level), released, and
  its % zeta versus amplitude measured (x3dpd.design.ringdown), one result per drive in
  ``DIR/configs/NAME/ringdown/``.

All configurations' chains go to one Dask cluster at once (:func:`x3dpd.design.sweep.
run_chains`; ``workers=1`` serially here): the same function computes every point in every
mode, so a parallel design equals the serial one bit for bit. A finished point is on disk at
once; a rerun computes only what is missing. Then ``DIR/design.csv`` and the figures
(x3dpd.design.design_table, x3dpd.analysis.design_charts).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

from x3dpd.api.decks import Deck
from x3dpd.design.configs import (
    Made,
    code_files,
    make_configurations,
    require_drive,
    write_configurations,
)
from x3dpd.design.design_file import DesignFile, read_design
from x3dpd.design.spec import SweepSpec
from x3dpd.design.steady_state import run_point
from x3dpd.design.sweep import (
    SweepDir,
    deck_hash,
    label_branches,
    pending,
    plan,
    run_chains,
    sort_rows,
    write_csv,
)
from x3dpd.errors import InputError
from x3dpd.units import labels_for


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


def run_design(
    path: str | os.PathLike,
    out: str | os.PathLike,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    overwrite: bool = False,
    echo: Callable[[str], None] = print,
) -> list[dict]:
    """Run (or resume) a design into ``out``; returns design.csv's rows (module doc)."""
    from x3dpd.design.design_table import design_rows, write_design_csv

    design = read_design(path)
    made = make_configurations(design)  # every error before anything is written
    require_drive(design, made)
    for code in code_files(made[0].deck) if design.usrfrc_code and made else ():
        echo(
            f"code run: {code} (the structure's USRFRC Python file, copied beside every "
            "configuration's deck): this design executes it with your permissions; read it "
            "first if the deck came from someone else (docs/usrfrc.md)"
        )
    out = Path(out)
    configs = [Config(m, out / "configs" / m.config.name) for m in made]
    ev = design.evaluation
    for c in configs:
        if ev.kind != "ringdown":
            c.spec = _sweep_spec(design, c.made)
    for c in configs:
        if c.spec is not None:
            plan(c.spec)  # a bad baseline or drive point: before writing
    for c, m in zip(configs, made):  # before any deck is written: stored points kept
        if (
            c.spec is not None
            and _changed(
                c.folder,
                replace(c.spec, deck_text_hash=hashlib.sha256(m.text.encode("utf-8")).hexdigest()),
            )
            and not overwrite
        ):
            raise InputError(
                f"{c.folder / 'sweep'}: holds points of another deck or other "
                f"settings for configuration {m.config.name} (the design file "
                "changed); give another --out, or --overwrite to recompute the "
                "configurations that changed"
            )
    made = write_configurations(made, out, design)
    _write_settings(out, design)
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
    for c in configs:
        if c.spec is not None:
            c.rows = sort_rows(c.rows)
            label_branches(c.rows)
            write_csv(c.folder / "sweep" / "sweep.csv", c.rows)
    rows = design_rows(design, configs)
    write_design_csv(out / "design.csv", rows)
    figures = _figures(out, design, rows, configs)
    best = [r for r in rows if r["best"]]
    tied = [r for r in rows if r["verdict"].startswith("no significant")]
    if best:
        b = best[0]
        echo(
            f"best configuration{' within the mass budget' if design.mass_budget else ''}: "
            f"{b['config']} (added mass {b['added_mass']:.4g}, {_score_text(b, ev.kind)})"
        )
    elif tied:
        a = tied[0]
        echo(
            f"no significant difference: {a['config']} leads ({_score_text(a, ev.kind)}) but "
            f"its interval overlaps the runner-up's, {a['verdict'].split(' from ')[-1]}"
        )
    else:
        echo("no best configuration: none within the budget converged at every point")
    echo(
        f"wrote {out / 'design.csv'} and "
        + ", ".join(str(f) for f in figures)
        + f" ({len(rows)} rows, {progress.computed} points computed in "
        f"{_duration(time.perf_counter() - progress.start)})"
    )
    return rows


def _figures(out: Path, design: DesignFile, rows: list[dict], configs: list[Config]) -> list:
    """The design's figures (x3dpd.analysis.design_charts); a sweep's also the responses of
    every configuration at each drive over the undamped baseline (Figures 45-48)."""
    from x3dpd.api.figures import (
        plot_attenuation_vs_mass,
        plot_configurations,
        plot_damping_families,
    )
    from x3dpd.design.closed_form import baseline_curves

    if not rows:
        return []
    title = design.title
    deck = configs[0].made.deck
    units = labels_for(deck.units.system if deck.units is not None else None)
    if design.evaluation.kind == "ringdown":
        return [
            plot_damping_families(
                out / "design_damping.png", rows, design.mass_budget, title, units["mass"]
            )
        ]
    figures = [
        plot_attenuation_vs_mass(
            out / "design_attenuation.png",
            rows,
            design.mass_budget,
            title,
            mass_unit=units["mass"],
            force_unit=units["force"],
        )
    ]
    if design.evaluation.kind == "sweep":
        curves = baseline_curves(configs[0].spec)
        for k, drive in enumerate(design.evaluation.drives, 1):
            series = {
                c.made.config.name: [
                    r for r in c.rows if r["config"] == "deck" and r["drive"] == drive
                ]
                for c in configs
            }
            base = {}
            if ("undamped", drive) in curves:
                base["undamped (closed form)"] = curves[("undamped", drive)]
            same_mass = len({c.made.values["added_mass"] for c in configs}) == 1
            if same_mass and ("added-mass", drive) in curves:  # e.g. an equal-mass study
                base["added mass (closed form)"] = curves[("added-mass", drive)]
            figures.append(
                plot_configurations(
                    out / f"design_response_{k}.png",
                    series,
                    base,
                    title=f"{title}, drive {drive:.5g} {units['force']}",
                )
            )
    return figures


def _score_text(row: dict, kind: str) -> str:
    ci = row.get("score_ci", math.nan)
    if kind == "ringdown":
        return f"mean zeta {row['score']:.3g} +/- {ci:.2g} %"
    return f"peak attenuation {row['score']:.2f} +/- {ci:.2f} dB (worst drive)"


def _sweep_spec(design: DesignFile, made: Made) -> SweepSpec:
    ev = design.evaluation
    node, dof = made.drive
    if node not in {n.nid for n in made.deck.nodes}:
        raise InputError(
            f"{design.where('evaluate', 'node')}: evaluate.node: node {node} is "
            f"not a node of {design.structure.name}"
        )
    return SweepSpec(
        deck=made.deck,
        deck_text_hash="",
        frequencies=ev.frequencies,
        drives=ev.drives,
        node=node,
        dof=dof,
        direction=ev.direction,
        baselines=ev.baselines,
        criterion=ev.criterion,
    )


def _changed(folder: Path, spec: SweepSpec) -> bool:
    """Whether ``folder``/sweep holds points computed with other settings or another deck."""
    stored = folder / "sweep" / "sweep.json"
    return stored.exists() and json.loads(stored.read_text()) != json.loads(
        json.dumps(spec.settings())
    )


def _write_settings(out: Path, design: DesignFile) -> None:
    out.mkdir(parents=True, exist_ok=True)
    (out / "design.toml").write_text(design.text)


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
            spec = f"sine:node={node},dof={dof},amp={level!r},hz={ev.frequencies[0]!r}"
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
    if isinstance(point, RingdownTask):
        return f"ring-down, zeta up to {max(row['zeta_percent'], default=math.nan):.3g} %"
    flag = "" if row["converged"] else "  NOT CONVERGED (cap)"
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
