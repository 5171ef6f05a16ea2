"""Overlapping sphere pairs (cell grid vs brute force) and sphere-over-triangle search."""

from __future__ import annotations

import numpy as np
import pytest

from x3dpd.geometry.pairs import overlapping_pairs
from x3dpd.geometry.walls import sphere_triangle_pairs


def brute_pairs(x, r, rel_tol=1e-9):
    out = []
    for i in range(len(x)):
        for j in range(i + 1, len(x)):
            d = np.linalg.norm(x[i] - x[j])
            if d < (r[i] + r[j]) * (1 - rel_tol):
                out.append((i, j, r[i] + r[j] - d))
    return out


@pytest.mark.parametrize("seed, n", [(0, 2), (1, 50), (2, 400), (3, 1000)])
def test_cell_grid_matches_brute_force(seed, n):
    rng = np.random.default_rng(seed)
    x = rng.uniform(-1.0, 1.0, size=(n, 3))
    r = rng.uniform(0.01, 0.08, size=n)
    pairs, depth = overlapping_pairs(x, r)
    expected = brute_pairs(x, r)
    assert pairs.tolist() == [[i, j] for i, j, _ in expected]
    np.testing.assert_allclose(depth, [d for _, _, d in expected], rtol=1e-12)


def test_touching_lattice_has_no_overlaps():
    g = np.arange(4) * 0.0625 + 0.03125
    x = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    pairs, _ = overlapping_pairs(x, np.full(len(x), 0.03125))
    assert pairs.shape == (0, 2)
    x[5] += [0.001, 0.0, 0.0]  # x is the slowest index: its +x neighbour is 5 + 16
    pairs, depth = overlapping_pairs(x, np.full(len(x), 0.03125))
    assert pairs.tolist() == [[5, 21]]
    np.testing.assert_allclose(depth, [0.001], rtol=1e-9)


def test_sphere_triangle_pairs_same_group_and_edge_tolerance():
    # one triangle in the plane z = 0, inward +z, group 0; the other the same, group 1
    p0 = np.array([[0.0, 0.0, 0.0]] * 2)
    p1 = np.array([[1.0, 0.0, 0.0]] * 2)
    p2 = np.array([[0.0, 1.0, 0.0]] * 2)
    n_in = np.array([[0.0, 0.0, 1.0]] * 2)
    centres = np.array([[0.2, 0.2, 0.05], [0.2, -0.05, -0.3], [0.2, 0.2, 0.5], [5.0, 5.0, 0.0]])
    group = np.array([0, 0, -1, 1])
    s, t, d = sphere_triangle_pairs(
        centres,
        group,
        p0,
        p1,
        p2,
        n_in,
        np.array([0, 1]),
        np.array([0.1, 0.1, 0.1, 0.1]),
        max_block=3,
    )
    assert list(zip(s.tolist(), t.tolist())) == [(0, 0), (1, 0)]
    np.testing.assert_allclose(d, [0.05, -0.3])
