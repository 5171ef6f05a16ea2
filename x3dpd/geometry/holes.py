"""Analytic drilled plate: identical cylindrical holes on a square grid, one sphere per hole --
the report's multiple individual particle (MIP) damper (Section 11.2, Figures 66-68).

A plate is given by two nodes and two lengths (HOLES card: SET NODE_A NODE_B RADIUS PITCH):
A is the centre of the bottom of one hole (the grid's origin), B the centre of its top, so
u = (B - A)/L is the holes' axis and L = |B - A| their length (the plate's thickness plus its
shims); RADIUS R is the holes' radius and PITCH p their spacing on a square grid through A,
its rows along the in-plane axes

    e1 = (u x h) / |u x h|,   e2 = u x e1,

h the coordinate axis most nearly perpendicular to u (the first of equals): for an axis along
a coordinate axis the rows run along the other two (u = y: e1 = -z, e2 = -x). The hole a
sphere is in is the grid point nearest its centre p: with d = p - A, s = d . u,

    i = round(d . e1 / p),   j = round(d . e2 / p),   o = p (i e1 + j e2),

and the hole is the cylinder of axis A + o -> B + o (x3dpd.geometry.cylinder): with
rho = d - s u - o,

* part 0, the bore: a = r + |rho| - R, n = -rho/|rho|, valid while 0 <= s <= L;
* part 1, the bottom at A (normal +u): a = r - s, valid while |rho| <= R;
* part 2, the top at B (normal -u): a = r - (L - s), valid while |rho| <= R.

The reaction goes to A and B with the weights (1 - xi, xi) of the axial point next to the wall
point (xi = s/L on the bore, 0 and 1 at the ends), and the lever from A + xi (B - A) to the
wall point is the cylinder's plus the hole's offset o: exact for A and B moving rigidly with a
plate that does not turn about its axis (the grid's axes follow u, not a turn about it; the
model builder refuses a plate on a body free to turn). Holes no wider than the pitch keep two
spheres apart (their centres stay p - 2(R - r) >= 2r apart), so a set of HOLES walls has no
pair contacts (``Shape.cells``); the builder refuses two spheres in one hole.

The geometry helpers describe the grid's origin hole (its volume, box and mesh); the particles
say which other holes are drilled (the PLATES card makes both: x3dpd.deck.plates).
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd._jit import step_kernel
from x3dpd.geometry.cylinder import _extent, _length, cylinder_mesh
from x3dpd.geometry.shape import Shape

__all__ = ["HOLE_PARTS", "SHAPE", "clear_of", "grid_axes", "hole_coordinates",
           "holes_clearance", "locate_parts"]

#: Contact entities of one hole: the bore, and the end nearer the sphere's centre.
HOLE_PARTS = 2
PART_NAMES = ("bore", "nearer end")


#: Where the model builder puts the plate's constants (:func:`plate_constants`) in its row of
#: parameters, after RADIUS and PITCH: u, e1 / p, e2 / p, p e1, p e2, L.
C_U, C_E1, C_E2, C_PE1, C_PE2, C_L = 2, 5, 8, 11, 14, 17
N_CONSTANTS = 16


@step_kernel
def locate_parts(x, na, nb, params, c, px, py, pz, r, out):
    """The two parts' rows (valid, a, n, xi, l) for a sphere at p of radius r in its hole of
    plate ``c`` with node A ``na`` (x3dpd.geometry.shapes): the bore, and the hole's end nearer
    the centre. ``params[c]``: RADIUS, PITCH, then :func:`plate_constants` (the plate never
    turns, so its axis and grid axes are those of the deck; A gives where it is now)."""
    q = params[c]
    ux = q[C_U]
    uy = q[C_U + 1]
    uz = q[C_U + 2]
    length = q[C_L]
    s, rx, ry, rz, ox, oy, oz = _in_hole(x, na, q, px, py, pz)
    rho = math.sqrt(rx * rx + ry * ry + rz * rz)
    # part 0, the bore (valid over the hole's length, away from its axis)
    big_r = q[0]
    if rho > 0.0 and s >= 0.0 and s <= length:
        inv = 1.0 / rho
        out[0, 0] = 1.0
        out[0, 1] = r + rho - big_r
        out[0, 2] = -rx * inv
        out[0, 3] = -ry * inv
        out[0, 4] = -rz * inv
        out[0, 5] = s / length
        out[0, 6] = big_r * rx * inv + ox
        out[0, 7] = big_r * ry * inv + oy
        out[0, 8] = big_r * rz * inv + oz
    else:
        out[0, 0] = 0.0
    # part 1, the nearer end: the bottom at A (normal +u) or the top at B (normal -u)
    out[1, 0] = 1.0 if rho <= big_r else 0.0
    if s <= 0.5 * length:
        out[1, 1] = r - s
        out[1, 2] = ux
        out[1, 3] = uy
        out[1, 4] = uz
        out[1, 5] = 0.0
    else:
        out[1, 1] = r - (length - s)
        out[1, 2] = -ux
        out[1, 3] = -uy
        out[1, 4] = -uz
        out[1, 5] = 1.0
    out[1, 6] = rx + ox
    out[1, 7] = ry + oy
    out[1, 8] = rz + oz


#: The bore's margin in :func:`clear_of`, relative to the hole's radius: far above the few
#: units in the last place by which ``r + |rho| - R`` can round, far below any clearance.
CLEAR_MARGIN = 1e-12


@step_kernel
def clear_of(x, na, nb, params, c, px, py, pz, r):
    """True when neither part of the sphere's hole touches it: the bore's overlap
    r + |rho| - R <= 0 and both ends' r - s, r - (L - s) <= 0 (:func:`locate_parts`'s values),
    tested without the square root as

        |rho|^2 <= (R - r - m)^2 with R - r - m > 0,   s >= r,   L - s >= r,

    m = CLEAR_MARGIN R: the margin makes the bore's test hold after rounding (|rho| then
    lies m below R - r, which ``r + |rho| - R`` cannot cross by rounding); the ends' are
    exact (a difference of two floats is positive exactly when they are ordered so). A
    sphere wider than its hole less the margin is never clear."""
    q = params[c]
    s, rx, ry, rz, _, _, _ = _in_hole(x, na, q, px, py, pz)
    inner = q[0] - r - CLEAR_MARGIN * q[0]
    return (s >= r and q[C_L] - s >= r and inner > 0.0
            and rx * rx + ry * ry + rz * rz <= inner * inner)


@step_kernel
def _in_hole(x, na, q, px, py, pz):
    """(s, rho, o) of a sphere centre p in the plate of constants ``q`` with node A ``na``
    (module docstring): its axial coordinate, its offset rho from its hole's axis and its hole's
    offset o from the grid's origin hole, as scalars (s, rho_x, rho_y, rho_z, o_x, o_y, o_z)."""
    ux = q[C_U]
    uy = q[C_U + 1]
    uz = q[C_U + 2]
    dx = px - x[na, 0]
    dy = py - x[na, 1]
    dz = pz - x[na, 2]
    s = dx * ux + dy * uy + dz * uz
    # the grid indices as floats (np.floor keeps a float: no round trip through an integer
    # register on the path to the square root; the same values, small whole numbers)
    i = np.floor(dx * q[C_E1] + dy * q[C_E1 + 1] + dz * q[C_E1 + 2] + 0.5)
    j = np.floor(dx * q[C_E2] + dy * q[C_E2 + 1] + dz * q[C_E2 + 2] + 0.5)
    ox = i * q[C_PE1] + j * q[C_PE2]
    oy = i * q[C_PE1 + 1] + j * q[C_PE2 + 1]
    oz = i * q[C_PE1 + 2] + j * q[C_PE2 + 2]
    return s, dx - s * ux - ox, dy - s * uy - oy, dz - s * uz - oz, ox, oy, oz


