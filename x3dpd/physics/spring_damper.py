"""Discrete spring-dampers (MATID type 1 + ELEMENTS), to ground or between two nodes.

Along each global axis d (x, y, z) an element between nodes a and b (b = ground when -1) exerts on a

.. math::  f_{a,d} = -k_d\\,(u_{a,d} - u_{b,d}) - c_d\\,(v_{a,d} - v_{b,d}),

and the opposite on b, where :math:`u = x - x_0` is the displacement from the deck's coordinates.
The spring stores :math:`U = \\tfrac12\\sum_d k_d (u_{a,d}-u_{b,d})^2`; the damper dissipates, per
step, the trapezoidal work :math:`-\\tfrac12 (f^n + f^{n+1})\\cdot\\Delta(u_a-u_b)`.
Units: stiffness force/length, damping force·s/length.

An effect unit (x3dpd.physics.effect_unit): its bundle :class:`SpringDampers`, its forces in
the step loop's slot ``force`` and its energy in ``energy``; the model's ``spring_*`` arrays
(x3dpd.model.build_structure) are its data.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.physics.effect_unit import L_DDAMP, EffectUnit, StateArray


class SpringDampers(NamedTuple):
    """The MATID type 1 elements (S of them)."""

    nodes: np.ndarray        # (S, 2) node indices (-1: ground)
    k: np.ndarray            # (S, 3) stiffness per direction [force/length]
    c: np.ndarray            # (S, 3) damping per direction [force*s/length]
    fd_prev: np.ndarray      # (S, 3) damper forces at the last step (state)


@step_kernel
def _spring_forces(x, x0, vel, nodes, k, c, force, fd_prev, dt):
    """Add spring and damper forces to ``force``; return the damper dissipation of this step.

    ``vel`` holds the half-step velocities, so ``dt * vel`` is the displacement of the step.
    ``fd_prev`` (S, 3) carries each damper's force between steps (updated in place).
    """
    dissipated = 0.0
    for s in range(nodes.shape[0]):
        a = nodes[s, 0]
        b = nodes[s, 1]
        for d in range(3):
            du = x[a, d] - x0[a, d]
            dv = vel[a, d]
            if b >= 0:
                du -= x[b, d] - x0[b, d]
                dv -= vel[b, d]
            fs = -k[s, d] * du
            fd = -c[s, d] * dv
            f = fs + fd
            force[a, d] += f
            if b >= 0:
                force[b, d] -= f
            dissipated -= 0.5 * (fd_prev[s, d] + fd) * dv * dt
            fd_prev[s, d] = fd
    return dissipated


@kernel
def _spring_energy(x, x0, nodes, k):
    """U = 1/2 sum k_d (u_a - u_b)_d^2 over all elements [energy]."""
    u_total = 0.0
    for s in range(nodes.shape[0]):
        a = nodes[s, 0]
        b = nodes[s, 1]
        for d in range(3):
            du = x[a, d] - x0[a, d]
            if b >= 0:
                du -= x[b, d] - x0[b, d]
            u_total += 0.5 * k[s, d] * du * du
    return u_total


@step_kernel
def force_hook(u, nodes, rigid, stepping, t):
    """Slot ``force``: the elements' forces; their dampers' dissipation to the ledger."""
    stepping.ledger[L_DDAMP] += _spring_forces(nodes.x, nodes.x0, nodes.vel, u.nodes, u.k, u.c,
                                               nodes.force, u.fd_prev, stepping.dt)


@step_kernel
def energy_hook(u, nodes, en):
    """Slot ``energy``: the springs' energy into U_spring."""
    en[3] += _spring_energy(nodes.x, nodes.x0, u.nodes, u.k)
    return 0.0


def _setup(model, dt, nodes) -> dict:
    return {"nodes": np.ascontiguousarray(model.spring_nodes, np.int64).reshape(-1, 2),
            "k": np.ascontiguousarray(model.spring_k, np.float64).reshape(-1, 3),
            "c": np.ascontiguousarray(model.spring_c, np.float64).reshape(-1, 3)}


def _stiffness(c) -> list:
    return [(c["nodes"], np.abs(c["k"][:, :3]), 0)]


UNIT = EffectUnit(
    name="spring_damper", flag="springs", effects=("springs", "dampers"),
    cards=("MATID", "ELEMENTS"), bundle=SpringDampers, setup=_setup,
    hooks={"force": "force_hook", "energy": "energy_hook"},
    state=(StateArray("fd_prev", "fd_prev", "nodes", (3,)),), stiffness=_stiffness,
    doc="MATID type 1: spring-dampers along the global axes")
