"""Axial spring-dampers (MATID type 2 + ELEMENTS, our extension): a spring and a dashpot along
the line between two nodes, as a finite-element spring (rod) element, exact for any rotation.

With :math:`\\mathbf d = \\mathbf x_b - \\mathbf x_a`, length :math:`L = |\\mathbf d|`, unit
vector :math:`\\mathbf e = \\mathbf d / L` and :math:`L_0` the distance of the nodes in the deck's
coordinates, the element exerts on node a

.. math::  \\mathbf f_a = k\\,(L - L_0)\\,\\mathbf e
           + c\\,\\big((\\mathbf v_b - \\mathbf v_a)\\cdot\\mathbf e\\big)\\,\\mathbf e,

and the opposite on b (a stretched spring pulls the nodes together). The spring stores
:math:`U = \\tfrac12 k (L - L_0)^2`; the damper dissipates, per step, the trapezoidal work
:math:`-\\tfrac12 (\\mathbf f_d^n + \\mathbf f_d^{n+1})\\cdot\\Delta(\\mathbf x_a - \\mathbf x_b)`
of its force vector, as the axis-aligned dampers of type 1 (``spring_damper``) do.
Units: stiffness k force/length, damping c force·s/length; L, L0 length.
A deck element has two distinct nodes at distinct coordinates (L0 > 0, checked by the model
builder); should the nodes meet during a run (L = 0) the direction is undefined and the
element exerts no force at that instant.

An effect unit (x3dpd.physics.effect_unit): its bundle :class:`AxialSprings`, its forces in
the step loop's slot ``force`` and its energy in ``energy``; the model's ``axial_*`` arrays
(x3dpd.model.build_structure) are its data.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.physics.effect_unit import L_DDAMP, EffectUnit, StateArray


class AxialSprings(NamedTuple):
    """The MATID type 2 elements (A of them)."""

    nodes: np.ndarray        # (A, 2) node indices
    k: np.ndarray            # (A,) stiffness along the element's line [force/length]
    c: np.ndarray            # (A,) damping along the line [force*s/length]
    rest: np.ndarray         # (A,) rest length L0 [length]
    fd_prev: np.ndarray      # (A, 3) damper force vectors on the first node, last step (state)


@step_kernel
def _axial_spring_forces(x, vel, nodes, k, c, rest, force, fd_prev, dt):
    """Add the axial spring and damper forces to ``force``; return the damper dissipation of
    this step.

    ``nodes`` (S, 2) node indices a, b; ``k``, ``c``, ``rest`` (S,) stiffness, damping and rest
    length L0. ``vel`` holds the half-step velocities, so ``dt * (v_a - v_b)`` is the step's
    change of x_a - x_b. ``fd_prev`` (S, 3) carries each damper's force vector on a between
    steps (updated in place).
    """
    dissipated = 0.0
    for s in range(nodes.shape[0]):
        a = nodes[s, 0]
        b = nodes[s, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        ex = 0.0
        ey = 0.0
        ez = 0.0
        if length > 0.0:
            ex = dx / length
            ey = dy / length
            ez = dz / length
        # relative velocity of a with respect to b
        ux = vel[a, 0] - vel[b, 0]
        uy = vel[a, 1] - vel[b, 1]
        uz = vel[a, 2] - vel[b, 2]
        stretch = length - rest[s]
        fs = k[s] * stretch
        fd = -c[s] * (ux * ex + uy * ey + uz * ez)   # c (v_b - v_a) . e
        f = fs + fd
        force[a, 0] += f * ex
        force[a, 1] += f * ey
        force[a, 2] += f * ez
        force[b, 0] -= f * ex
        force[b, 1] -= f * ey
        force[b, 2] -= f * ez
        fdx = fd * ex
        fdy = fd * ey
        fdz = fd * ez
        dissipated -= 0.5 * ((fd_prev[s, 0] + fdx) * ux + (fd_prev[s, 1] + fdy) * uy
                             + (fd_prev[s, 2] + fdz) * uz) * dt
        fd_prev[s, 0] = fdx
        fd_prev[s, 1] = fdy
        fd_prev[s, 2] = fdz
    return dissipated


@kernel
def _axial_spring_energy(x, nodes, k, rest):
    """U = 1/2 sum k (L - L0)^2 over all axial elements [energy]."""
    u_total = 0.0
    for s in range(nodes.shape[0]):
        a = nodes[s, 0]
        b = nodes[s, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        stretch = math.sqrt(dx * dx + dy * dy + dz * dz) - rest[s]
        u_total += 0.5 * k[s] * stretch * stretch
    return u_total


@step_kernel
def force_hook(u, nodes, rigid, stepping, t):
    """Slot ``force``: the elements' forces; their dampers' dissipation to the ledger."""
    stepping.ledger[L_DDAMP] += _axial_spring_forces(nodes.x, nodes.vel, u.nodes, u.k, u.c,
                                                     u.rest, nodes.force, u.fd_prev,
                                                     stepping.dt)


@step_kernel
def energy_hook(u, nodes, en):
    """Slot ``energy``: the springs' energy into U_spring."""
    en[3] += _axial_spring_energy(nodes.x, u.nodes, u.k, u.rest)
    return 0.0


def _setup(model, dt, nodes) -> dict:
    return {"nodes": np.ascontiguousarray(model.axial_nodes, np.int64).reshape(-1, 2),
            "k": np.ascontiguousarray(model.axial_k, np.float64),
            "c": np.ascontiguousarray(model.axial_c, np.float64),
            "rest": np.ascontiguousarray(model.axial_length, np.float64)}


def _stiffness(c) -> list:
    """k along each axis: the element's k e e^T is at most k I."""
    return [(c["nodes"], np.repeat(np.abs(c["k"])[:, None], 3, axis=1), 0)]


UNIT = EffectUnit(
    name="axial_spring", flag="axial_springs", effects=("axial_springs",),
    cards=("MATID", "ELEMENTS"), bundle=AxialSprings, setup=_setup,
    hooks={"force": "force_hook", "energy": "energy_hook"},
    state=(StateArray("fd_prev", "axial_fd_prev", "nodes", (3,)),), stiffness=_stiffness,
    doc="MATID type 2: spring-dampers along the line between two nodes")
