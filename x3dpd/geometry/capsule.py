"""Analytic capsule cavity: a cylinder with hemispherical ends -- a bore with rounded ends (a
ball-end mill's), or a spherical cavity. The report's test capsules (Sections 5-6) are
flat-capped cylinders (x3dpd.geometry.cylinder); this shape shows what rounded ends change.

A capsule is every point within R of the segment from node A to node B: the cap centres A
and B, the inner radius R [length] (CAPSULE card: SET NODE_A NODE_B RADIUS). Its wall is one
smooth surface, so one contact entity serves it. With the particle centre p, the segment
u = B - A, the segment's point nearest p

    q = A + t u,   t = clamp((p - A) . u / |u|^2, 0, 1),

and d = p - q, a sphere of radius r overlaps the wall by a = r + |d| - R; the normal from the
wall into the particle is n = -d/|d|, the wall point c = q + R d/|d|. The reaction goes to A and
B with the weights (1 - t, t), and the lever from q to the wall point, l = R d/|d|, carries the
moment l x F to node A (x3dpd.geometry.shapes). Coinciding A and B make a spherical cavity
(t = 0).

The contact is exact for a sphere inside a capsule: the nearest wall point of a sphere's
centre is where the sphere first touches, because the wall is a surface of constant distance
R from the segment.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd._jit import step_kernel
from x3dpd.geometry.shape import Shape

__all__ = ["SHAPE", "capsule_clearance", "capsule_mesh", "capsule_outline", "clear_of",
           "locate_parts"]


@step_kernel
def locate_parts(x, na, nb, params, c, px, py, pz, r, out):
    """The wall's row (valid, a, n, xi, l) for a sphere at p of radius r in capsule ``c``
    (radius ``params[c, 0]``) with cap centres ``na``, ``nb`` (x3dpd.geometry.shapes)."""
    t, dx, dy, dz, dist = _from_segment(x, na, nb, px, py, pz)
    if dist <= 0.0:   # the centre on the segment: no direction to the wall
        out[0, 0] = 0.0
        return
    big_r = params[c, 0]
    inv = 1.0 / dist
    ex = dx * inv
    ey = dy * inv
    ez = dz * inv
    out[0, 0] = 1.0
    out[0, 1] = r + dist - big_r
    out[0, 2] = -ex
    out[0, 3] = -ey
    out[0, 4] = -ez
    out[0, 5] = t
    out[0, 6] = big_r * ex
    out[0, 7] = big_r * ey
    out[0, 8] = big_r * ez


@step_kernel
def clear_of(x, na, nb, params, c, px, py, pz, r):
    """True when capsule ``c``'s wall does not touch the sphere: its overlap r + |d| - R,
    computed as :func:`locate_parts` does (the same bits), is <= 0 (x3dpd.geometry.shapes)."""
    return r + _from_segment(x, na, nb, px, py, pz)[4] - params[c, 0] <= 0.0


@step_kernel
def _from_segment(x, na, nb, px, py, pz):
    """(t, d, |d|) of the point p: the segment's nearest point A + t (B - A) and d = p - q
    from it (module docstring), as scalars (t, dx, dy, dz, dist)."""
    ax = x[na, 0]
    ay = x[na, 1]
    az = x[na, 2]
    ux = x[nb, 0] - ax
    uy = x[nb, 1] - ay
    uz = x[nb, 2] - az
    dx = px - ax
    dy = py - ay
    dz = pz - az
    uu = ux * ux + uy * uy + uz * uz
    t = 0.0
    if uu > 0.0:
        t = min(max((dx * ux + dy * uy + dz * uz) / uu, 0.0), 1.0)
    dx -= t * ux
    dy -= t * uy
    dz -= t * uz
    return t, dx, dy, dz, math.sqrt(dx * dx + dy * dy + dz * dz)


def _segment_distance(points, a, b) -> np.ndarray:
    """Distance of each point (N, 3) to the segment from a to b."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    a = np.asarray(a, dtype=np.float64)
    u = np.asarray(b, dtype=np.float64) - a
    uu = float(u @ u)
    d = points - a
    t = np.clip(d @ u / uu, 0.0, 1.0) if uu > 0.0 else np.zeros(points.shape[0])
    return np.linalg.norm(d - t[:, None] * u[None, :], axis=1)


