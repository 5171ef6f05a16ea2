"""The drilled plate's locator (x3dpd.geometry.holes, HOLES card) against the cylinder's
(x3dpd.geometry.cylinder): a sphere in hole (i, j) of a plate is a sphere in the cylinder of
axis A + o -> B + o, o = p (i e1 + j e2), the cylinder's curved wall the plate's bore and its
cap nearer the centre the plate's nearer end; the plate's lever is the cylinder's plus o
(both measured from the axial point of the weights on A and B). An obviously correct slow
reference (the cylinder, itself checked against closed forms in test_cylinder.py) for the
compiled one, on plates with tilted axes."""

from __future__ import annotations

import numpy as np
import pytest

from x3dpd.geometry import cylinder, holes
from x3dpd.geometry.shapes import BY_SHAPE_NAME


def _plate(rng):
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    a = rng.uniform(-1, 1, size=3)
    length, radius, pitch = 0.51, 0.252, 0.6
    return a, a + length * u, radius, pitch


@pytest.mark.parametrize("seed", range(5))
def test_a_hole_is_the_cylinder_at_its_grid_point(seed):
    rng = np.random.default_rng(seed)
    a, b, big_r, pitch = _plate(rng)
    params = np.array([[big_r, pitch, *holes.plate_constants(np.stack([a, b]), (big_r, pitch))]])
    u, e1, e2 = holes.grid_axes(a, b)
    length = np.linalg.norm(b - a)
    out_h, out_c = np.zeros((3, 9)), np.zeros((3, 9))
    for _ in range(200):
        i, j = rng.integers(-6, 7, size=2)
        o = pitch * (i * e1 + j * e2)
        # a centre anywhere in or near the hole: across the rim (less than p / 2 from the axis:
        # nearer its own than any other) and past the ends
        s = rng.uniform(-0.05, length + 0.05)
        rho = rng.uniform(0.0, 1.15 * big_r) * (
            np.cos(t := rng.uniform(0, 6.3)) * e1 + np.sin(t) * e2
        )
        p = a + o + s * u + rho
        r = 0.25
        x = np.stack([a, b, a + o, b + o])
        holes.locate_parts(x, 0, 1, params, 0, *p, r, out_h)
        cylinder.locate_parts(x, 2, 3, np.array([[big_r]]), 0, *p, r, out_c)
        end = 1 if s <= 0.5 * length else 2
        for part, ref in ((0, 0), (1, end)):
            assert out_h[part, 0] == out_c[ref, 0]
            if out_c[ref, 0]:
                np.testing.assert_allclose(out_h[part, 1:6], out_c[ref, 1:6], atol=1e-12)
                np.testing.assert_allclose(out_h[part, 6:9], out_c[ref, 6:9] + o, atol=1e-12)


@pytest.mark.parametrize("seed", range(3))
def test_clear_of_says_clear_only_where_no_part_touches(seed):
    """``clear_of`` (the step loop skips a sphere it calls clear) against the locator: never
    clear where a part touches, down to the last bits of the bore's rim; clear wherever the
    sphere keeps more than a hair from every part (so it does skip the spheres in flight)."""
    rng = np.random.default_rng(seed)
    a, b, big_r, pitch = _plate(rng)
    params = np.array([[big_r, pitch, *holes.plate_constants(np.stack([a, b]), (big_r, pitch))]])
    u, e1, e2 = holes.grid_axes(a, b)
    length = np.linalg.norm(b - a)
    x = np.stack([a, b])
    out = np.zeros((2, 9))
    r = 0.15
    said_clear = 0
    for n in range(3000):
        i, j = rng.integers(-6, 7, size=2)
        o = pitch * (i * e1 + j * e2)
        s = rng.uniform(-0.02, length + 0.02)
        if n % 3 == 0:  # at the bore's rim: |rho| = R - r within a few units in the last place
            rim = (big_r - r) * (1.0 + rng.integers(-40, 41) * np.finfo(float).eps)
        else:
            rim = rng.uniform(0.0, 1.1 * (big_r - r))
        t = rng.uniform(0, 6.3)
        p = a + o + s * u + rim * (np.cos(t) * e1 + np.sin(t) * e2)
        holes.locate_parts(x, 0, 1, params, 0, *p, r, out)
        touching = any(out[k, 0] != 0.0 and out[k, 1] > 0.0 for k in range(2))
        clear = holes.clear_of(x, 0, 1, params, 0, *p, r)
        assert not (clear and touching), (p, out)
        far = (rim < (big_r - r) * (1 - 1e-9)) and (r * (1 + 1e-9) < s < length - r * (1 + 1e-9))
        assert clear or not far
        said_clear += clear
    assert said_clear > 300


def test_clearance_and_cells_are_each_spheres_own_hole():
    rng = np.random.default_rng(7)
    a, b, big_r, pitch = _plate(rng)
    shape = BY_SHAPE_NAME["holes"]
    u, e1, e2 = holes.grid_axes(a, b)
    ij = rng.integers(-4, 5, size=(50, 2))
    o = pitch * (ij[:, :1] * e1 + ij[:, 1:] * e2)
    p = a + o + rng.uniform(0.2, 0.3, size=(50, 1)) * u
    r = np.full(50, 0.24)
    gap, inside = shape.clearance(p, r, np.stack([a, b]), (big_r, pitch))
    for k in range(50):
        g, ok = cylinder.cylinder_clearance(p[k : k + 1], r[:1], a + o[k], b + o[k], big_r)
        assert gap[k] == pytest.approx(g[0], abs=1e-12) and inside[k] == ok[0]
    assert np.array_equal(shape.cells(p, np.stack([a, b]), (big_r, pitch)), ij)


def test_the_grid_rows_run_along_the_other_coordinate_axes():
    """An axis along y: rows along -z and -x (e1 = u x x, e2 = u x e1)."""
    u, e1, e2 = holes.grid_axes(np.zeros(3), np.array([0.0, 2.0, 0.0]))
    assert np.array_equal(u, [0, 1, 0]) and np.array_equal(e1, [0, 0, -1])
    assert np.array_equal(e2, [-1, 0, 0])


def test_holes_wider_than_the_pitch_are_a_problem():
    shape = BY_SHAPE_NAME["holes"]
    ends = np.array([[0.0, 0, 0], [0, 0.5, 0]])
    assert shape.problem(ends, (0.25, 0.6)) is None
    assert "overlap" in shape.problem(ends, (0.3, 0.6))
    assert "no length" in shape.problem(np.zeros((2, 3)), (0.25, 0.6))
