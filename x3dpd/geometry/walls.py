"""Spheres against oriented wall triangles: which centres lie over which triangles, and how far.

Pure numpy for one-off checks before a run (the solver has its own contact kernels).
"""

from __future__ import annotations

import numpy as np

from x3dpd.geometry.triangle import points_in_triangles, signed_distances


def sphere_triangle_pairs(centres: np.ndarray, sphere_group: np.ndarray, p0: np.ndarray,
                          p1: np.ndarray, p2: np.ndarray, n_in: np.ndarray,
                          tri_group: np.ndarray, edge_tol: np.ndarray,
                          max_block: int = 500_000) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Sphere-triangle pairs of one group whose centre lies over the (grown) triangle.

    A pair ``(i, t)`` is returned when sphere ``i`` and triangle ``t`` have the same group
    (cavity) and the projection of centre :math:`\mathbf x_i` onto the triangle's plane lies
    inside the triangle grown by ``edge_tol[i]`` (see
    :func:`~x3dpd.geometry.triangle.points_in_triangles`). With it comes the signed distance
    :math:`d = (\mathbf x_i-\mathbf p_{0t})\cdot\hat{\mathbf n}_t`,
    positive on the inner side of the wall. A sphere of radius :math:`R` penetrates the wall when
    :math:`0 \le d < R` and lies behind it (outside the cavity) when :math:`d < 0`.

    Parameters
    ----------
    centres : (N, 3) array [length]
    sphere_group : (N,) int array, cavity of each sphere (-1: none, never paired).
    p0, p1, p2 : (T, 3) array [length], triangle corners.
    n_in : (T, 3) array, unit inward normals.
    tri_group : (T,) int array, cavity of each triangle.
    edge_tol : (N,) array [length], how far outside a triangle's edges a projection may fall.
    max_block : int, largest N*T block evaluated at once (bounds memory).

    Returns
    -------
    sphere, triangle : (M,) int64 arrays
    distance : (M,) array [length]
    """
    centres = np.asarray(centres, dtype=np.float64).reshape(-1, 3)
    n, t = centres.shape[0], np.asarray(p0).reshape(-1, 3).shape[0]
    out_s, out_t, out_d = [], [], []
    step = max(1, max_block // max(t, 1))
    for a in range(0, n if t else 0, step):
        sl = slice(a, min(n, a + step))
        same = sphere_group[sl, None] == tri_group[None, :]
        same &= sphere_group[sl, None] >= 0
        if not same.any():
            continue
        over = same & points_in_triangles(centres[sl], p0, p1, p2, edge_tol[sl])
        i, k = np.nonzero(over)
        d = signed_distances(centres[sl], p0, n_in)[i, k]
        out_s.append(i + a)
        out_t.append(k)
        out_d.append(d)
    if not out_s:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0)
    return (np.concatenate(out_s).astype(np.int64), np.concatenate(out_t).astype(np.int64),
            np.concatenate(out_d))
