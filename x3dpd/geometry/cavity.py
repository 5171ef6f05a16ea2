"""Cavity geometry built from wall triangles: faces, extents, closedness, enclosed volume.

A *cavity* is the set of triangles of one CONTACT set. A *face* is a group of its triangles that
are coplanar and share one inward normal (e.g. the two triangles of one side of a box).
Pure numpy; see :mod:`x3dpd.geometry.triangle` for the per-triangle formulas.
"""

from __future__ import annotations

import numpy as np

from x3dpd.geometry.triangle import PLANE_TOL, triangle_normals


def cavity_extents(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Axis-aligned bounding box ``(lo, hi)`` of a cavity's triangle nodes, each (3,) [length]."""
    points = np.atleast_2d(np.asarray(points, dtype=np.float64))
    return points.min(axis=0), points.max(axis=0)


def geometry_size(points: np.ndarray) -> float:
    """Largest side of the bounding box of ``points`` (1.0 when they all coincide) [length]."""
    lo, hi = cavity_extents(points)
    size = float(np.max(hi - lo))
    return size if size > 0.0 else 1.0


def group_faces(n_in: np.ndarray, p0: np.ndarray, size: float,
                tol: float = PLANE_TOL) -> np.ndarray:
    r"""Group coplanar triangles with the same inward normal into faces.

    Triangles :math:`i, j` share a face when
    :math:`\max_k |\hat n_{ik} - \hat n_{jk}| \le \mathrm{tol}` and
    :math:`|\hat{\mathbf n}_i\cdot\mathbf p_{0i} - \hat{\mathbf n}_j\cdot\mathbf p_{0j}|
    \le \mathrm{tol}\cdot\mathrm{size}` (same plane offset).

    Parameters
    ----------
    n_in : (T, 3) array, unit inward normals.
    p0 : (T, 3) array [length], one corner of each triangle.
    size : float [length], size of the cavity (scales the offset tolerance).
    tol : float, relative tolerance.

    Returns
    -------
    (T,) int64 array, face number of each triangle, numbered in order of first appearance.
    """
    n_in = np.atleast_2d(np.asarray(n_in, dtype=np.float64))
    offsets = np.einsum("tk,tk->t", n_in, np.atleast_2d(np.asarray(p0, dtype=np.float64)))
    # Each triangle joins the first face (in order of appearance) whose first triangle is within
    # the tolerances. Keys (normal, offset / size) within tol of each other lie in the same or
    # a neighbouring cell of side tol, so only the 3^4 cells around a key can hold a match:
    # O(T) instead of comparing every triangle with every face (a curved cavity of 16,000
    # facets has about as many faces).
    keys = np.column_stack([n_in, offsets / size]) if n_in.shape[0] else np.zeros((0, 4))
    cells = np.floor(keys / tol).astype(np.int64) if tol > 0 else np.zeros((len(keys), 4),
                                                                          np.int64)
    around = np.array(np.meshgrid(*[[-1, 0, 1]] * 4, indexing="ij")).reshape(4, -1).T
    face = np.full(n_in.shape[0], -1, dtype=np.int64)
    reps: list[int] = []
    by_cell: dict[tuple, list[int]] = {}
    for t in range(n_in.shape[0]):
        best = -1
        for cell in map(tuple, cells[t] + around):
            for f in by_cell.get(cell, ()):
                r = reps[f]
                if ((best < 0 or f < best) and np.max(np.abs(n_in[t] - n_in[r])) <= tol
                        and abs(offsets[t] - offsets[r]) <= tol * size):
                    best = f
        if best < 0:
            best = len(reps)
            reps.append(t)
            by_cell.setdefault(tuple(cells[t]), []).append(best)
        face[t] = best
    return face


def merge_vertices(points: np.ndarray, size: float, tol: float = PLANE_TOL) -> np.ndarray:
    """Labels that identify coincident points (within ``tol * size``), for edge matching.

    Distinct node ids at one position (the cube deck puts nodes 8 and 9 at one corner) get
    one label.

    Returns
    -------
    (N,) int64 array of labels.
    """
    q = np.round(np.asarray(points, dtype=np.float64) / (tol * size)).astype(np.int64)
    _, labels = np.unique(q, axis=0, return_inverse=True)
    return labels.reshape(-1).astype(np.int64)


def surface_edges(tri_vertices: np.ndarray, signs: np.ndarray) -> tuple[bool, bool]:
    """Whether a triangulated surface is closed, and whether its orientation is consistent.

    Closed: every undirected edge belongs to exactly two triangles (a watertight, edge-conforming
    triangulation; a surface with T-junctions counts as open). Consistent: after reversing the
    triangles with ``signs < 0``, each directed edge ``a -> b`` is matched by exactly one
    ``b -> a`` (all normals point to the same side of the surface).

    Parameters
    ----------
    tri_vertices : (T, 3) int array, merged vertex labels of the corners.
    signs : (T,) array of +1/-1, orientation of each triangle.

    Returns
    -------
    (closed, consistent) : tuple of bool
    """
    tv = np.asarray(tri_vertices, dtype=np.int64).copy()
    if tv.shape[0] == 0:
        return False, True
    flip = np.asarray(signs) < 0
    tv[flip, 1], tv[flip, 2] = tv[flip, 2].copy(), tv[flip, 1].copy()
    directed = np.concatenate([tv[:, [0, 1]], tv[:, [1, 2]], tv[:, [2, 0]]])
    undirected = np.sort(directed, axis=1)
    _, counts = np.unique(undirected, axis=0, return_counts=True)
    closed = bool(np.all(counts == 2))
    _, dcounts = np.unique(directed, axis=0, return_counts=True)
    consistent = bool(np.all(dcounts == 1))
    return closed, consistent


def enclosed_volume(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray, signs: np.ndarray) -> float:
    r"""Volume enclosed by a closed triangulated surface whose inward normals are ``signs * n``.

    Divergence theorem with :math:`\nabla\cdot\mathbf x = 3`:
    :math:`V = \tfrac13\oint \mathbf x\cdot\mathbf n_\mathrm{out}\,dA
    = -\tfrac16\sum_t s_t\,\mathbf n_t\cdot\mathbf p_{0t}`, where
    :math:`\mathbf n_t = (\mathbf p_1-\mathbf p_0)\times(\mathbf p_2-\mathbf p_0)` has length
    :math:`2A_t` and :math:`\mathbf x\cdot\mathbf n_t` is constant over the triangle.
    Meaningful only for a closed surface (see :func:`surface_edges`).

    Returns
    -------
    float [length^3]
    """
    n = triangle_normals(p0, p1, p2)
    return float(-np.sum(np.asarray(signs) * np.einsum("tk,tk->t", n, np.asarray(p0))) / 6.0)
