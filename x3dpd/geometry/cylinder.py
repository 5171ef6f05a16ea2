"""Analytic cylindrical cavity: the report's drilled holes and capsules (Sections 5-6, 9-10).

A cylinder is given by its two axis end nodes A and B (the centres of its end caps) and its
inner radius R [length]; particles live inside. Its wall has three parts, each a contact
entity of its own (a sphere near the rim touches the curved wall and a cap at once):

* part 0, the curved wall: with the particle centre p, the axis u = (B - A)/L, L = |B - A|,
  the axial coordinate s = (p - A) . u and the radial vector rho = p - A - s u, the sphere of
  radius r overlaps the wall by a = r + |rho| - R; the normal from the wall into the particle
  is n = -rho/|rho|, the wall point c = A + s u + R rho/|rho|; valid while 0 <= s <= L;
* part 1, the end cap at A (normal +u): a = r - s, wall point A + rho; valid while |rho| <= R;
* part 2, the end cap at B (normal -u): a = r - (L - s), wall point B + rho; valid while
  |rho| <= R.

The contact response (x3dpd.solver) spreads the wall's reaction over A and B with the weights
(1 - xi, xi) of the axial point A + xi (B - A) next to the wall point, xi = s/L on the curved
wall, 0 and 1 on the caps; the lever l = c - (A + xi (B - A)) from that axial point to the wall
point carries the moment l x F (to node A) and the wall point's velocity
v_c = (1 - xi) v_A + xi v_B + omega x l. Both are exact for nodes moving rigidly with the
cavity (RBEL slaves share their master's omega); nothing is neglected.

The compiled locators (``_cylinder_frame``, ``_locate_on_cylinder``) take scalars and arrays
only; the numpy helpers serve the checks before and during a run and the triangulated
cylinder of the viewers and tests.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd._jit import step_kernel
from x3dpd.geometry.shape import Shape

__all__ = ["CYLINDER_PARTS", "SHAPE", "clear_of", "cylinder_clearance", "cylinder_coordinates",
           "cylinder_mesh", "locate_parts", "_cylinder_frame", "_locate_on_cylinder"]

#: Contact entities of one cylinder: the curved wall, the cap at A, the cap at B.
CYLINDER_PARTS = 3
PART_NAMES = ("curved wall", "end cap at node A", "end cap at node B")


@step_kernel
def _cylinder_frame(x, na, nb, px, py, pz):
    """Axis frame of the point p: (L, u, s, rho, |rho|) with L = |B - A|, u = (B - A)/L,
    s = (p - A) . u and rho = p - A - s u (see the module docstring)."""
    ux = x[nb, 0] - x[na, 0]
    uy = x[nb, 1] - x[na, 1]
    uz = x[nb, 2] - x[na, 2]
    length = math.sqrt(ux * ux + uy * uy + uz * uz)
    inv = 1.0 / length
    ux *= inv
    uy *= inv
    uz *= inv
    dx = px - x[na, 0]
    dy = py - x[na, 1]
    dz = pz - x[na, 2]
    s = dx * ux + dy * uy + dz * uz
    rx = dx - s * ux
    ry = dy - s * uy
    rz = dz - s * uz
    rho = math.sqrt(rx * rx + ry * ry + rz * rz)
    return length, ux, uy, uz, s, rx, ry, rz, rho


@step_kernel
def _locate_on_cylinder(part, r, big_r, length, ux, uy, uz, s, rx, ry, rz, rho):
    """Contact of a sphere (radius r, frame from ``_cylinder_frame``) with one ``part`` of a
    cylinder of radius ``big_r``: (valid, a, n, xi, l) -- whether the centre lies over the
    part, the overlap a [length] (> 0 in contact), the unit normal n from the wall into the
    particle, the axial fraction xi of the reaction's weights (1 - xi, xi) on A and B, and the
    lever l from the axial point A + xi (B - A) to the wall point."""
    if part == 0:
        if rho <= 0.0 or s < 0.0 or s > length:
            return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        inv = 1.0 / rho
        ex = rx * inv
        ey = ry * inv
        ez = rz * inv
        return (True, r + rho - big_r, -ex, -ey, -ez, s / length,
                big_r * ex, big_r * ey, big_r * ez)
    if rho > big_r:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if part == 1:
        return True, r - s, ux, uy, uz, 0.0, rx, ry, rz
    return True, r - (length - s), -ux, -uy, -uz, 1.0, rx, ry, rz


@step_kernel
def locate_parts(x, na, nb, params, c, px, py, pz, r, out):
    """The three parts' rows (valid, a, n, xi, l) for a sphere at p of radius r in cylinder
    ``c`` (radius ``params[c, 0]``) with axis nodes ``na``, ``nb`` (x3dpd.geometry.shapes)."""
    length, ux, uy, uz, s, rx, ry, rz, rho = _cylinder_frame(x, na, nb, px, py, pz)
    big_r = params[c, 0]
    for part in range(CYLINDER_PARTS):
        ok, a, nx, ny, nz, xi, lx, ly, lz = _locate_on_cylinder(
            part, r, big_r, length, ux, uy, uz, s, rx, ry, rz, rho)
        out[part, 0] = 1.0 if ok else 0.0
        out[part, 1] = a
        out[part, 2] = nx
        out[part, 3] = ny
        out[part, 4] = nz
        out[part, 5] = xi
        out[part, 6] = lx
        out[part, 7] = ly
        out[part, 8] = lz


@step_kernel
def clear_of(x, na, nb, params, c, px, py, pz, r):
    """True when no part of cylinder ``c`` touches the sphere: the overlaps of
    :func:`locate_parts`, computed from the same frame by the same operations (so the same
    bits), r + |rho| - R, r - s and r - (L - s), are all <= 0 (x3dpd.geometry.shapes)."""
    length, _, _, _, s, _, _, _, rho = _cylinder_frame(x, na, nb, px, py, pz)
    return r + rho - params[c, 0] <= 0.0 and r - s <= 0.0 and r - (length - s) <= 0.0


def cylinder_coordinates(points: np.ndarray, a: np.ndarray, b: np.ndarray
                         ) -> tuple[np.ndarray, np.ndarray, float]:
    """Axial coordinate s and radial distance |rho| of ``points`` (N, 3) in the cylinder with
    axis ends ``a``, ``b``; returns (s, rho, L) [length]."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    a = np.asarray(a, dtype=np.float64)
    axis = np.asarray(b, dtype=np.float64) - a
    length = float(np.linalg.norm(axis))
    u = axis / length
    d = points - a
    s = d @ u
    rho = np.linalg.norm(d - s[:, None] * u[None, :], axis=1)
    return s, rho, length


