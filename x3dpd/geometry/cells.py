"""Broad-phase search for particle pairs: cell list (or all pairs for a handful of particles).

Finds every pair (i < j) of particles in the same cavity whose centre distance is below
``R_i + R_j + skin``. A Verlet list built with a skin stays valid until particles have moved
``skin / 2`` each; the solver rebuilds it then. Cells have the side of the largest cut-off, so a
particle's partners lie in its own and the 26 neighbouring cells: O(N) work instead of O(N^2).
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd._jit import kernel

#: Up to this many particles, all pairs are tested directly (cheaper than binning).
BRUTE_FORCE_LIMIT = 64


@kernel
def _pairs_brute(x, radius, cavity, skin, out_i, out_j):
    n = x.shape[0]
    count = 0
    cap = out_i.shape[0]
    for i in range(n):
        for j in range(i + 1, n):
            if cavity[i] != cavity[j]:
                continue
            cut = radius[i] + radius[j] + skin
            dx = x[j, 0] - x[i, 0]
            dy = x[j, 1] - x[i, 1]
            dz = x[j, 2] - x[i, 2]
            if dx * dx + dy * dy + dz * dz < cut * cut:
                if count >= cap:
                    return -1
                out_i[count] = i
                out_j[count] = j
                count += 1
    return count


# Over 80 lines: a compiled kernel: one cell-list sweep, no call per candidate.
@kernel
def _pairs_cells(x, radius, cavity, skin, out_i, out_j):
    """Cell-list pair search; pairs come out sorted by i, then j. Returns -1 on overflow."""
    n = x.shape[0]
    if n == 0:
        return 0
    rmax = 0.0
    lo = np.empty(3)
    hi = np.empty(3)
    for d in range(3):
        lo[d] = x[0, d]
        hi[d] = x[0, d]
    for i in range(n):
        if radius[i] > rmax:
            rmax = radius[i]
        for d in range(3):
            if x[i, d] < lo[d]:
                lo[d] = x[i, d]
            if x[i, d] > hi[d]:
                hi[d] = x[i, d]
    cell = 2.0 * rmax + skin
    # bound the grid to ~ 8 n cells so that scattered particles cannot blow up memory
    dims = np.empty(3, dtype=np.int64)
    while True:
        total = 1
        for d in range(3):
            dims[d] = max(1, int(math.floor((hi[d] - lo[d]) / cell)) + 1)
            total *= dims[d]
        if total <= 8 * n + 27:
            break
        cell *= 1.5
    ncell = dims[0] * dims[1] * dims[2]
    key = np.empty(n, dtype=np.int64)
    start = np.zeros(ncell + 1, dtype=np.int64)
    for i in range(n):
        cx = min(int((x[i, 0] - lo[0]) / cell), dims[0] - 1)
        cy = min(int((x[i, 1] - lo[1]) / cell), dims[1] - 1)
        cz = min(int((x[i, 2] - lo[2]) / cell), dims[2] - 1)
        key[i] = cx + dims[0] * (cy + dims[1] * cz)
        start[key[i] + 1] += 1
    for c in range(ncell):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    order = np.empty(n, dtype=np.int64)
    for i in range(n):
        order[fill[key[i]]] = i
        fill[key[i]] += 1
    count = 0
    cap = out_i.shape[0]
    buf = np.empty(n, dtype=np.int64)
    for i in range(n):
        k = key[i]
        cx = k % dims[0]
        cy = (k // dims[0]) % dims[1]
        cz = k // (dims[0] * dims[1])
        nb = 0
        for ox in range(-1, 2):
            gx = cx + ox
            if gx < 0 or gx >= dims[0]:
                continue
            for oy in range(-1, 2):
                gy = cy + oy
                if gy < 0 or gy >= dims[1]:
                    continue
                for oz in range(-1, 2):
                    gz = cz + oz
                    if gz < 0 or gz >= dims[2]:
                        continue
                    c = gx + dims[0] * (gy + dims[1] * gz)
                    for q in range(start[c], start[c + 1]):
                        j = order[q]
                        if j <= i or cavity[j] != cavity[i]:
                            continue
                        cut = radius[i] + radius[j] + skin
                        dx = x[j, 0] - x[i, 0]
                        dy = x[j, 1] - x[i, 1]
                        dz = x[j, 2] - x[i, 2]
                        if dx * dx + dy * dy + dz * dz < cut * cut:
                            # j into buf[:nb] in order: an insertion sort of the few partners
                            # of i (numba's compiled array sort cost a fresh clone ~1 CPU-s)
                            k = nb
                            while k > 0 and buf[k - 1] > j:
                                buf[k] = buf[k - 1]
                                k -= 1
                            buf[k] = j
                            nb += 1
        if count + nb > cap:
            return -1
        for q in range(nb):
            out_i[count] = i
            out_j[count] = buf[q]
            count += 1
    return count


@kernel
def _find_pairs(x, radius, cavity, skin, out_i, out_j):
    """Dispatch: all pairs for few particles, cells otherwise. Sorted by (i, j)."""
    if x.shape[0] <= BRUTE_FORCE_LIMIT:
        return _pairs_brute(x, radius, cavity, skin, out_i, out_j)
    return _pairs_cells(x, radius, cavity, skin, out_i, out_j)


def find_pairs(x, radius, cavity=None, skin: float = 0.0, method: str = "auto"):
    """All pairs (i < j) with |x_i - x_j| < R_i + R_j + skin in the same cavity.

    Parameters
    ----------
    x : (N, 3) array of centres [length]; radius : (N,) or scalar [length];
    cavity : (N,) int labels (pairs only within a label), default all one cavity;
    skin : extra distance [length] >= 0; method : "auto", "cells" or "brute".

    Returns
    -------
    (M, 2) int64 array of index pairs sorted by (i, j).
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    if x.ndim != 2 or x.shape[1] != 3:
        raise ValueError(f"x must have shape (N, 3), got {x.shape}")
    n = x.shape[0]
    radius = np.broadcast_to(np.asarray(radius, dtype=np.float64), (n,)).copy()
    if np.any(radius <= 0):
        raise ValueError("radii must be > 0")
    if skin < 0:
        raise ValueError("skin must be >= 0")
    cavity = np.zeros(n, np.int64) if cavity is None else np.ascontiguousarray(cavity, np.int64)
    fn = {"auto": _find_pairs, "cells": _pairs_cells, "brute": _pairs_brute}[method]
    cap = max(16, 8 * n)
    while True:
        out_i = np.empty(cap, np.int64)
        out_j = np.empty(cap, np.int64)
        m = fn(x, radius, cavity, float(skin), out_i, out_j)
        if m >= 0:
            return np.stack([out_i[:m], out_j[:m]], axis=1)
        cap *= 2
