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
import math
import os
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

from x3dpd.api.cluster import check_scheduler
from x3dpd.design.configs import (
    Made,
    code_files,
    make_configurations,
    require_drive,
    write_configurations,
)
from x3dpd.design.design_file import DesignFile, read_design
from x3dpd.design.spec import SweepSpec
from x3dpd.design.design_runs import (
    Config,
    RingdownTask,  # noqa: F401  (re-exported: x3dpd.design.explore.RingdownTask)
    _changed,
    _duration,
    _run_auto_design,
    _run_fixed_design,
    run_ringdown,  # noqa: F401  (re-exported)
)
from x3dpd.design.replicas import pooled
from x3dpd.design.ringdown import check_design_rings
from x3dpd.design.sweep import configurations, label_branches, sort_rows, write_csv
from x3dpd.errors import InputError
from x3dpd.units import labels_for


# Over 80 lines: a design's one flow: configurations, resume, cluster, rows and figures.
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
    check_design_rings(design, made)
    check_scheduler(scheduler)
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
            configurations(c.spec)  # a bad baseline or drive point: before writing
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
    if ev.auto is not None:
        progress = _run_auto_design(configs, made, ev, workers, scheduler, echo, design)
    else:
        progress = _run_fixed_design(configs, made, ev, workers, scheduler, echo, design, out)
    for c in configs:
        if c.spec is not None:
            c.rows = sort_rows(pooled(c.rows, ev.criterion.tol))
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
    units = labels_for(deck.unit_system)
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
        for k, drive in enumerate(design.evaluation.drives, 1):
            # the configurations driven at this level ([levels]: one drive each)
            mine = [c for c in configs if drive in c.spec.drives]
            curves = baseline_curves(mine[0].spec)
            series = {
                c.made.config.name: [
                    r for r in c.rows if r["config"] == "deck" and r["drive"] == drive
                ]
                for c in mine
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
        auto=ev.auto,
        frequencies=ev.frequencies,
        # a [levels] configuration is its drive level's (x3dpd.design.levels)
        drives=(made.values["level"],) if "level" in made.values else ev.drives,
        node=node,
        dof=dof,
        direction=ev.direction,
        baselines=ev.baselines,
        criterion=ev.criterion,
    )


def _write_settings(out: Path, design: DesignFile) -> None:
    out.mkdir(parents=True, exist_ok=True)
    (out / "design.toml").write_text(design.text)
