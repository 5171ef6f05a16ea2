"""The analytic cylinder's locator (x3dpd.geometry.cylinder) against its closed form: a sphere
put at a known axial coordinate s and radial offset rho in a tilted cylinder, and the gap,
normal, reaction weights and lever each wall part must report; and the triangulated cylinder
of the viewers and tests (its facets lie within the sagitta of the analytic wall)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.geometry.cylinder import (
    _cylinder_frame,
    _locate_on_cylinder,
    cylinder_clearance,
    cylinder_mesh,
)

A = np.array([1.0, -2.0, 0.5])
U = np.array([2.0, 1.0, -2.0]) / 3.0  # unit axis, tilted
E = np.array([1.0, -2.0, 0.0]) / math.sqrt(5.0)  # unit, perpendicular to U
LENGTH = 0.8
BIG_R = 0.3
R = 0.05
#: Rounding of the frame's few products and one square root on numbers of order 1.
TOL = 1e-13


def _locate(s: float, rho: float):
    """Every part's answer for a sphere at A + s U + rho E (nodes 0, 1 = A, B)."""
    x = np.array([A, A + LENGTH * U])
    p = A + s * U + rho * E
    frame = _cylinder_frame(x=x, na=0, nb=1, px=p[0], py=p[1], pz=p[2])
    length, ux, uy, uz, s_, rx, ry, rz, rho_ = frame
    assert length == pytest.approx(LENGTH, abs=TOL)
    assert s_ == pytest.approx(s, abs=TOL) and rho_ == pytest.approx(abs(rho), abs=TOL)
    out = []
    for part in range(3):
        ok, a, nx, ny, nz, xi, lx, ly, lz = _locate_on_cylinder(
            part=part,
            r=R,
            big_r=BIG_R,
            length=length,
            ux=ux,
            uy=uy,
            uz=uz,
            s=s_,
            rx=rx,
            ry=ry,
            rz=rz,
            rho=rho_,
        )
        out.append((ok, a, np.array([nx, ny, nz]), xi, np.array([lx, ly, lz])))
    return out


def test_sphere_touching_the_curved_wall_and_nothing_else():
    s, rho = 0.35, BIG_R - R + 0.002  # overlaps the curved wall by 0.002
    curved, cap_a, cap_b = _locate(s, rho)
    ok, a, n, xi, lever = curved
    assert ok
    assert a == pytest.approx(0.002, abs=TOL)
    np.testing.assert_allclose(n, -E, atol=TOL)  # from the wall back towards the axis
    assert xi == pytest.approx(s / LENGTH, abs=TOL)
    np.testing.assert_allclose(lever, BIG_R * E, atol=TOL)
    # the reaction's point: (1 - xi) A + xi B + lever is the wall point A + s U + R E
    wall_point = (1 - xi) * A + xi * (A + LENGTH * U) + lever
    np.testing.assert_allclose(wall_point, A + s * U + BIG_R * E, atol=TOL)
    # both caps are far: negative overlap r - s and r - (L - s)
    assert cap_a[0] and cap_a[1] == pytest.approx(R - s, abs=TOL)
    assert cap_b[0] and cap_b[1] == pytest.approx(R - (LENGTH - s), abs=TOL)


def test_sphere_in_the_rim_corner_touches_the_wall_and_a_cap():
    s, rho = R - 0.001, BIG_R - R + 0.003
    curved, cap_a, cap_b = _locate(s, rho)
    assert curved[0] and curved[1] == pytest.approx(0.003, abs=TOL)
    ok, a, n, xi, lever = cap_a
    assert ok and a == pytest.approx(0.001, abs=TOL)
    np.testing.assert_allclose(n, U, atol=TOL)  # the cap at A pushes along +axis
    assert xi == 0.0
    np.testing.assert_allclose(lever, rho * E, atol=TOL)  # from A to the wall point A + rho E
    assert cap_b[1] < 0.0


def test_sphere_against_the_far_cap():
    s, rho = LENGTH - R + 0.004, 0.1
    _, _, (ok, a, n, xi, lever) = _locate(s, rho)
    assert ok and a == pytest.approx(0.004, abs=TOL)
    np.testing.assert_allclose(n, -U, atol=TOL)
    assert xi == 1.0
    np.testing.assert_allclose(lever, 0.1 * E, atol=TOL)


def test_parts_out_of_reach_are_not_valid():
    # beyond the caps' axial range the curved wall does not apply; outside the radius the caps
    curved, _, _ = _locate(-0.01, BIG_R - R)
    assert not curved[0]
    curved, _, _ = _locate(LENGTH + 0.01, BIG_R - R)
    assert not curved[0]
    _, cap_a, cap_b = _locate(0.01, BIG_R + 0.001)
    assert not cap_a[0] and not cap_b[0]


def test_clearance_of_spheres():
    b = A + LENGTH * U
    pts = np.array(
        [
            A + 0.4 * U + 0.1 * E,  # nearest: curved wall at 0.2
            A + 0.02 * U,  # on the axis, 0.02 from cap A
            A + 0.4 * U + (BIG_R + 0.01) * E,
        ]
    )  # centre outside
    gap, inside = cylinder_clearance(pts, np.full(3, R), A, b, BIG_R)
    np.testing.assert_allclose(gap, [0.2 - R, 0.02 - R, -0.01 - R], atol=TOL)
    assert inside.tolist() == [True, True, False]


@pytest.mark.parametrize("n", [8, 33, 128])
def test_triangulated_cylinder_lies_within_the_sagitta(n):
    """Every vertex on the radius (or a cap centre), every side facet's plane at R cos(pi/n)
    from the axis (the sagitta R (1 - cos(pi/n)) is the facet error), the
    surface closed (each edge in two triangles, opposite ways) and wound outwards (its signed
    volume is the prism's, pi R^2 L scaled by the polygon's area ratio)."""
    b = A + LENGTH * U
    verts, tris = cylinder_mesh(A, b, BIG_R, n)
    _, rho = _axial_radial(verts, A, b)
    np.testing.assert_allclose(rho[: 2 * n], BIG_R, atol=TOL)
    np.testing.assert_allclose(rho[2 * n :], 0.0, atol=TOL)
    # the side facets (the first 2n triangles): planes parallel to the axis at R cos(pi/n)
    p0, p1, p2 = (verts[tris[: 2 * n, k]] for k in range(3))
    normal = np.cross(p1 - p0, p2 - p0)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    np.testing.assert_allclose(normal @ U, 0.0, atol=TOL)
    np.testing.assert_allclose(
        np.abs(np.einsum("ij,ij->i", normal, p0 - A)), BIG_R * math.cos(math.pi / n), atol=TOL
    )
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    fwd = {tuple(e) for e in edges.tolist()}
    assert len(fwd) == edges.shape[0] and all((b_, a_) in fwd for a_, b_ in fwd)
    p0, p1, p2 = (verts[tris[:, k]] for k in range(3))
    volume = np.einsum("ij,ij->i", p0, np.cross(p1, p2)).sum() / 6.0
    polygon = 0.5 * n * BIG_R**2 * math.sin(2 * math.pi / n)
    assert volume == pytest.approx(polygon * LENGTH, rel=1e-12)


def _axial_radial(points, a, b):
    u = (b - a) / np.linalg.norm(b - a)
    d = points - a
    s = d @ u
    return s, np.linalg.norm(d - s[:, None] * u, axis=1)
