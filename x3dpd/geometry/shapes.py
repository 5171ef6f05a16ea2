"""Analytic wall shapes: what a shape module provides, and the registry of shapes.

A triangulated cavity (CONTACT card) needs no code of its own; an analytic one -- a cylinder, a
capsule, a drilled plate's holes -- is a module of ``x3dpd.geometry`` that describes itself with
a :class:`Shape` and computes, in compiled code, where a sphere touches it. Everything else is
shared:

* the deck reader makes a card of every registered shape (``SET``, its node fields, its
  positive length fields), and the writer prints it back;
* the model builder checks its nodes (distinct, moving rigidly together) and assigns its
  particles by the card's SET;
* the step loop calls the shape's ``locate_parts`` for every (particle, shape) pair and hands
  each touching part to the one contact response every wall uses (x3dpd.solver);
* ``x3dpd check``, the run-time containment check and the variable-step gap use ``clearance``;
  the viewers draw ``mesh``; the time-step estimate uses ``extent``.

A shape has up to two nodes (A and B): its wall moves rigidly with them, and the reaction on
the wall goes to them with the weights (1 - xi, xi) that the locator returns, plus a moment
l x F to node A. A one-node shape returns xi = 0.

The compiled locator
--------------------
``locate_parts(x, na, nb, params, c, px, py, pz, r, out)`` -- positions ``x`` (n, 3), the
shape's node indices ``na``, ``nb``, its parameters ``params[c, :]`` [length], the particle
centre p and radius r -- writes one row per part into ``out`` (at least (parts, 9)):

    out[part] = (valid, a, nx, ny, nz, xi, lx, ly, lz)

``valid`` 1.0 when the centre lies over the part (else 0.0), a the overlap [length] (> 0 in
contact), n the unit normal from the wall into the particle, xi the weight of node B, and
l = (lx, ly, lz) the lever from the point A + xi (B - A) to the wall point [length]. It must
allocate nothing (it runs inside the step loop) and be decorated with
``x3dpd._jit.step_kernel``.

A shape may also give ``clear_of(x, na, nb, params, c, px, py, pz, r)``, compiled the same way:
True only when no part touches the sphere (it may say False when unsure). A sphere clear of its
wall whose parts' contacts are all closed is then skipped without locating its parts (most of
a bed's spheres are away from the wall; a drilled plate's are in flight most of the time).
Every shape here gives one (tests/geometry/test_clear_of.py).

Adding a shape
--------------
Write ``x3dpd/geometry/<name>.py`` with ``SHAPE = Shape(...)`` and ``locate_parts``, then add
the module to :data:`SHAPES` below. ``x3dpd.geometry.capsule`` is a complete example.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from x3dpd.geometry import capsule, cylinder, holes
from x3dpd.geometry.shape import MAX_SHAPE_NODES, Shape

__all__ = ["SHAPES", "BY_SHAPE_NAME", "BY_SHAPE_CARD", "MAX_SHAPE_NODES", "MAX_SHAPE_PARAMS",
           "MAX_SHAPE_PARTS", "Shape",
           "analytic_wall", "kind_of"]


def _register(*modules) -> tuple[Shape, ...]:
    out = []
    for m in modules:
        shape = m.SHAPE
        if len(shape.node_fields) not in range(1, MAX_SHAPE_NODES + 1):
            raise ValueError(f"{m.__name__}: a shape has 1 to {MAX_SHAPE_NODES} nodes")
        out.append(dataclasses.replace(shape, module=m.__name__))
    names = [s.name for s in out]
    keys = [s.key for s in out]
    if len(set(names)) != len(names) or len(set(keys)) != len(keys):
        raise ValueError(f"shape names and four-letter keys must be unique: {names}, {keys}")
    return tuple(out)


#: The registered shapes; a shape's kind number is its index here (kept in restart dumps'
#: order: append new shapes at the end).
SHAPES: tuple[Shape, ...] = _register(cylinder, capsule, holes)

#: Shape by name ("cylinder"), and by card keyword ("CYLINDER").
BY_SHAPE_NAME: dict[str, Shape] = {s.name: s for s in SHAPES}
BY_SHAPE_CARD: dict[str, Shape] = {s.card: s for s in SHAPES}
#: Parameters per shape in the model's and kernels' arrays (the most any shape has: its card's
#: lengths and its constants).
MAX_SHAPE_PARAMS = max(len(s.param_fields) + s.n_constants for s in SHAPES)
#: Parts of the shape with the most (the rows of the locator's scratch).
MAX_SHAPE_PARTS = max(s.parts for s in SHAPES)


def kind_of(name: str) -> int:
    """A shape's kind number (its index in :data:`SHAPES`)."""
    return next(k for k, s in enumerate(SHAPES) if s.name == name)


def analytic_wall(kind, nodes, params, x) -> tuple[Shape, np.ndarray, np.ndarray]:
    """One analytic wall as its shape's helpers take it, from a row of the model's arrays
    (kind, the (2,) node indices, the zero-padded (P,) lengths): its shape, the positions of
    its k nodes in ``x`` (k, 3) and its own lengths."""
    shape = SHAPES[int(kind)]
    return (shape, np.asarray(x)[np.asarray(nodes)[:len(shape.node_fields)]],
            np.asarray(params)[:len(shape.param_fields)])