def capsule_clearance(points, radii, a, b, big_r: float) -> tuple[np.ndarray, np.ndarray]:
    """Gap of each sphere to the capsule's wall [length] (negative: overlap), R - |d| - r, and
    whether its centre is inside (|d| <= R)."""
    dist = _segment_distance(points, a, b)
    return big_r - dist - np.asarray(radii, dtype=np.float64), dist <= big_r


def capsule_mesh(a, b, big_r: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A closed triangulated capsule with ``n`` facets around: the profile runs from the pole
    beyond A over m = max(2, n // 4) latitude rings of each hemisphere (one shared equator
    when A = B) to the pole beyond B, every vertex on the analytic wall, so the facets lie
    inside it by at most R (1 - cos(pi/n) cos(pi/(4 m))). Returns (vertices, triangles)."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    axis = b - a
    length = float(np.linalg.norm(axis))
    u = axis / length if length > 0.0 else np.array([1.0, 0.0, 0.0])
    helper = np.eye(3)[int(np.argmin(np.abs(u)))]
    e1 = np.cross(u, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    m = max(2, n // 4)
    theta = 0.5 * np.pi * np.arange(1, m + 1) / m          # from the pole to the equator
    # ring profile (axial position from A, ring radius): hemisphere at A, then at B
    zs = np.concatenate([-big_r * np.cos(theta), length + big_r * np.cos(theta[::-1])])
    rs = np.concatenate([big_r * np.sin(theta), big_r * np.sin(theta[::-1])])
    if length == 0.0:   # a sphere: its two equator rings are one
        zs, rs = np.delete(zs, m), np.delete(rs, m)
    phi = 2.0 * np.pi * np.arange(n) / n
    circle = np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2
    rings = [a + z * u + rad * circle for z, rad in zip(zs, rs)]
    poles = np.stack([a - big_r * u, a + (length + big_r) * u])
    verts = np.concatenate(rings + [poles])
    k = np.arange(n)
    nxt = (k + 1) % n
    tris = []
    for j in range(len(rings) - 1):
        lo, hi = j * n, (j + 1) * n
        tris += [np.stack([lo + k, lo + nxt, hi + k], axis=1),
                 np.stack([lo + nxt, hi + nxt, hi + k], axis=1)]
    pa, pb = len(rings) * n, len(rings) * n + 1
    last = (len(rings) - 1) * n
    tris += [np.stack([np.full(n, pa), nxt, k], axis=1),
             np.stack([np.full(n, pb), last + k, last + nxt], axis=1)]
    return verts, np.concatenate(tris).astype(np.int64)


def capsule_outline(ends, params, n: int) -> np.ndarray:
    """Edges (E, 2) of :func:`capsule_mesh`'s vertices along the circles where the hemispheres
    meet the bore (its rings m - 1 and m; one circle, the equator, for a sphere)."""
    m = max(2, n // 4)
    rings = (m - 1,) if _length(ends) == 0.0 else (m - 1, m)
    k = np.arange(n)
    return np.concatenate([np.stack([j * n + k, j * n + (k + 1) % n], axis=1)
                           for j in rings]).astype(np.int64)


def _length(ends) -> float:
    return float(np.linalg.norm(np.asarray(ends[1], float) - np.asarray(ends[0], float)))


def _extent(ends, params) -> tuple[np.ndarray, np.ndarray]:
    """Bounding box: that of the end spheres."""
    a, b = np.asarray(ends[0], float), np.asarray(ends[1], float)
    big_r = float(params[0])
    return np.minimum(a, b) - big_r, np.maximum(a, b) + big_r


SHAPE = Shape(
    name="capsule", card="CAPSULE", node_fields=("NODE_A", "NODE_B"), param_fields=("RADIUS",),
    part_names=("wall",), locate_parts=locate_parts,
    clearance=lambda points, radii, ends, params: capsule_clearance(
        points, radii, ends[0], ends[1], float(params[0])),
    volume=lambda ends, params: (math.pi * float(params[0]) ** 2 * _length(ends)
                                 + 4.0 / 3.0 * math.pi * float(params[0]) ** 3),
    extent=_extent,
    mesh=lambda ends, params, n: capsule_mesh(ends[0], ends[1], float(params[0]), n),
    describe=lambda ends, params: (f"radius {float(params[0]):g}, {_length(ends):.6g} between "
                                   f"the cap centres"),
    problem=lambda ends, params: None,
    outline=capsule_outline, clear_of=clear_of,
    doc="a cylinder with hemispherical ends (a bore with rounded ends; a spherical cavity)")
