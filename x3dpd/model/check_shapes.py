"""Pre-run checks of the analytic walls (CYLINDER, CAPSULE ... cards; x3dpd.geometry.shapes):
which particles start outside their shape or overlapping its wall, each one's clearance, and
each shape's size and volume for the summary of ``x3dpd check``."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from x3dpd.geometry.shapes import analytic_wall
from x3dpd.model.model import Model


class ShapeClearance(NamedTuple):
    """One particle of an analytic wall's cavity at t0: its gap to the nearest wall part
    (negative: overlap) and whether its centre is inside."""

    particle: int  # 0-based particle number
    node_id: int
    shape: int  # 0-based analytic wall, in file order
    gap: float  # [length]
    inside: bool


def _wall(model: Model, w: int):
    """(shape, node positions at t0, lengths) of analytic wall ``w``."""
    return analytic_wall(model.shape_kind[w], model.shape_nodes[w], model.shape_params[w], model.x0)


def shape_clearances(model: Model) -> list[ShapeClearance]:
    """Every (particle, analytic wall of its cavity) pair at the deck's coordinates."""
    out = []
    p0 = model.particle_start
    for w in range(model.shape_kind.shape[0]):
        mine = np.flatnonzero(model.particle_cavity == model.shape_cavity[w])
        if mine.size == 0:
            continue
        shape, ends, lengths = _wall(model, w)
        gap, inside = shape.clearance(model.x0[p0 + mine], model.radius[mine], ends, lengths)
        out += [
            ShapeClearance(int(i), int(model.node_ids[p0 + i]), w, float(g), bool(ok))
            for i, g, ok in zip(mine, gap, inside)
        ]
    return out


def describe_shape(model: Model, w: int) -> str:
    """'the cylinder on axis nodes 2, 3 (radius 0.2, length 0.263)'."""
    shape, ends, lengths = _wall(model, w)
    ids = ", ".join(
        str(int(model.node_ids[i])) for i in model.shape_nodes[w][: len(shape.node_fields)]
    )
    return f"the {shape.name} on {shape.nodes_word} {ids} ({shape.describe(ends, lengths)})"


def shape_volume(model: Model, w: int) -> float:
    """The volume inside analytic wall ``w`` [length^3]; a shape of cells (a drilled plate's
    holes) counts each cell its particles are in."""
    shape, ends, lengths = _wall(model, w)
    return float(shape.volume(ends, lengths)) * _cells(model, w, shape, ends, lengths)


def _cells(model: Model, w: int, shape, ends, lengths) -> int:
    """How many cells the particles of wall ``w`` occupy (1 for a shape without cells)."""
    mine = np.flatnonzero(model.particle_cavity == model.shape_cavity[w])
    if shape.cells is None or not mine.size:
        return 1
    cells = shape.cells(model.x0[model.particle_start + mine], ends, lengths)
    return int(np.unique(cells, axis=0).shape[0])


def summary_extent(model: Model, w: int) -> tuple[np.ndarray, np.ndarray]:
    """Bounding box (lo, hi) of analytic wall ``w`` at t0 for a summary: a shape of cells
    (a drilled plate) with every hole its particles are in (the box of its first hole moved
    across the axis A -> B to each particle, which sits on its hole's axis or near it)."""
    shape, ends, lengths = _wall(model, w)
    lo, hi = shape.extent(ends, lengths)
    mine = np.flatnonzero(model.particle_cavity == model.shape_cavity[w])
    if shape.cells is not None and mine.size:
        u = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
        d = model.x0[model.particle_start + mine] - ends[0]
        d -= (d @ u)[:, None] * u
        lo = np.minimum(lo, lo + d.min(axis=0))
        hi = np.maximum(hi, hi + d.max(axis=0))
    return lo, hi


def shape_extent(model: Model, w: int) -> tuple[np.ndarray, np.ndarray]:
    """Bounding box (lo, hi) of analytic wall ``w`` at t0."""
    shape, ends, lengths = _wall(model, w)
    return shape.extent(ends, lengths)


def shape_warnings(model: Model, rel_tol: float) -> list[tuple[str, str, list[str]]]:
    """(code, headline, detail lines) of particles that start outside their analytic wall or
    in it (deeper than ``rel_tol`` of their radius)."""
    found = shape_clearances(model)
    out = []
    outside = [f for f in found if not f.inside]
    names = " or ".join(sorted({_wall(model, f.shape)[0].name for f in found})) or "shape"
    if outside:
        out.append(
            (
                "particles-outside",
                f"{len(outside)} of the {model.n_particles} particles start outside the "
                f"{names} they belong to, so its walls would push them from the wrong side",
                [
                    f"particle node {f.node_id}: centre outside {describe_shape(model, f.shape)}"
                    for f in outside
                ],
            )
        )
    r = model.radius
    deep = sorted(
        (f for f in found if f.inside and f.gap < -rel_tol * r[f.particle]), key=lambda f: f.gap
    )
    if deep:
        worst = deep[0]
        out.append(
            (
                "wall-penetration",
                f"{len(deep)} particles start penetrating a {names} wall (deepest: particle "
                f"node {worst.node_id}, {-worst.gap:.6g} = {-worst.gap / r[worst.particle]:.3g}"
                f" R into {describe_shape(model, worst.shape)})",
                [
                    f"particle node {f.node_id}: {-f.gap:.6g} ({-f.gap / r[f.particle]:.3g} R) "
                    f"into {describe_shape(model, f.shape)}"
                    for f in deep
                ],
            )
        )
    return out


def smallest_clearance(
    model: Model, w: int, found: list[ShapeClearance] | None = None
) -> float | None:
    """The smallest gap of any particle to analytic wall ``w`` at t0 (None: no particles);
    ``found``: :func:`shape_clearances`, when the caller has them already."""
    gaps = [f.gap for f in (shape_clearances(model) if found is None else found) if f.shape == w]
    return min(gaps) if gaps else None