def plate_constants(ends, params) -> tuple[float, ...]:
    """The plate's constants after RADIUS and PITCH in its row of parameters
    (:data:`N_CONSTANTS`): u, e1 / p, e2 / p, p e1, p e2, L (module docstring)."""
    u, e1, e2 = grid_axes(ends[0], ends[1])
    p = float(params[1])
    return tuple(float(v) for v in (*u, *(e1 / p), *(e2 / p), *(p * e1), *(p * e2))) + (
        _length(ends),)


def grid_axes(a, b) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(u, e1, e2): the plate's axis and the grid's in-plane axes (module docstring)."""
    a = np.asarray(a, dtype=np.float64)
    u = np.asarray(b, dtype=np.float64) - a
    u = u / np.linalg.norm(u)
    k = int(np.argmin(np.abs(u)))
    e1 = np.cross(u, np.eye(3)[k])
    e1 /= np.linalg.norm(e1)
    return u, e1, np.cross(u, e1)


def hole_coordinates(points, a, b, pitch: float):
    """(s, |rho|, L, cells) of ``points`` (N, 3) in the plate: the axial coordinate, the
    distance from the axis of the hole each is in, the holes' length, and that hole's grid
    indices (N, 2) int."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    a = np.asarray(a, dtype=np.float64)
    u, e1, e2 = grid_axes(a, b)
    d = points - a
    s = d @ u
    cells = np.floor(np.stack([d @ e1, d @ e2], axis=1) / pitch + 0.5)
    rho = d - s[:, None] * u - pitch * (cells[:, :1] * e1 + cells[:, 1:] * e2)
    length = float(np.linalg.norm(np.asarray(b, dtype=np.float64) - a))
    return s, np.linalg.norm(rho, axis=1), length, cells.astype(np.int64)


