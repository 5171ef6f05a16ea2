"""Overlapping sphere pairs by a uniform cell grid (pure numpy, for one-off checks).

The solver's broad phase lives in ``x3dpd/geometry/cells.py``; this is the vectorised numpy
version used before a run, where building numba kernels would cost more than the search.
"""

from __future__ import annotations

import itertools

import numpy as np


def overlapping_pairs(centres: np.ndarray, radii: np.ndarray,
                      rel_tol: float = 1e-9) -> tuple[np.ndarray, np.ndarray]:
    r"""All pairs of overlapping spheres.

    Overlap: :math:`|\mathbf x_i-\mathbf x_j| < (R_i+R_j)(1-\epsilon)`.

    Spheres that just touch (distance :math:`R_i+R_j` up to the relative tolerance
    :math:`\epsilon`) do not count. Cost :math:`O(N)` for bounded density: the centres are
    binned into cubic cells of side :math:`2\max R`, so overlapping spheres sit in the same or
    adjacent cells, and only the 27 neighbouring cells of each sphere are searched.

    Parameters
    ----------
    centres : (N, 3) array [length]
    radii : (N,) array [length]
    rel_tol : float, relative tolerance :math:`\epsilon`.

    Returns
    -------
    pairs : (M, 2) int64 array, ``i < j``, sorted.
    depth : (M,) array [length], overlaps :math:`R_i+R_j-|\mathbf x_i-\mathbf x_j|`.
    """
    x = np.asarray(centres, dtype=np.float64).reshape(-1, 3)
    r = np.asarray(radii, dtype=np.float64).reshape(-1)
    n = x.shape[0]
    if n < 2:
        return np.zeros((0, 2), dtype=np.int64), np.zeros(0)
    cell = 2.0 * float(r.max())
    cell = cell if cell > 0.0 else 1.0
    ijk = np.floor((x - x.min(axis=0)) / cell).astype(np.int64)
    dims = ijk.max(axis=0) + 3  # one empty layer on each side for the neighbour offsets
    ijk += 1

    def encode(c: np.ndarray) -> np.ndarray:
        return (c[:, 0] * dims[1] + c[:, 1]) * dims[2] + c[:, 2]

    keys = encode(ijk)
    order = np.argsort(keys, kind="stable")
    sorted_keys = keys[order]
    found_i: list[np.ndarray] = []
    found_j: list[np.ndarray] = []
    for off in itertools.product((-1, 0, 1), repeat=3):
        target = encode(ijk + np.asarray(off, dtype=np.int64))
        lo = np.searchsorted(sorted_keys, target, side="left")
        hi = np.searchsorted(sorted_keys, target, side="right")
        count = hi - lo
        i = np.repeat(np.arange(n), count)
        starts = np.repeat(lo, count)
        within = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        j = order[starts + within]
        keep = i < j
        found_i.append(i[keep])
        found_j.append(j[keep])
    i = np.concatenate(found_i)
    j = np.concatenate(found_j)
    dist = np.linalg.norm(x[i] - x[j], axis=1)
    reach = r[i] + r[j]
    hit = dist < reach * (1.0 - rel_tol)
    pairs = np.stack([i[hit], j[hit]], axis=1)
    depth = (reach - dist)[hit]
    if pairs.shape[0]:
        o = np.lexsort((pairs[:, 1], pairs[:, 0]))
        pairs, depth = pairs[o], depth[o]
    return pairs.astype(np.int64), depth
