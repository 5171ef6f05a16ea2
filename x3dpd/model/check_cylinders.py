"""Pre-run checks of the analytic cylindrical cavities (CYLINDER card, x3dpd.geometry.cylinder):
which particles start outside their cylinder or overlapping its wall, each one's clearance,
and the cylinder's size and volume for the summary of ``x3dpd check``."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from x3dpd.geometry.cylinder import cylinder_clearance
from x3dpd.model.model import Model


class CylinderClearance(NamedTuple):
    """One particle of a cylinder's cavity at t0: its gap to the nearest wall part (negative:
    overlap) and whether its centre is inside."""

    particle: int   # 0-based particle number
    node_id: int
    cylinder: int   # 0-based, in CYLINDER order
    gap: float      # [length]
    inside: bool


def cylinder_clearances(model: Model) -> list[CylinderClearance]:
    """Every (particle, cylinder of its cavity) pair at the deck's coordinates."""
    out = []
    p0 = model.particle_start
    for c in range(model.cylinder_radius.shape[0]):
        mine = np.flatnonzero(model.particle_cavity == model.cylinder_cavity[c])
        if mine.size == 0:
            continue
        a, b = model.x0[model.cylinder_nodes[c]]
        gap, inside = cylinder_clearance(model.x0[p0 + mine], model.radius[mine], a, b,
                                         float(model.cylinder_radius[c]))
        out += [CylinderClearance(int(i), int(model.node_ids[p0 + i]), c, float(g), bool(ok))
                for i, g, ok in zip(mine, gap, inside)]
    return out


def describe_cylinder(model: Model, c: int) -> str:
    """'the cylinder on axis nodes 2, 3 (radius 0.2, length 0.263)'."""
    ids = ", ".join(str(int(model.node_ids[i])) for i in model.cylinder_nodes[c])
    return (f"the cylinder on axis nodes {ids} (radius {model.cylinder_radius[c]:g}, length "
            f"{cylinder_length(model, c):.6g})")


def cylinder_length(model: Model, c: int) -> float:
    a, b = model.x0[model.cylinder_nodes[c]]
    return float(np.linalg.norm(b - a))


def cylinder_volume(model: Model, c: int) -> float:
    """pi R^2 L [length^3]."""
    return math.pi * float(model.cylinder_radius[c]) ** 2 * cylinder_length(model, c)


def cylinder_extent(model: Model, c: int) -> tuple[np.ndarray, np.ndarray]:
    """Bounding box of the cylinder: its two end discs (a disc of radius R normal to the unit
    axis u reaches R sqrt(1 - u_k^2) along axis k)."""
    a, b = model.x0[model.cylinder_nodes[c]]
    u = (b - a) / np.linalg.norm(b - a)
    reach = float(model.cylinder_radius[c]) * np.sqrt(np.maximum(1.0 - u * u, 0.0))
    return np.minimum(a, b) - reach, np.maximum(a, b) + reach


def cylinder_warnings(model: Model, rel_tol: float) -> list[tuple[str, str, list[str]]]:
    """(code, headline, detail lines) of particles that start outside their cylinder or in
    its wall (deeper than ``rel_tol`` of their radius)."""
    found = cylinder_clearances(model)
    out = []
    outside = [f for f in found if not f.inside]
    if outside:
        out.append(("particles-outside",
                    f"{len(outside)} of the {model.n_particles} particles start outside the "
                    f"cylinder they belong to, so its walls would push them from the wrong side",
                    [f"particle node {f.node_id}: centre outside "
                     f"{describe_cylinder(model, f.cylinder)}" for f in outside]))
    r = model.radius
    deep = sorted((f for f in found if f.inside and f.gap < -rel_tol * r[f.particle]),
                  key=lambda f: f.gap)
    if deep:
        worst = deep[0]
        out.append(("wall-penetration",
                    f"{len(deep)} particles start penetrating a cylinder wall (deepest: particle "
                    f"node {worst.node_id}, {-worst.gap:.6g} = {-worst.gap / r[worst.particle]:.3g}"
                    f" R into {describe_cylinder(model, worst.cylinder)})",
                    [f"particle node {f.node_id}: {-f.gap:.6g} ({-f.gap / r[f.particle]:.3g} R) "
                     f"into {describe_cylinder(model, f.cylinder)}" for f in deep]))
    return out


def smallest_clearance(model: Model, c: int) -> float | None:
    """The smallest gap of any particle to cylinder ``c``'s wall at t0 (None: no particles)."""
    gaps = [f.gap for f in cylinder_clearances(model) if f.cylinder == c]
    return min(gaps) if gaps else None
