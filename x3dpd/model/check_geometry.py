"""Geometry finders of the pre-run check: particles penetrating or outside their cavity's walls,
overlapping particles, wall planes through the particle cloud, and whether a cavity closes.

Each is reusable on its own; the solver uses :func:`particle_wall_penetrations` to refuse a
start with deep penetrations. :mod:`x3dpd.model.check` turns their findings into a report.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from x3dpd.geometry.cavity import cavity_extents, geometry_size, merge_vertices, surface_edges
from x3dpd.geometry.pairs import overlapping_pairs
from x3dpd.geometry.triangle import unit_normals
from x3dpd.geometry.walls import sphere_triangle_pairs
from x3dpd.model.model import Model

#: Relative tolerance for "touching" (distance equal to a radius sum or a radius).
REL_TOL = 1e-9


class WallPenetration(NamedTuple):
    """A particle whose sphere crosses a wall it lies over (centre on the inner side)."""

    particle: int  # 0-based particle number (node index - particle_start)
    node_id: int
    triangle: int  # 0-based, in CONTACT order
    depth: float  # R - d [length]


class OutsideParticle(NamedTuple):
    """A particle whose centre starts outside the cavity it belongs to."""

    particle: int
    node_id: int
    triangle: int  # 0-based triangle it lies behind, -1 when only outside the bounding box
    distance: float  # how far behind the wall (or outside the box) [length]


def _walls(model: Model):
    p = [model.x0[model.tri_nodes[:, k]] for k in range(3)]
    n_in = model.tri_sign[:, None] * unit_normals(*p)
    return p, n_in, model.face_cavity[model.tri_face]


def _over_walls(model: Model, edge_tol: np.ndarray):
    (p0, p1, p2), n_in, tri_cav = _walls(model)
    return sphere_triangle_pairs(
        model.x0[model.particle_start :], model.particle_cavity, p0, p1, p2, n_in, tri_cav, edge_tol
    )


def _deepest_per_face(model: Model, s, t, value, keep) -> list[tuple[int, int, float]]:
    """Largest ``value`` per (particle, face) among the kept pairs, sorted by particle.

    Returns (particle, triangle, value) with the first triangle in CONTACT order on ties.
    """
    s, t, value = s[keep], t[keep], value[keep]
    face = model.tri_face[t]
    order = np.lexsort((t, -value, face, s))
    s, t, value, face = s[order], t[order], value[order], face[order]
    first = np.ones(s.shape[0], dtype=bool)
    first[1:] = (s[1:] != s[:-1]) | (face[1:] != face[:-1])
    return list(zip(s[first].tolist(), t[first].tolist(), value[first].tolist()))


def particle_wall_penetrations(
    model: Model, min_depth_fraction: float = 0.0
) -> list[WallPenetration]:
    r"""Particles that start penetrating a wall of their cavity.

    Penetration of particle :math:`i` into triangle :math:`t`: its centre is on the inner side
    and closer than :math:`R` to the plane, :math:`0 \le d < R`, and its projection lies in the
    triangle grown by :math:`R` (an edge contact counts). Depth :math:`R - d`. One entry per
    particle and face (the deepest triangle of the face); only depths above
    ``min_depth_fraction * R`` (and above touching, :data:`REL_TOL`) are returned.
    """
    r = model.radius
    s, t, d = _over_walls(model, r)
    depth = r[s] - d
    keep = (d >= -REL_TOL * r[s]) & (depth > np.maximum(REL_TOL, min_depth_fraction) * r[s])
    return [
        WallPenetration(i, int(model.node_ids[model.particle_start + i]), k, v)
        for i, k, v in _deepest_per_face(model, s, t, depth, keep)
    ]


def particles_outside(model: Model) -> list[OutsideParticle]:
    r"""Particles whose centre starts outside the cavity they bound.

    Outside: behind some wall, :math:`d < 0` with the projection inside the wall's triangle, or
    -- for a closed cavity -- outside the bounding box of its triangle nodes. An open cavity (a
    floor, an open-top box) has no inside beyond its walls' inner half-spaces, so only the first
    test applies to it. One entry per particle (the farthest behind). Exact for convex cavities.
    """
    p0 = model.particle_start
    s, t, d = _over_walls(model, REL_TOL * model.radius)
    keep = d < -REL_TOL * model.radius[s]
    worst: dict[int, tuple[float, int]] = {}
    for i, k, v in _deepest_per_face(model, s, t, -d, keep):
        if i not in worst or v > worst[i][0]:
            worst[i] = (v, k)
    for c in range(model.cavity_set_ids.shape[0]):
        if not np.any(model.face_cavity[model.tri_face] == c) or not _closed(model, c)[0]:
            continue  # (an analytic wall's own test: x3dpd.model.check_shapes)
        lo, hi = cavity_extents(
            model.x0[model.tri_nodes[model.face_cavity[model.tri_face] == c].reshape(-1)]
        )
        tol = REL_TOL * geometry_size(np.stack([lo, hi]))
        mine = np.flatnonzero(model.particle_cavity == c)
        x = model.x0[p0 + mine]
        gap = np.max(np.maximum(lo - x, x - hi), axis=1)
        for i, g in zip(mine[gap > tol].tolist(), gap[gap > tol].tolist()):
            worst.setdefault(i, (g, -1))
    return [
        OutsideParticle(i, int(model.node_ids[p0 + i]), k, v) for i, (v, k) in sorted(worst.items())
    ]


def particle_overlaps(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Overlapping particle pairs as ``(node id pairs (M, 2), overlap depths (M,))``."""
    pairs, depth = overlapping_pairs(model.x0[model.particle_start :], model.radius, REL_TOL)
    return model.node_ids[model.particle_start :][pairs].reshape(-1, 2), depth


def faces_in_particle_cloud(model: Model) -> list[int]:
    r"""Faces whose plane cuts through their cavity's particles.

    A face is inside the particle cloud when, among the particles of its cavity whose centres
    lie over it (projection within :math:`R` of its triangles), some centres are on or behind
    its plane (:math:`d \le 0`) and some in front (:math:`d > 0`). A cavity wall should have
    every particle on its inner side.
    """
    s, t, d = _over_walls(model, model.radius)
    tol = REL_TOL * model.radius[s]
    face = model.tri_face[t]
    return [
        int(f)
        for f in np.unique(face)
        if np.any(d[face == f] <= tol[face == f]) and np.any(d[face == f] > tol[face == f])
    ]


def _closed(model: Model, c: int) -> tuple[bool, bool]:
    """(closed, consistently oriented) for the surface of cavity ``c``'s triangles."""
    mine = np.flatnonzero(model.face_cavity[model.tri_face] == c)
    pts = model.x0[model.tri_nodes[mine]].reshape(-1, 3)
    labels = merge_vertices(pts, geometry_size(pts)).reshape(-1, 3)
    return surface_edges(labels, model.tri_sign[mine])
