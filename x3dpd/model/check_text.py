"""Text of the pre-run check's findings: planes, spans, triangles, node id ranges, and the
cap on how many detail lines a warning lists."""

from __future__ import annotations

import math

import numpy as np

from x3dpd.model.model import Model

#: Longest listing of one warning's details.
MAX_LISTED = 20
_AXES = "xyz"


def _planes_text(n_in: np.ndarray, p0: np.ndarray) -> str:
    """'x = 0.0625, 0.1875, z = ±0.09375' for axis-aligned planes, 'n·x = d' otherwise."""
    by_axis: dict[int, list[float]] = {}
    other = []
    for n, p in zip(n_in, p0):
        k = int(np.argmax(np.abs(n)))
        if abs(abs(n[k]) - 1.0) <= 1e-9:
            by_axis.setdefault(k, []).append(float(p[k]))
        else:
            other.append(f"({n[0]:.4g}, {n[1]:.4g}, {n[2]:.4g})·x = {float(n @ p):.6g}")
    parts = []
    for k in sorted(by_axis):
        vals = sorted(set(round(v, 12) for v in by_axis[k]), key=lambda v: (abs(v), v))
        text, used = [], set()
        for v in vals:
            if v in used:
                continue
            if v != 0.0 and -v in vals:
                text.append(f"±{abs(v):g}")
                used.update({v, -v})
            else:
                text.append(f"{v:g}")
                used.add(v)
        parts.append(f"{_AXES[k]} = {', '.join(text)}")
    return ", ".join(parts + other)


def _span_text(centres: np.ndarray) -> str:
    """'x, y from 0.03125 to 0.21875 and z from -0.09375 to 0.09375'."""
    if centres.shape[0] == 0:
        return "nothing"
    lo, hi = centres.min(axis=0), centres.max(axis=0)
    groups: list[tuple[list[str], float, float]] = []
    for k in range(3):
        for g in groups:
            if math.isclose(g[1], lo[k], abs_tol=1e-12) and math.isclose(
                g[2], hi[k], abs_tol=1e-12
            ):
                g[0].append(_AXES[k])
                break
        else:
            groups.append(([_AXES[k]], float(lo[k]), float(hi[k])))
    return " and ".join(f"{', '.join(a)} from {a_lo:g} to {a_hi:g}" for a, a_lo, a_hi in groups)


def _tri(model: Model, k: int) -> str:
    nodes = " ".join(str(int(model.node_ids[i])) for i in model.tri_nodes[k])
    return f"triangle {k + 1} (nodes {nodes})"


def _listed(lines: list[str]) -> tuple[str, ...]:
    if len(lines) <= MAX_LISTED:
        return tuple(lines)
    return (*lines[:MAX_LISTED], f"... and {len(lines) - MAX_LISTED} more")


def _ranges(ids: np.ndarray) -> str:
    """'26-40, 42, 44-50' from sorted ids."""
    ids = np.sort(np.asarray(ids))
    out, start = [], 0
    for k in range(1, ids.size + 1):
        if k == ids.size or ids[k] != ids[k - 1] + 1:
            a, b = int(ids[start]), int(ids[k - 1])
            out.append(f"{a}" if a == b else f"{a}-{b}")
            start = k
    return ", ".join(out)


_WORDS = (
    "zero one two three four five six seven eight nine ten eleven twelve thirteen "
    "fourteen fifteen sixteen seventeen eighteen nineteen twenty"
).split()


def _count(n: int) -> str:
    return _WORDS[n] if 0 <= n < len(_WORDS) else str(n)