def holes_clearance(points, radii, a, b, big_r: float, pitch: float):
    """Gap of each sphere to the nearest wall part of its hole [length] (negative: overlap)
    and whether its centre lies inside the hole."""
    s, rho, length, _ = hole_coordinates(points, a, b, pitch)
    wall = np.minimum(np.minimum(big_r - rho, s), length - s)
    inside = (rho <= big_r) & (s >= 0.0) & (s <= length)
    return wall - np.asarray(radii, dtype=np.float64), inside


def _problem(ends, params) -> str | None:
    if not _length(ends) > 0.0:
        return "coincide: the holes have no length"
    if not float(params[1]) > 2.0 * float(params[0]):
        return (f"hold holes of diameter {2.0 * float(params[0]):g} at pitch "
                f"{float(params[1]):g}: holes wider than the pitch overlap")
    return None


SHAPE = Shape(
    name="holes", card="HOLES", node_fields=("NODE_A", "NODE_B"),
    param_fields=("RADIUS", "PITCH"), part_names=PART_NAMES, locate_parts=locate_parts,
    clearance=lambda points, radii, ends, params: holes_clearance(
        points, radii, ends[0], ends[1], float(params[0]), float(params[1])),
    volume=lambda ends, params: math.pi * float(params[0]) ** 2 * _length(ends),
    extent=_extent,  # the grid's origin hole's box (the cylinder's)
    mesh=lambda ends, params, n: cylinder_mesh(ends[0], ends[1], float(params[0]), n),
    describe=lambda ends, params: (f"holes of radius {float(params[0]):g}, length "
                                   f"{_length(ends):.6g}, pitch {float(params[1]):g}"),
    problem=_problem,
    cells=lambda points, ends, params: hole_coordinates(points, ends[0], ends[1],
                                                        float(params[1]))[3],
    constants=plate_constants, n_constants=N_CONSTANTS, clear_of=clear_of,
    node_words=("node A (a hole's bottom)", "node B (its top)"),
    nodes_word="nodes",
    doc="a drilled plate: identical cylindrical holes on a square grid, one sphere per hole "
        "(Section 11.2, the MIP damper)")
