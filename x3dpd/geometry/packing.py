r"""Sphere packings inside a closed cavity given as triangles (``x3dpd fill``; cf. the report's
Appendix D ``create_cavity.m``, which "does not calculate packing correctly").

A centre is admissible when it lies inside the closed surface (ray-parity test,
:func:`points_inside`) and at least ``R + gap`` from every triangle (:func:`triangle_distances`,
exact point-triangle distance): the sphere then fits with ``gap`` to spare. Packings:

* ``cubic`` -- simple cubic lattice, pitch :math:`2R + g` (packing fraction
  :math:`\pi/6 \approx 0.524` in an unbounded lattice);
* ``hcp`` -- hexagonal close packed: triangular layers (rows :math:`\sqrt3/2\,p` apart, every
  other row shifted by :math:`p/2`), layers :math:`\sqrt{2/3}\,p` apart stacked ABAB (B shifted by
  :math:`(p/2, \sqrt3 p/6)`), fraction :math:`\pi/\sqrt{18} \approx 0.740` at :math:`g = 0`;
* ``random`` -- random sequential addition (random loose packing): uniform candidates, each kept
  if admissible and ``2R + gap`` from every kept centre, until ``n`` are placed or ``attempts``
  (5000) admissible candidates in a row overlapped.

Lattices are anchored at the lowest admissible layer along the stacking axis (gravity's) and
centred across it; the lowest layers are filled first, like particles settled on the floor.
"""

from __future__ import annotations

import math

import numpy as np

PACKINGS = ("cubic", "hcp", "random")


