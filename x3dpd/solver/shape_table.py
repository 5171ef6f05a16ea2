"""The analytic walls' static contact list, in the form the step kernels take
(x3dpd.solver.bundles.Shapes): built once from a model with :func:`shape_table`."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


def _f64(a):
    return np.ascontiguousarray(a, dtype=np.float64)


def _i64(a):
    return np.ascontiguousarray(a, dtype=np.int64)


class ShapeTable(NamedTuple):
    """The analytic walls (W of them; x3dpd.geometry.shapes) and their static contact list:
    every particle of a wall's cavity against each of the wall's parts (K (particle, wall)
    pairs; pair k owns the state rows row[k] .. row[k] + parts[wall[k]] - 1)."""

    kind: np.ndarray          # (W,) shape kind (index in SHAPES)
    nodes: np.ndarray         # (W, 2) node indices (A, B)
    params: np.ndarray        # (W, P) lengths [length]
    parts: np.ndarray         # (W,) contact entities (parts) of each wall
    entity: np.ndarray        # (W,) number of its first part among all walls' parts
    particle: np.ndarray      # (K,) particle of each pair
    wall: np.ndarray          # (K,) wall of each pair
    row: np.ndarray           # (K,) first state row of each pair
    row_particle: np.ndarray  # (R,) particle of each state row


def shape_table(model, pcav: np.ndarray) -> ShapeTable:
    """The analytic walls of ``model`` and every (particle of its cavity, wall) pair, pairs in
    wall order (a cylinder's pair k owns rows 3 k .. 3 k + 2, as before shapes were
    registered, so restart dumps carry over)."""
    from x3dpd.geometry.shapes import SHAPES

    kind = _i64(model.shape_kind)
    parts = np.array([SHAPES[k].parts for k in kind], dtype=np.int64)
    entity = np.cumsum(parts) - parts
    pairs = [(p, w) for w in range(kind.shape[0])
             for p in np.flatnonzero(pcav == model.shape_cavity[w])]
    pairs = np.array(pairs, dtype=np.int64).reshape(-1, 2)
    per_pair = parts[pairs[:, 1]]
    row = np.cumsum(per_pair) - per_pair
    return ShapeTable(kind, _i64(model.shape_nodes).reshape(-1, 2), _f64(model.shape_params),
                      parts, _i64(entity), _i64(pairs[:, 0]), _i64(pairs[:, 1]), _i64(row),
                      _i64(np.repeat(pairs[:, 0], per_pair)))
