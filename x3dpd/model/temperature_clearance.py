"""The clearance of a cavity: how far one of its spheres could travel alone, along each of the
cavity's directions (the TEMPERATURE card's check lines, x3dpd.model.temperature).

For a cavity whose largest sphere has radius r:

* an analytic wall (CYLINDER, CAPSULE ...): along its axis, its inner length there less the
  diameter -- L - 2r between a cylinder's flat caps (for one sphere, the report's *free length*,
  Sections 6.3 and 11), L + 2R - 2r between a capsule's hemispherical ends -- and across it,
  2R - 2r (twice the radial gap R - r). Measured in the shape's own frame (its axis along x) with
  the shape's ``extent``, so a tilted wall has the same clearance as an aligned one;
* triangles: the span of the cavity's wall nodes along x, y and z, less 2r (a box's interior
  lengths less the diameter).

For a cavity holding many spheres this is one sphere's rattle space, not the bed's (that is
x3dpd.model.check_beds' free length); a clearance at or below zero means a sphere has no room
along that direction.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from x3dpd.geometry.shapes import analytic_wall

_AXES = "xyz"


class Clearance(NamedTuple):
    """One direction of one cavity: ``what`` it measures ("cylinder 1 along its axis", "box
    along x") and the clearance [length] of its largest sphere at the assembly temperature and
    at the operating one."""

    set_id: int
    what: str
    assembly: float
    operating: float


def _axis_frame(ends: np.ndarray) -> np.ndarray:
    """``ends`` (k, 3) moved so that the first lies at the origin and the axis along +x."""
    if len(ends) < 2:
        return np.zeros_like(ends)
    length = float(np.linalg.norm(ends[1] - ends[0]))
    out = np.zeros_like(ends)
    out[1, 0] = length
    return out


def wall_widths(model, w: int) -> tuple[float, float]:
    """(along its axis, across) the inner widths of analytic wall ``w`` [length]."""
    shape, ends, lengths = analytic_wall(
        model.shape_kind[w], model.shape_nodes[w], model.shape_params[w], model.x0
    )
    lo, hi = shape.extent(_axis_frame(np.asarray(ends, float)), lengths)
    return float(hi[0] - lo[0]), float(hi[1] - lo[1])


def cavity_clearances(model, c: int) -> list[tuple[str, float]]:
    """(what, clearance) of each direction of cavity ``c`` for its largest sphere; [] when it
    holds no particle."""
    mine = np.flatnonzero(model.particle_cavity == c)
    if not mine.size:
        return []
    diameter = 2.0 * float(model.radius[mine].max())
    out = []
    walls = np.flatnonzero(model.shape_cavity == c)
    for k, w in enumerate(walls, start=1):
        name = analytic_wall(
            model.shape_kind[w], model.shape_nodes[w], model.shape_params[w], model.x0
        )[0].name
        label = name if len(walls) == 1 else f"{name} {k}"
        along, across = wall_widths(model, int(w))
        out += [
            (f"{label} along its axis", along - diameter),
            (f"{label} across", across - diameter),
        ]
    tri = model.tri_nodes[model.face_cavity[model.tri_face] == c].reshape(-1)
    if tri.size:
        span = np.ptp(model.x0[np.unique(tri)], axis=0)
        out += [(f"box along {_AXES[d]}", float(span[d]) - diameter) for d in range(3)]
    return out


def clearances(cold, hot) -> list[Clearance]:
    """Each cavity's clearances in the model at the assembly temperature (``cold``) and at the
    operating one (``hot``: the same cavities, grown)."""
    out = []
    for c, sid in enumerate(cold.cavity_set_ids.tolist()):
        for (what, before), (_, after) in zip(
            cavity_clearances(cold, c), cavity_clearances(hot, c)
        ):
            out.append(Clearance(int(sid), what, before, after))
    return out


__all__ = ["Clearance", "cavity_clearances", "clearances", "wall_widths"]
