"""The analytic capsule (x3dpd.geometry.capsule) against its closed form: a sphere put at a
known place in a tilted capsule -- over the cylindrical part, beyond either cap centre, on the
axis -- and the overlap, normal, reaction weight and lever the compiled locator must report;
the clearance of the pre-run checks; the triangulated capsule of the viewers and tests (on the
wall, closed, wound outwards, within the facet error of the wall); the shape's volume and
bounding box."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from x3dpd.geometry.capsule import (
    SHAPE,
    capsule_clearance,
    capsule_mesh,
    capsule_outline,
    locate_parts,
)

A = np.array([1.0, -2.0, 0.5])
U = np.array([2.0, 1.0, -2.0]) / 3.0  # unit axis, tilted
E = np.array([1.0, -2.0, 0.0]) / math.sqrt(5.0)  # unit, perpendicular to U
F = np.cross(U, E)  # completes the frame
LENGTH = 0.8
B = A + LENGTH * U
BIG_R = 0.3
R = 0.05
#: Rounding of the locator's few products, one square root and one division on numbers of
#: order 1 (coordinates up to 2): a few ulp, 1e-15; 1e-13 leaves two orders of room and is
#: still far below any length in the scene (the smallest overlap tested is 2e-3).
TOL = 1e-13


def _locate(p, a=A, b=B):
    """The locator's row (valid, a, n, xi, l) for a sphere of radius R at p in the capsule
    with cap centres a, b (nodes 0, 1) of radius BIG_R; the row starts as NaN so that an
    unwritten field shows."""
    x = np.array([a, b], dtype=np.float64)
    params = np.array([[BIG_R]])
    out = np.full((1, 9), np.nan)
    locate_parts(x, 0, 1, params, 0, float(p[0]), float(p[1]), float(p[2]), R, out)
    row = out[0]
    return row[0], row[1], row[2:5], row[5], row[6:9]


def _unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def test_sphere_over_the_cylindrical_part():
    """Centre p = A + s U + rho E with 0 < s < L: the nearest axis point is A + s U, so
    a = r + rho - R, n = -E, xi = s/L and l = R E; the reaction point (1 - xi) A + xi B + l is
    the wall point A + s U + R E."""
    for s, rho in [(0.35, BIG_R - R + 0.002), (0.01, BIG_R - R - 0.01), (0.79, 0.1)]:
        valid, a, n, xi, lever = _locate(A + s * U + rho * E)
        assert valid == 1.0
        assert a == pytest.approx(R + rho - BIG_R, abs=TOL)
        np.testing.assert_allclose(n, -E, atol=TOL)
        assert xi == pytest.approx(s / LENGTH, abs=TOL)
        np.testing.assert_allclose(lever, BIG_R * E, atol=TOL)
        np.testing.assert_allclose((1 - xi) * A + xi * B + lever, A + s * U + BIG_R * E, atol=TOL)


@pytest.mark.parametrize("end", ["A", "B"])
def test_sphere_beyond_either_cap_centre(end):
    """Centre p = C + d w with C the cap centre (A or B) and w a unit vector pointing beyond
    it (w . U < 0 at A, > 0 at B), off the axis: the nearest segment point is C itself, so
    a = r + d - R, n = -(p - C)/|p - C| = -w, xi = 0 at A and 1 at B, l = R w. The first
    distance overlaps the hemisphere by 3e-3 -- a flat cap at C (the cylinder's) would have
    reported r - d |w . U| instead."""
    centre, sign, xi_want = (A, -1.0, 0.0) if end == "A" else (B, 1.0, 1.0)
    for w in (_unit(sign * 0.6 * U + 0.8 * E), _unit(sign * U + 0.3 * E - 0.5 * F), sign * U):
        for d in (BIG_R - R + 0.003, 0.1):
            p = centre + d * w
            valid, a, n, xi, lever = _locate(p)
            assert valid == 1.0
            assert a == pytest.approx(R + d - BIG_R, abs=TOL)
            np.testing.assert_allclose(n, -(p - centre) / np.linalg.norm(p - centre), atol=TOL)
            assert xi == xi_want
            np.testing.assert_allclose(lever, BIG_R * w, atol=TOL)


def test_centre_on_the_axis_has_no_direction_to_the_wall():
    """On the segment (at either end, and between) the wall is equally far in every direction:
    the row is marked not valid. The axis here, B - A = (0.5, 0.25, -0.5) (the tilted U, length
    0.75), and the points on it are exact binary fractions, so the centre lies on the segment
    exactly (a rounded point beside it gets an arbitrary direction and overlap r - R < 0)."""
    b = A + np.array([0.5, 0.25, -0.5])
    for t in (0.0, 0.25, 0.5, 1.0):
        valid, *_ = _locate(A + t * (b - A), b=b)
        assert valid == 0.0
    # and just beside it, a valid row pointing away from the nearest axis point
    valid, a, n, xi, _ = _locate(A + 0.5 * (b - A) + 1e-3 * E, b=b)
    assert valid == 1.0 and a == pytest.approx(R + 1e-3 - BIG_R, abs=TOL)
    assert xi == pytest.approx(0.5, abs=TOL)
    np.testing.assert_allclose(n, -E, atol=1e-12)


def test_coinciding_cap_centres_make_a_spherical_cavity():
    """A = B: every point within R of A, so a = r + d - R, n = -w, xi = 0, l = R w for a
    centre at A + d w in any direction w."""
    for w in (E, -U, _unit(U + E + F), _unit([0.3, -0.2, 0.9])):
        for d in (BIG_R - R + 0.004, 0.17):
            valid, a, n, xi, lever = _locate(A + d * w, a=A, b=A)
            assert valid == 1.0
            assert a == pytest.approx(R + d - BIG_R, abs=TOL)
            np.testing.assert_allclose(n, -w, atol=TOL)
            assert xi == 0.0
            np.testing.assert_allclose(lever, BIG_R * w, atol=TOL)
    valid, *_ = _locate(A, a=A, b=A)
    assert valid == 0.0


def test_clearance_of_spheres():
    """gap = R - dist - r with dist the centre's distance to the segment (put there by
    construction), inside while dist <= R: over the cylindrical part, beyond B on the axis
    (outside a flat-capped cylinder, inside the capsule), beyond A off the axis, in the wall,
    and outside the rounded end."""
    w = _unit(-0.6 * U + 0.8 * E)
    cases = [
        (A + 0.4 * U + 0.1 * E, 0.1),
        (B + 0.2 * U, 0.2),
        (A + 0.25 * w, 0.25),
        (B + (BIG_R - R + 0.01) * _unit(U - F), BIG_R - R + 0.01),
        (A + (BIG_R + 0.01) * w, BIG_R + 0.01),
    ]
    pts = np.array([p for p, _ in cases])
    dist = np.array([d for _, d in cases])
    gap, inside = capsule_clearance(pts, np.full(len(cases), R), A, B, BIG_R)
    np.testing.assert_allclose(gap, BIG_R - dist - R, atol=TOL)
    assert inside.tolist() == [True, True, True, True, False]
    # the same through the shape's description (the pre-run checks call this one)
    gap2, inside2 = SHAPE.clearance(pts, np.full(len(cases), R), np.stack([A, B]), (BIG_R,))
    np.testing.assert_array_equal(gap2, gap)
    np.testing.assert_array_equal(inside2, inside)


def test_volume_and_extent():
    """Volume pi R^2 L + 4/3 pi R^3 (a cylinder and a ball); bounding box that of the two end
    balls, min(A, B) - R .. max(A, B) + R per coordinate (a capsule is the segment swept by a
    ball, so this box is tight). Both are a few operations on numbers of order 1."""
    ends = np.stack([A, B])
    vol = math.pi * BIG_R**2 * LENGTH + 4.0 / 3.0 * math.pi * BIG_R**3
    assert SHAPE.volume(ends, (BIG_R,)) == pytest.approx(vol, rel=1e-14)
    lo, hi = SHAPE.extent(ends, (BIG_R,))
    want_lo = [min(A[k], B[k]) - BIG_R for k in range(3)]
    want_hi = [max(A[k], B[k]) + BIG_R for k in range(3)]
    np.testing.assert_allclose(lo, want_lo, atol=TOL)
    np.testing.assert_allclose(hi, want_hi, atol=TOL)
    # a sphere: volume 4/3 pi R^3, box A +- R
    assert SHAPE.volume(np.stack([A, A]), (BIG_R,)) == pytest.approx(
        4.0 / 3.0 * math.pi * BIG_R**3, rel=1e-14
    )
    lo, hi = SHAPE.extent(np.stack([A, A]), (BIG_R,))
    np.testing.assert_allclose(lo, A - BIG_R, atol=TOL)
    np.testing.assert_allclose(hi, A + BIG_R, atol=TOL)


# --- the triangulated capsule --------------------------------------------------------------


def _segment_distance(points, a, b):
    """Distance of points (N, 3) to the segment a-b (closed form, written for the test)."""
    u = b - a
    uu = float(u @ u)
    t = np.clip((points - a) @ u / uu, 0.0, 1.0) if uu > 0 else np.zeros(len(points))
    return np.linalg.norm(points - a - t[:, None] * u, axis=1)


def _capsule_volume(big_r, length):
    return math.pi * big_r**2 * length + 4.0 / 3.0 * math.pi * big_r**3


def facet_error(big_r: float, n: int) -> float:
    """The claimed largest depth of the triangulated capsule's facets below the wall:
    R (1 - cos(pi/n) cos(pi/(4 m))), m = max(2, n // 4) latitude rings per hemisphere (the
    circumscribed cap of a cell spanning 2 pi/n around and pi/(2 m) in latitude)."""
    m = max(2, n // 4)
    return big_r * (1.0 - math.cos(math.pi / n) * math.cos(math.pi / (4 * m)))


def _mesh_checks(a, b, n, degenerate_ok=False):
    verts, tris = capsule_mesh(a, b, BIG_R, n)
    length = float(np.linalg.norm(b - a))
    # every vertex on the wall
    np.testing.assert_allclose(_segment_distance(verts, a, b), BIG_R, atol=1e-12)
    # closed and consistently oriented: every directed edge once, and its reverse once
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    fwd = {tuple(e) for e in edges.tolist()}
    assert len(fwd) == edges.shape[0]
    assert all((j, i) in fwd for i, j in fwd)
    assert len(np.unique(tris)) == len(verts)  # no stray vertex
    p0, p1, p2 = (verts[tris[:, k]] for k in range(3))
    normal = np.cross(p1 - p0, p2 - p0)
    area = np.linalg.norm(normal, axis=1)
    # enclosed volume (divergence theorem about a; positive when wound outwards)
    volume = np.einsum("ij,ij->i", p0 - a, np.cross(p1 - a, p2 - a)).sum() / 6.0
    if degenerate_ok:  # leave zero-area triangles out of the facet-error check only
        keep = area > 1e-14
        p0, normal, area = p0[keep], normal[keep], area[keep]
        tris = tris[keep]
    assert area.min() > 0.0  # no degenerate triangle
    normal /= area[:, None]
    # Facet error, rigorously: a facet's points are no nearer the segment than its plane is
    # to the cap centre it surrounds (facets with every corner beyond A, or beyond B) or to
    # the axis line (the facets between the equators, parallel to the axis). So R minus that
    # plane distance bounds each facet's depth below the wall; it must not exceed the claim.
    u = (b - a) / length if length > 0 else np.array([1.0, 0.0, 0.0])
    z = np.stack([(verts[tris[:, k]] - a) @ u for k in range(3)], axis=1)
    slack = 1e-12
    at_a = z.max(axis=1) <= slack
    at_b = z.min(axis=1) >= length - slack
    middle = ~(at_a | at_b)
    depth = np.empty(len(tris))
    depth[at_a] = BIG_R - np.abs(np.einsum("ij,ij->i", normal[at_a], p0[at_a] - a))
    depth[at_b] = BIG_R - np.abs(np.einsum("ij,ij->i", normal[at_b], p0[at_b] - b))
    if middle.any():
        np.testing.assert_allclose(normal[middle] @ u, 0.0, atol=1e-12)
        depth[middle] = BIG_R - np.abs(np.einsum("ij,ij->i", normal[middle], p0[middle] - a))
    delta = facet_error(BIG_R, n)
    assert depth.max() <= delta + 1e-12, (depth.max(), delta)
    assert depth.max() > 0.9 * delta  # the claim is close: the solver test relies on it
    return volume, delta, length


@pytest.mark.parametrize("n", [8, 16, 33, 64, 128])
def test_triangulated_capsule_is_closed_on_the_wall_and_within_the_facet_error(n):
    """Every vertex at distance R from the segment (to 1e-12: products and a square root on
    numbers of order 1); every edge in exactly two triangles, traversed in opposite ways (a
    closed, consistently oriented surface); no facet deeper below the wall than the claimed
    facet error delta; and the enclosed volume between the capsules of radius R - delta and
    R: the facets, inside the convex capsule K, leave out only points within delta of its
    wall (the distance to K's wall is concave on K, so a segment from the axis to a point
    outside the mesh crosses the mesh where that distance is at most delta), i.e. at most
    the shell vol(K) - vol(K shrunk by delta)."""
    volume, delta, length = _mesh_checks(A, B, n)
    assert _capsule_volume(BIG_R - delta, length) < volume < _capsule_volume(BIG_R, length)


def test_triangulated_sphere_when_the_cap_centres_coincide():
    """A = B: the same checks for the spherical cavity (the mesh has no cylindrical part),
    but for its zero-area triangles (see the next test)."""
    volume, delta, _ = _mesh_checks(A, A.copy(), 24, degenerate_ok=True)
    assert _capsule_volume(BIG_R - delta, 0.0) < volume < _capsule_volume(BIG_R, 0.0)


def test_triangulated_sphere_has_no_degenerate_triangles():
    """A = B: a sphere's triangulation needs one equator ring, not two coinciding ones; a
    zero-area triangle has no normal (the deck reader refuses it, so the spherical capsule
    cannot be written as CONTACT triangles)."""
    verts, tris = capsule_mesh(A, A.copy(), BIG_R, 24)
    p0, p1, p2 = (verts[tris[:, k]] for k in range(3))
    assert np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1).min() > 1e-6


def test_triangulated_capsule_volume_converges_from_below():
    """The volume deficit pi R^2 L + 4/3 pi R^3 - V(n) stays positive and shrinks as n grows
    -- as delta ~ 1/n^2: quadrupling n divides it by more than 10 (16 for the asymptotic
    1/n^2; the bound above already holds it under the shell of depth delta)."""
    exact = _capsule_volume(BIG_R, LENGTH)
    deficits = []
    for n in (8, 16, 32, 64, 128):
        volume, _, _ = _mesh_checks(A, B, n)
        deficits.append(exact - volume)
    assert all(d > 0 for d in deficits)
    assert all(d1 < d0 for d0, d1 in itertools.pairwise(deficits))
    assert deficits[2] < deficits[0] / 10 and deficits[4] < deficits[2] / 10


@pytest.mark.parametrize("length", [LENGTH, 0.0])
def test_outline_is_where_the_hemispheres_meet_the_bore(length):
    """The viewers draw a smooth capsule by the circles of radius R in the planes through A
    and B normal to the axis (one circle, the equator, for a sphere): closed loops of mesh
    edges whose vertices lie on those circles (to rounding, 1e-12)."""
    n = 24
    b = A + length * U
    verts, tris = capsule_mesh(A, b, BIG_R, n)
    edges = capsule_outline(np.stack([A, b]), (BIG_R,), n)
    circles = 2 if length > 0.0 else 1
    axis = U if length > 0.0 else np.array([1.0, 0.0, 0.0])  # a sphere's mesh turns about x
    assert edges.shape == (circles * n, 2)
    mesh_edges = {frozenset(e) for tri in tris for e in itertools.combinations(tri, 2)}
    assert all(frozenset(e) in mesh_edges for e in edges.tolist())
    for centre in [A, b] if length > 0.0 else [A]:
        on = [e for e in edges if abs((verts[e[0]] - centre) @ axis) < 1e-12]
        assert len(on) == n  # a whole loop per circle
        pts = verts[np.unique(np.array(on))]
        np.testing.assert_allclose(np.linalg.norm(pts - centre, axis=1), BIG_R, atol=1e-12)
        np.testing.assert_allclose((pts - centre) @ axis, 0.0, atol=1e-12)
        assert (
            sorted(
                np.bincount(np.array(on).ravel(), minlength=verts.shape[0])[
                    np.unique(np.array(on))
                ].tolist()
            )
            == [2] * n
        )  # each vertex on two edges: a loop
