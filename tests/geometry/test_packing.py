"""Sphere packings in a closed triangulated cavity (x3dpd.geometry.packing) against counts and
distances computed here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.geometry.packing import lattice, pack, points_inside, triangle_distances

_CORNERS = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    dtype=float,
)
_TRIS = [
    (0, 1, 2),
    (0, 2, 3),
    (4, 6, 5),
    (4, 7, 6),
    (0, 5, 1),
    (0, 4, 5),
    (3, 2, 6),
    (3, 6, 7),
    (0, 3, 7),
    (0, 7, 4),
    (1, 5, 6),
    (1, 6, 2),
]


def box(size):
    return (_CORNERS * np.asarray(size, float))[np.array(_TRIS)]


def octahedron(r):
    v = np.array([[r, 0, 0], [-r, 0, 0], [0, r, 0], [0, -r, 0], [0, 0, r], [0, 0, -r]], float)
    faces = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    return v[np.array(faces)]


def test_distances_and_inside_against_a_box():
    rng = np.random.default_rng(1)
    size = np.array([2.0, 1.0, 3.0])
    pts = rng.uniform(-0.5, 3.5, size=(2000, 3))
    inside = np.all((pts > 0) & (pts < size), axis=1)
    np.testing.assert_array_equal(points_inside(pts, box(size)), inside)
    # inside a box the nearest wall is the nearest face plane
    d_in = np.minimum(pts, size - pts).min(axis=1)
    np.testing.assert_allclose(
        triangle_distances(pts[inside], box(size)), d_in[inside], rtol=1e-12, atol=1e-12
    )
    # outside: distance to the box (clamped point)
    out = ~inside
    d_out = np.linalg.norm(pts[out] - np.clip(pts[out], 0, size), axis=1)
    np.testing.assert_allclose(
        triangle_distances(pts[out], box(size)), d_out, rtol=1e-12, atol=1e-12
    )


@pytest.mark.parametrize("packing", ["cubic", "hcp", "random"])
def test_every_sphere_fits_and_none_overlap(packing):
    r, gap = 0.05, 0.002
    tri = octahedron(1.0)
    n = 80 if packing == "random" else None  # "as many as fit" is slow for random
    pos = pack(tri, r, n, packing=packing, gap=gap, seed=3)
    assert pos.shape[0] == 80 if packing == "random" else pos.shape[0] > 200
    assert np.all(points_inside(pos, tri))
    assert triangle_distances(pos, tri).min() >= r + gap - 1e-12
    d = np.linalg.norm(pos[:, None] - pos[None], axis=-1) + np.eye(pos.shape[0]) * 10
    assert d.min() >= 2 * r + gap - 1e-12


def test_cubic_count_in_a_box_is_the_lattice_count():
    """A box 1 x 1 x 1, R = 0.1, no gap: floor((1 - 2R) / 2R) + 1 = 5 per axis -> 125."""
    pos = pack(box((1.0, 1.0, 1.0)), 0.1, None, packing="cubic")
    assert pos.shape[0] == 125


def test_hcp_is_denser_than_cubic_and_close_to_its_density():
    """In a box many diameters wide the HCP fraction approaches pi / sqrt(18) = 0.7405 (walls
    cost a layer of half-empty cells: at 10 diameters about 25 %); cubic approaches pi/6."""
    r = 0.05
    size = 1.0
    n_hcp = pack(box((size,) * 3), r, None, packing="hcp").shape[0]
    n_cub = pack(box((size,) * 3), r, None, packing="cubic").shape[0]
    phi_hcp = n_hcp * 4 / 3 * math.pi * r**3 / size**3
    phi_cub = n_cub * 4 / 3 * math.pi * r**3 / size**3
    assert phi_cub == pytest.approx(math.pi / 6, rel=1e-12)  # 10 x 10 x 10 exactly
    assert n_hcp > 1.2 * n_cub
    assert 0.75 * math.pi / math.sqrt(18) < phi_hcp < math.pi / math.sqrt(18)


def test_lowest_layer_first_and_n_respected():
    pos = pack(box((1.0, 1.0, 1.0)), 0.1, 30, packing="cubic", stack_axis=1)
    assert pos.shape[0] == 30
    assert np.all(np.diff(np.round(pos[:, 1], 9)) >= 0)  # y never decreases
    assert np.isclose(pos[:25, 1], 0.1).all()  # the floor layer is full first


def test_hcp_lattice_spacing():
    p = 0.1
    g = lattice((0, 0, 0), (1, 1, 1), p, "hcp")
    d = np.linalg.norm(g[:, None] - g[None], axis=-1) + np.eye(g.shape[0])
    assert d.min() == pytest.approx(p, rel=1e-12)  # 12 neighbours at exactly the pitch
    inner = np.all((g > 0.3) & (g < 0.7), axis=1)
    counts = (np.abs(d[inner] - p) < 1e-9).sum(axis=1)
    assert np.all(counts == 12)
