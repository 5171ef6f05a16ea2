"""``x3dpd design SPEC --plan``: what a design would compute, before it computes anything.

A design can cost CPU-hours (the report's beam study, docs/design.md). Its plan reads the
design file, makes and checks every configuration's deck exactly as a run does (every error a
run would meet first is met here), writes nothing, and says per configuration what it would
run: the particles, the step, the points -- a sweep's frequencies x drives x chains (x2 for
``direction = "both"``) x replicas, at most ``POINTS`` per drive and chain for
``frequencies = "auto:..."``; a ring-down's drives -- and the most steps they can take:

* a sweep point runs at most ``max_cycles`` drive cycles of 1 / (f dt) steps each, so a
  configuration takes at most :math:`\\sum_{points} N_{cap}\\,R / (f\\,\\Delta t)` steps (R
  replicas; an auto search's points at its band's low end, the longest cycles);
* a ring-down runs ``drive_until + ring`` seconds per drive: (t_d + t_r) / dt steps.

Most points stop well before their cap; the bound is what the design can cost, not what it will.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from x3dpd.design.configs import make_configurations, require_drive
from x3dpd.design.design_file import read_design
from x3dpd.design.ringdown import check_design_rings


@dataclass(frozen=True)
class PlannedConfiguration:
    """One configuration of a plan: its ``name``, the ``values`` it resolved to (count,
    radius, dt, added mass ...: x3dpd.design.configs), its ``points`` (sweep points or
    ring-downs) and the most steps they can take (``max_steps``)."""

    name: str
    values: dict
    points: int
    max_steps: float


def plan_design(path) -> tuple[object, list[PlannedConfiguration]]:
    """The design file at ``path`` and what each of its configurations would run (module
    docstring); nothing is written."""
    design = read_design(path)
    made = make_configurations(design)  # the run's own checks, in the run's order
    require_drive(design, made)
    check_design_rings(design, made)
    ev = design.evaluation
    out = []
    for m in made:
        dt = float(m.deck.parameters.dtmax)
        drives = (m.values["level"],) if "level" in m.values else ev.drives
        if ev.kind == "ringdown":
            points = len(drives)
            steps = points * (ev.drive_until + ev.ring) / dt
        else:
            chains = 2 if ev.direction == "both" else 1
            per = ev.criterion.max_cycles * ev.criterion.replicas / dt
            if ev.auto is not None:
                points = ev.auto.max_points * len(drives) * chains
                steps = points * per / ev.auto.lo
            else:
                points = len(ev.frequencies) * len(drives) * chains
                steps = len(drives) * chains * sum(per / f for f in ev.frequencies)
            points *= ev.criterion.replicas
        out.append(PlannedConfiguration(m.config.name, dict(m.values), points, steps))
    return design, out


def format_plan(design, planned: list[PlannedConfiguration]) -> list[str]:
    """The plan as lines: one per configuration, then the total."""
    ev = design.evaluation
    what = (
        f"ring-downs: {ev.drive_until:g} s driven, {ev.ring:g} s ringing"
        if ev.kind == "ringdown"
        else (
            f"sweep points: at most {ev.criterion.max_cycles} cycles each"
            + (f", {ev.criterion.replicas} replicas" if ev.criterion.replicas > 1 else "")
        )
    )
    lines = [
        f"plan of {design.path}: {design.title}",
        f"{len(planned)} configurations, {ev.kind}; {what}; nothing written",
        f"  {'configuration':<24}{'particles':>10}{'radius':>12}{'dt [s]':>11}"
        f"{'points':>8}{'steps at most':>16}",
    ]
    for p in planned:
        v = p.values
        lines.append(
            f"  {p.name:<24}{int(v.get('count', 0)):>10}{_g(v.get('radius')):>12}"
            f"{_g(v.get('dt')):>11}{p.points:>8}{p.max_steps:>16.3g}"
        )
    total = sum(p.max_steps for p in planned)
    lines.append(
        f"  {'total':<24}{'':>10}{'':>12}{'':>11}{sum(p.points for p in planned):>8}{total:>16.3g}"
    )
    lines.append(
        "most points stop well before their cap: the steps are what the design can cost; "
        "the time per step of each configuration's scene is in `x3dpd study CONFIG_DECK`"
    )
    return lines


def _g(x) -> str:
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.4g}"
