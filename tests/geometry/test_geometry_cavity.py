"""Cavity geometry: faces, closure and enclosed volume of a box with mixed windings."""

from __future__ import annotations

import numpy as np
import pytest

from x3dpd.geometry.cavity import (
    cavity_extents,
    enclosed_volume,
    geometry_size,
    group_faces,
    merge_vertices,
    surface_edges,
)
from x3dpd.geometry.triangle import inward_signs, unit_normals

CORNERS = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    dtype=float,
)
# 0-based corners; every triangle wound with its normal pointing inward
TRIS = np.array(
    [
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
)
FLIP = [1, 2, 5, 6, 9, 10]  # half of them, one of each face's pair


def box(size=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0), flip=FLIP):
    tris = TRIS.copy()
    tris[flip, 1], tris[flip, 2] = TRIS[flip, 2], TRIS[flip, 1]
    pts = CORNERS * np.asarray(size) + np.asarray(origin)
    return pts, tris


def test_mixed_windings_get_inward_signs_from_the_centroid():
    pts, tris = box()
    s = inward_signs(pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]], pts.mean(axis=0))
    expected = np.ones(12)
    expected[FLIP] = -1.0
    np.testing.assert_array_equal(s, expected)


def test_coplanar_triangles_group_into_six_faces():
    pts, tris = box(size=(2.0, 3.0, 5.0))
    p = [pts[tris[:, k]] for k in range(3)]
    s = inward_signs(*p, pts.mean(axis=0))
    faces = group_faces(s[:, None] * unit_normals(*p), p[0], geometry_size(pts))
    np.testing.assert_array_equal(faces, np.repeat(np.arange(6), 2))


def test_opposite_normals_in_one_plane_are_different_faces():
    # two coincident triangles facing opposite ways (a thin wall seen from both sides)
    n = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.0, 0.0, 1.0]])
    p0 = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [5.0, 5.0, 1e-12]])
    np.testing.assert_array_equal(group_faces(n, p0, 1.0), [0, 1, 0])
    p0[2, 2] = 1e-6  # a parallel plane 1e-6 away is another face
    np.testing.assert_array_equal(group_faces(n, p0, 1.0), [0, 1, 2])


def _group_faces_reference(n_in, p0, size, tol):
    """The definition, literally: each triangle joins the first face (in order of appearance)
    whose first triangle's normal and plane offset are within tol (offset: tol * size)."""
    offsets = np.einsum("tk,tk->t", n_in, p0)
    face, reps = np.full(n_in.shape[0], -1), []
    for t in range(n_in.shape[0]):
        for f, r in enumerate(reps):
            if (
                np.max(np.abs(n_in[t] - n_in[r])) <= tol
                and abs(offsets[t] - offsets[r]) <= tol * size
            ):
                face[t] = f
                break
        else:
            face[t] = len(reps)
            reps.append(t)
    return face


def test_face_grouping_matches_its_definition_at_the_tolerance():
    """group_faces looks only at the neighbouring cells of side tol around a key; triangles
    whose keys differ by just under and just over tol, on both sides of cell boundaries, and
    chains a < tol < a + b (where the first-face rule decides), must group exactly as
    comparing every triangle with every face does."""
    rng = np.random.default_rng(7)
    tol, size = 1e-3, 2.0
    base = rng.normal(size=(12, 3))
    base /= np.linalg.norm(base, axis=1)[:, None]
    normals, p0 = [], []
    for n in base:
        for _ in range(8):
            step = rng.choice([0.0, 0.4, 0.7, 0.99, 1.01, 1.6]) * tol
            normals.append(n + step * rng.choice([-1.0, 1.0], size=3) * (rng.random(3) < 0.5))
            p0.append(rng.choice([0.0, 0.3, 0.999, 1.001]) * tol * size * n)
    normals, p0 = np.array(normals), np.array(p0)
    order = rng.permutation(normals.shape[0])
    normals, p0 = normals[order], p0[order]
    expected = _group_faces_reference(normals, p0, size, tol)
    assert 12 < expected.max() + 1 < normals.shape[0]  # some grouped, some apart
    np.testing.assert_array_equal(group_faces(normals, p0, size, tol), expected)


def test_extents_and_size():
    pts, _ = box(size=(2.0, 3.0, 5.0), origin=(-1.0, 0.5, 2.0))
    lo, hi = cavity_extents(pts)
    np.testing.assert_array_equal(lo, [-1.0, 0.5, 2.0])
    np.testing.assert_array_equal(hi, [1.0, 3.5, 7.0])
    assert geometry_size(pts) == 5.0


@pytest.mark.parametrize(
    "size, origin",
    [((1, 1, 1), (0, 0, 0)), ((2, 3, 5), (-1, 0.5, 2)), ((0.25, 0.25, 0.25), (0, 0, -0.125))],
)
def test_closed_box_volume_by_the_divergence_theorem(size, origin):
    pts, tris = box(size, origin)
    p = [pts[tris[:, k]] for k in range(3)]
    s = inward_signs(*p, pts.mean(axis=0))
    labels = merge_vertices(pts, geometry_size(pts))[tris]
    assert surface_edges(labels, s) == (True, True)
    assert enclosed_volume(*p, s) == pytest.approx(np.prod(size), rel=1e-14)
    # the raw windings are inconsistent, and the volume with all signs +1 is not the box's
    assert surface_edges(labels, np.ones(12)) == (True, False)


def test_open_box_is_not_closed():
    pts, tris = box()
    keep = np.arange(10)  # drop the x = 1 face
    s = inward_signs(*(pts[tris[keep, k]] for k in range(3)), pts.mean(axis=0))
    closed, consistent = surface_edges(tris[keep], s)
    assert not closed and consistent


def test_duplicate_corner_nodes_are_merged():
    """The cube deck puts distinct node ids at one corner (nodes 8 and 9, 13 and 17...)."""
    pts, tris = box()
    dup = np.vstack([pts, pts])  # every corner twice
    tris2 = tris + 8 * (np.arange(12) % 2)[:, None]  # odd triangles use the copies
    labels = merge_vertices(dup, 1.0)
    np.testing.assert_array_equal(labels[:8], labels[8:])
    s = inward_signs(*(dup[tris2[:, k]] for k in range(3)), pts.mean(axis=0))
    assert surface_edges(labels[tris2], s) == (True, True)
    assert surface_edges(tris2, s)[0] is False  # without merging it looks open