def triangle_distances(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Smallest distance from each point (N, 3) to the triangles ``tri`` (T, 3, 3) [length].

    Closest point on a triangle by its Voronoi regions (Ericson, Real-Time Collision Detection,
    5.1.5), vectorised over points x triangles in chunks.
    """
    points = np.asarray(points, float).reshape(-1, 3)
    out = np.full(points.shape[0], np.inf)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    ab, ac = b - a, c - a
    chunk = max(1, 2_000_000 // max(1, tri.shape[0]))
    for s in range(0, points.shape[0], chunk):
        p = points[s:s + chunk, None, :]
        ap = p - a
        d1 = np.einsum("ntk,tk->nt", ap, ab)
        d2 = np.einsum("ntk,tk->nt", ap, ac)
        bp = p - b
        d3 = np.einsum("ntk,tk->nt", bp, ab)
        d4 = np.einsum("ntk,tk->nt", bp, ac)
        cp = p - c
        d5 = np.einsum("ntk,tk->nt", cp, ab)
        d6 = np.einsum("ntk,tk->nt", cp, ac)
        va = d3 * d6 - d5 * d4
        vb = d5 * d2 - d1 * d6
        vc = d1 * d4 - d3 * d2
        denom = va + vb + vc
        with np.errstate(divide="ignore", invalid="ignore"):
            v = np.where(denom != 0, vb / denom, 0.0)
            w = np.where(denom != 0, vc / denom, 0.0)
            # edge regions (parameter clipped to [0, 1]) and vertices
            t_ab = np.clip(d1 / np.where(d1 - d3 != 0, d1 - d3, 1.0), 0.0, 1.0)
            t_ac = np.clip(d2 / np.where(d2 - d6 != 0, d2 - d6, 1.0), 0.0, 1.0)
            t_bc = np.clip((d4 - d3) / np.where((d4 - d3) + (d5 - d6) != 0,
                                                (d4 - d3) + (d5 - d6), 1.0), 0.0, 1.0)
        inside = (va >= 0) & (vb >= 0) & (vc >= 0) & (denom > 0)
        q_face = a + v[..., None] * ab + w[..., None] * ac
        q_ab = a + t_ab[..., None] * ab
        q_ac = a + t_ac[..., None] * ac
        q_bc = b + t_bc[..., None] * (c - b)
        dist = np.minimum(np.minimum(np.linalg.norm(p - q_ab, axis=-1),
                                     np.linalg.norm(p - q_ac, axis=-1)),
                          np.linalg.norm(p - q_bc, axis=-1))
        dist = np.where(inside, np.linalg.norm(p - q_face, axis=-1), dist)
        out[s:s + chunk] = dist.min(axis=1)
    return out


def points_inside(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """True for points inside the closed triangulated surface ``tri`` (T, 3, 3): an odd number of
    crossings of a ray in a fixed skew direction (Moeller-Trumbore), whatever the winding."""
    points = np.asarray(points, float).reshape(-1, 3)
    direction = np.array([0.5773502691896257, 0.5773502691896258, 0.5773502691896259])
    direction = direction + np.array([1e-3, 2.3e-3, -1.7e-3])
    direction /= np.linalg.norm(direction)
    a, e1, e2 = tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    h = np.cross(direction, e2)
    det = np.einsum("tk,tk->t", e1, h)
    ok = np.abs(det) > 1e-300
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    count = np.zeros(points.shape[0], dtype=np.int64)
    chunk = max(1, 2_000_000 // max(1, tri.shape[0]))
    for s in range(0, points.shape[0], chunk):
        sv = points[s:s + chunk, None, :] - a
        u = np.einsum("ntk,tk->nt", sv, h) * inv
        q = np.cross(sv, e1)
        v = np.einsum("ntk,k->nt", q, direction) * inv
        t = np.einsum("ntk,tk->nt", q, e2) * inv
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        count[s:s + chunk] = hit.sum(axis=1)
    return count % 2 == 1


def lattice(lo, hi, pitch: float, packing: str, stack_axis: int = 1) -> np.ndarray:
    """Lattice points covering the box ``lo..hi`` (inclusive), layers along ``stack_axis``."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    u, w = [a for a in (0, 2, 1) if a != stack_axis]
    if packing == "cubic":
        axes = [np.arange(lo[k], hi[k] + 1e-9 * pitch, pitch) for k in range(3)]
        g = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        return g
    if packing != "hcp":
        raise ValueError(f"packing {packing!r}: expected cubic or hcp")
    row = pitch * math.sqrt(3.0) / 2.0
    layer = pitch * math.sqrt(2.0 / 3.0)
    pts = []
    n_layers = int(math.floor((hi[stack_axis] - lo[stack_axis]) / layer + 1e-9)) + 1
    for k in range(n_layers):
        off_u, off_w = (0.0, 0.0) if k % 2 == 0 else (pitch / 2.0, row / 3.0)
        n_rows = int(math.floor((hi[w] - lo[w] + pitch) / row)) + 2
        for j in range(n_rows):
            shift = off_u + (pitch / 2.0 if j % 2 else 0.0)
            us = np.arange(lo[u] - pitch + shift, hi[u] + pitch, pitch)
            p = np.zeros((us.shape[0], 3))
            p[:, u] = us
            p[:, w] = lo[w] + off_w + j * row
            p[:, stack_axis] = lo[stack_axis] + k * layer
            pts.append(p)
    g = np.concatenate(pts) if pts else np.zeros((0, 3))
    keep = np.all((g >= lo - 1e-9 * pitch) & (g <= hi + 1e-9 * pitch), axis=1)
    return g[keep]


def _admissible(points, tri, clearance) -> np.ndarray:
    if points.shape[0] == 0:
        return np.zeros(0, bool)
    ok = points_inside(points, tri)
    idx = np.flatnonzero(ok)
    ok[idx] = triangle_distances(points[idx], tri) >= clearance * (1.0 - 1e-12)
    return ok


def _order(points: np.ndarray, stack_axis: int, upward: bool) -> np.ndarray:
    """Lowest layer first (along gravity), then by the other axes (x fastest)."""
    u, w = [a for a in (0, 2, 1) if a != stack_axis]
    h = points[:, stack_axis] if upward else -points[:, stack_axis]
    return points[np.lexsort((points[:, u], points[:, w], np.round(h, 9)))]


def pack(tri: np.ndarray, radius: float, n: int | None = None, *, packing: str = "cubic",
         gap: float = 0.0, stack_axis: int = 1, upward: bool = True, seed: int | None = None,
         attempts: int = 5000) -> np.ndarray:
    """Centres of up to ``n`` spheres of ``radius`` in the cavity ``tri`` (T, 3, 3) [length].

    ``n=None`` places as many as fit. Lattices try several offsets of the lattice across the
    stacking axis and keep the one that holds the most; ``upward`` fills from the low end of
    ``stack_axis`` (gravity pointing to -axis). Returns (m, 3) with m <= n, lowest first.
    """
    if packing not in PACKINGS:
        raise ValueError(f"packing {packing!r}: expected one of {', '.join(PACKINGS)}")
    tri = np.asarray(tri, float).reshape(-1, 3, 3)
    clearance = radius + gap
    pts = tri.reshape(-1, 3)
    lo, hi = pts.min(axis=0) + clearance, pts.max(axis=0) - clearance
    if np.any(hi < lo):
        return np.zeros((0, 3))
    if packing == "random":
        return _random(tri, radius, n, gap, lo, hi, stack_axis, upward, seed, attempts)
    pitch = 2.0 * radius + gap
    best = np.zeros((0, 3))
    u, w = [a for a in (0, 2, 1) if a != stack_axis]
    for fu in (0.0, 0.25, 0.5, 0.75):
        for fw in (0.0, 0.25, 0.5, 0.75):
            start = lo.copy()
            start[u] -= fu * pitch
            start[w] -= fw * pitch
            g = lattice(start, hi + pitch, pitch, packing, stack_axis)
            g = g[np.all((g >= lo - 1e-9 * pitch) & (g <= hi + 1e-9 * pitch), axis=1)]
            if not upward:
                g[:, stack_axis] = lo[stack_axis] + hi[stack_axis] - g[:, stack_axis]
            g = g[_admissible(g, tri, clearance)]
            if g.shape[0] > best.shape[0]:
                best = g
    best = _order(best, stack_axis, upward)
    return best if n is None else best[:n]


def _random(tri, radius, n, gap, lo, hi, stack_axis, upward, seed, attempts) -> np.ndarray:
    rng = np.random.default_rng(seed)
    placed: list[np.ndarray] = []
    min_d2 = (2.0 * radius + gap) ** 2
    fails = 0
    target = n if n is not None else np.inf
    while len(placed) < target and fails < attempts:
        cand = rng.uniform(lo, hi, size=(256, 3))
        cand = cand[_admissible(cand, tri, radius + gap)]
        if cand.shape[0] == 0:
            fails += 256      # nothing admissible in this batch: a cavity too small to hold one
        for c in cand:
            if placed:
                arr = np.asarray(placed)
                if np.min(np.sum((arr - c) ** 2, axis=1)) < min_d2:
                    fails += 1
                    continue
            placed.append(c)
            fails = 0
            if len(placed) >= target:
                break
    out = np.asarray(placed).reshape(-1, 3)
    return _order(out, stack_axis, upward)