def cylinder_clearance(points: np.ndarray, radii: np.ndarray, a: np.ndarray, b: np.ndarray,
                       big_r: float) -> tuple[np.ndarray, np.ndarray]:
    """Gap of each sphere to the nearest wall part of the cylinder [length] (negative: it
    overlaps the wall by that much) and whether its centre lies inside the cylinder."""
    s, rho, length = cylinder_coordinates(points, a, b)
    wall = np.minimum(np.minimum(big_r - rho, s), length - s)
    inside = (rho <= big_r) & (s >= 0.0) & (s <= length)
    return wall - np.asarray(radii, dtype=np.float64), inside


def cylinder_mesh(a, b, big_r: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A closed triangulated cylinder: ``n`` facets around, vertices on the radius (so the
    facets lie inside the analytic wall by at most the sagitta R (1 - cos(pi/n))) and a fan of
    ``n`` triangles on each cap. Returns (vertices (2n + 2, 3), triangles (4n, 3) of vertex
    indices): rings at A (0..n-1) and B (n..2n-1), then the cap centres A (2n) and B (2n+1)."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    u = (b - a) / np.linalg.norm(b - a)
    helper = np.eye(3)[int(np.argmin(np.abs(u)))]
    e1 = np.cross(u, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    phi = 2.0 * np.pi * np.arange(n) / n
    ring = big_r * (np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2)
    verts = np.concatenate([a + ring, b + ring, a[None, :], b[None, :]])
    k = np.arange(n)
    nxt = (k + 1) % n
    side = np.concatenate([np.stack([k, nxt, n + k], axis=1),
                           np.stack([nxt, n + nxt, n + k], axis=1)])
    caps = np.concatenate([np.stack([np.full(n, 2 * n), nxt, k], axis=1),
                           np.stack([np.full(n, 2 * n + 1), n + k, n + nxt], axis=1)])
    return verts, np.concatenate([side, caps]).astype(np.int64)


def _length(ends) -> float:
    return float(np.linalg.norm(np.asarray(ends[1], float) - np.asarray(ends[0], float)))


def _extent(ends, params) -> tuple[np.ndarray, np.ndarray]:
    """Bounding box: the two end discs (a disc of radius R normal to the unit axis u reaches
    R sqrt(1 - u_k^2) along axis k)."""
    a, b = np.asarray(ends[0], float), np.asarray(ends[1], float)
    u = (b - a) / np.linalg.norm(b - a)
    reach = float(params[0]) * np.sqrt(np.maximum(1.0 - u * u, 0.0))
    return np.minimum(a, b) - reach, np.maximum(a, b) + reach


def _problem(ends, params) -> str | None:
    if not _length(ends) > 0.0:
        return "coincide: the cylinder has no length"
    return None


SHAPE = Shape(
    name="cylinder", card="CYLINDER", node_fields=("NODE_A", "NODE_B"), param_fields=("RADIUS",),
    part_names=PART_NAMES, locate_parts=locate_parts,
    clearance=lambda points, radii, ends, params: cylinder_clearance(
        points, radii, ends[0], ends[1], float(params[0])),
    volume=lambda ends, params: math.pi * float(params[0]) ** 2 * _length(ends),
    extent=_extent,
    mesh=lambda ends, params, n: cylinder_mesh(ends[0], ends[1], float(params[0]), n),
    describe=lambda ends, params: f"radius {float(params[0]):g}, length {_length(ends):.6g}",
    problem=_problem, clear_of=clear_of,
    doc="a closed circular cylinder: curved wall and two flat end caps (Sections 5-6, 9-10)")
