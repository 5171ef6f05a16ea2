"""A particle bed against its cavity: the free length along an axis, and the beds that fill their
cavity wall to wall (an ``x3dpd check`` warning).

The free length along an axis is the report's clearance (Sections 10, 11.2; the clearance rule
of thumb, x3dpd.model.rules_of_thumb): the cavity's extent less the bed's, the particles'
centres' span plus their radii, as they start. A bed is jammed along an axis when every one of
its particles lies in a chain of touching particles (contact normals within 60 degrees of the
axis) that reaches from wall to wall along it -- ``x3dpd fill --packing cubic`` with the
default gap 0 in a cavity a whole number of diameters long: the particles have no room to move
relative to the cavity, rattle only by their contacts' elastic give and damp next to nothing by
impacts. A bed with a row not full, or an empty site to move into, is not jammed. The axis is
the drive's (the built-in USRFRC laws'); without a drive, a bed is jammed when it is along
every axis.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.errors import X3dpdError
from x3dpd.geometry.shapes import SHAPES
from x3dpd.model.check_shapes import shape_extent
from x3dpd.model.model import Model
from x3dpd.physics.usrfrc import force_table, law_count, split_specs

#: A gap below this fraction of the bed's smallest particle diameter counts as none.
JAM_TOLERANCE = 1e-6
#: Contacts whose normal is within 60 degrees of an axis carry a chain along it.
CHAIN_COSINE = 0.5
_AXES = "xyz"


def cavity_span(model: Model, c: int, d: int) -> tuple[float, float]:
    """(lo, hi) of cavity ``c`` along axis ``d``: its triangles' nodes and analytic walls."""
    tri = model.tri_nodes[model.face_cavity[model.tri_face] == c].reshape(-1)
    pts = [model.x0[tri, d]] if tri.size else []
    for w in np.flatnonzero(model.shape_cavity == c):
        lo, hi = shape_extent(model, int(w))
        pts.append(np.array([lo[d], hi[d]]))
    both = np.concatenate(pts) if pts else np.zeros(0)
    return (float(both.min()), float(both.max())) if both.size else (math.nan, math.nan)


def bed_extent(model: Model, c: int, d: int) -> tuple[float, float, float] | None:
    """(cavity length, bed extent, free length) of cavity ``c`` along axis ``d`` [length], or
    None when the cavity holds no particles or has no walls along ``d``."""
    mine = np.flatnonzero(model.particle_cavity == c)
    lo, hi = cavity_span(model, c, d)
    if not mine.size or not math.isfinite(hi - lo):
        return None
    x, r = model.x0[model.particle_start + mine, d], model.radius[mine]
    bed = float(np.max(x + r) - np.min(x - r))
    if _one_per_cell(model, c):  # a drilled plate: its span is one hole's, each sphere alone
        bed = float(2.0 * r.max())
    return hi - lo, bed, (hi - lo) - bed


def _one_per_cell(model: Model, c: int) -> bool:
    """Whether cavity ``c`` is walls whose particles sit alone in cells (``Shape.cells``: the
    holes of a drilled plate) and nothing else."""
    walls = np.flatnonzero(model.shape_cavity == c)
    own_faces = bool(np.any(model.face_cavity[model.tri_face] == c))
    kinds = model.shape_kind[walls].tolist()
    return bool(walls.size) and not own_faces and all(SHAPES[k].cells is not None for k in kinds)


def drive_axes(model: Model, usrfrc=()) -> list[int]:
    """Axes 0-2 along which the built-in USRFRC laws of the deck (or ``usrfrc`` specs, which
    replace them as ``x3dpd run --usrfrc`` does) push translations; [] when none does."""
    laws, _ = split_specs(tuple(usrfrc) or tuple(model.usrfrc))
    try:
        table = force_table(laws, model.node_ids) if laws else np.zeros((0, 3))
    except X3dpdError:
        return []
    dofs = [int(row[2]) for row in table[: law_count(table)] if int(row[2]) < 3]
    return list(dict.fromkeys(dofs))


def _chained(model: Model, c: int, d: int, tol: float) -> bool:
    """Whether every particle of cavity ``c`` lies in a chain of touching particles (gaps <=
    ``tol``, normals within :data:`CHAIN_COSINE` of axis ``d``) from wall to wall along ``d``."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    mine = np.flatnonzero(model.particle_cavity == c)
    x, r = model.x0[model.particle_start + mine], model.radius[mine]
    lo, hi = cavity_span(model, c, d)
    pairs = cKDTree(x).query_pairs(2.0 * float(r.max()) + tol, output_type="ndarray")
    gap = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1)
    along = np.abs(x[pairs[:, 0], d] - x[pairs[:, 1], d]) >= CHAIN_COSINE * gap
    pairs = pairs[(gap <= r[pairs[:, 0]] + r[pairs[:, 1]] + tol) & along]
    n = mine.size
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    low = np.bincount(label, weights=x[:, d] - r <= lo + tol) > 0
    high = np.bincount(label, weights=x[:, d] + r >= hi - tol) > 0
    return bool(np.all(low & high))


def jammed_beds(model: Model, usrfrc=()) -> list[tuple[str, str, list[str]]]:
    """(code, headline, details) of each cavity whose bed is jammed along the drive (every axis
    without a drive): module docstring."""
    axes = drive_axes(model, usrfrc)
    out = []
    for c, sid in enumerate(model.cavity_set_ids.tolist()):
        mine = np.flatnonzero(model.particle_cavity == c)
        if not mine.size:
            continue
        tol = JAM_TOLERANCE * 2.0 * float(model.radius[mine].min())
        spans = {d: bed_extent(model, c, d) for d in axes or range(3)}
        tight = [
            d
            for d, e in spans.items()
            if e is not None and e[2] <= tol and _chained(model, c, d, tol)
        ]
        if not tight or (not axes and len(tight) < 3):
            continue
        where = ", ".join(_AXES[d] for d in tight)
        what = "the drive's axis" if axes else "every axis"
        out.append(
            (
                "jammed-bed",
                f"cavity set {sid}: the particles fill it wall to wall along {where} ({what}; "
                f"free length {max(spans[d][2] for d in tight):.3g} of a cavity "
                f"{spans[tight[0]][0]:.4g} long): they have no room to move relative to the "
                "cavity and will damp next to nothing by impacts; leave a clearance (x3dpd "
                "fill --gap, fewer particles, a longer cavity)",
                [],
            )
        )
    return out


__all__ = ["JAM_TOLERANCE", "bed_extent", "cavity_span", "drive_axes", "jammed_beds"]
