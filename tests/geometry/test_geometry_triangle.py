"""Triangle geometry against hand-computed values and brute-force references."""

from __future__ import annotations

import numpy as np
import pytest

from x3dpd.geometry.triangle import (
    edge_distances,
    inward_signs,
    points_in_triangles,
    signed_distances,
    triangle_areas,
    triangle_normals,
    unit_normals,
)

# a 3-4-5 right triangle in the plane z = 2, wound counter-clockwise seen from +z
P0 = np.array([[0.0, 0.0, 2.0]])
P1 = np.array([[3.0, 0.0, 2.0]])
P2 = np.array([[0.0, 4.0, 2.0]])


def test_normal_and_area_of_a_right_triangle():
    np.testing.assert_array_equal(triangle_normals(P0, P1, P2), [[0.0, 0.0, 12.0]])
    np.testing.assert_array_equal(triangle_areas(P0, P1, P2), [6.0])
    np.testing.assert_array_equal(unit_normals(P0, P1, P2), [[0.0, 0.0, 1.0]])
    np.testing.assert_array_equal(unit_normals(P0, P2, P1), [[0.0, 0.0, -1.0]])
    np.testing.assert_array_equal(unit_normals(P0, P0, P1), [[0.0, 0.0, 0.0]])


def test_signed_distance_is_positive_on_the_normal_side():
    pts = np.array([[1.0, 1.0, 5.0], [10.0, -3.0, 0.5], [7.0, 7.0, 2.0]])
    d = signed_distances(pts, P0, unit_normals(P0, P1, P2))
    np.testing.assert_allclose(d, [[3.0], [-1.5], [0.0]])


def test_edge_distances_of_a_right_triangle():
    # point (1, 1): 1 from the leg y = 0, 1 from the leg x = 0, and from the hypotenuse
    # 4x + 3y = 12: (12 - 7) / 5 = 1
    d = edge_distances([[1.0, 1.0, 9.0]], P0, P1, P2)
    # order: opposite corner 0 (hypotenuse), opposite corner 1 (leg x = 0), opposite 2 (y = 0)
    np.testing.assert_allclose(d[0, 0], [1.0, 1.0, 1.0])
    d = edge_distances([[-2.0, 1.0, 0.0]], P0, P1, P2)
    np.testing.assert_allclose(d[0, 0], [(12 - (-8 + 3)) / 5.0, -2.0, 1.0])


@pytest.mark.parametrize(
    "point, tol, inside",
    [
        ((1.0, 1.0), 0.0, True),
        ((3.0, 0.0), 0.0, True),  # a corner
        ((1.5, 2.0), 0.0, True),  # on the hypotenuse: 4*1.5 + 3*2 = 12
        ((1.0, -0.1), 0.0, False),  # 0.1 below the leg y = 0
        ((1.0, -0.1), 0.1001, True),  # ... within a tolerance of 0.1
        ((1.0, -0.1), 0.0999, False),
        ((2.0, 2.0), 0.4001, True),  # (4*2 + 3*2 - 12) / 5 = 0.4 beyond the hypotenuse
        ((2.0, 2.0), 0.3999, False),
    ],
)
def test_point_in_triangle_with_an_edge_tolerance(point, tol, inside):
    pts = np.array([[point[0], point[1], -7.0]])  # the height above the plane does not matter
    assert points_in_triangles(pts, P0, P1, P2, tol)[0, 0] == inside


def test_point_in_triangle_matches_a_brute_force_area_test():
    rng = np.random.default_rng(3)
    tri = rng.normal(size=(5, 3, 3))
    pts = rng.normal(size=(200, 3))
    got = points_in_triangles(pts, tri[:, 0], tri[:, 1], tri[:, 2])
    for t in range(5):
        a, b, c = tri[t]
        n = np.cross(b - a, c - a)
        n /= np.linalg.norm(n)
        q = pts - np.outer((pts - a) @ n, n)  # projections
        s1 = np.cross(b - a, q - a) @ n
        s2 = np.cross(c - b, q - b) @ n
        s3 = np.cross(a - c, q - c) @ n
        expected = ((s1 >= 0) & (s2 >= 0) & (s3 >= 0)) | ((s1 <= 0) & (s2 <= 0) & (s3 <= 0))
        np.testing.assert_array_equal(got[:, t], expected)


def test_per_point_tolerances():
    pts = np.array([[1.0, -0.2, 0.0], [1.0, -0.2, 0.0]])
    np.testing.assert_array_equal(
        points_in_triangles(pts, P0, P1, P2, np.array([0.1, 0.3]))[:, 0], [False, True]
    )


def test_inward_signs_face_the_reference_point():
    p0 = np.vstack([P0, P0])
    p1 = np.vstack([P1, P2])
    p2 = np.vstack([P2, P1])  # the same triangle, wound both ways
    np.testing.assert_array_equal(inward_signs(p0, p1, p2, [0.0, 0.0, 5.0]), [1.0, -1.0])
    np.testing.assert_array_equal(inward_signs(p0, p1, p2, [0.0, 0.0, -5.0]), [-1.0, 1.0])
    np.testing.assert_array_equal(inward_signs(p0, p1, p2, [9.0, 9.0, 2.0]), [0.0, 0.0])
