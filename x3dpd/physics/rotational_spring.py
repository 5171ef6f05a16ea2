"""Rotational spring-dampers (MATID type 3 + ELEMENTS, our extension): torsion springs and
dashpots about the global axes between the rotational DOFs of two nodes, or a node and ground.

The small-rotation (per-axis) rotational spring: about each global axis d (x, y, z) an element
between nodes a and b (b = ground when -1) exerts on a the moment

.. math::  M_{a,d} = -k_d\\,\\theta_d - c\\,(\\omega_{a,d} - \\omega_{b,d}),

and the opposite on b, where :math:`\\theta_d` is the element's relative rotation about axis d
since t0. Nodes do not store rotation angles, so each element carries its own
:math:`\\boldsymbol\\theta` (restart dumps save it), advanced in the drift of every step with the
half-step angular velocities, :math:`\\boldsymbol\\theta \\mathrel{+}= \\Delta t\\,(\\boldsymbol
\\omega_a - \\boldsymbol\\omega_b)` -- exactly as positions advance, so it is consistent with
velocity Verlet. Summing angular velocity components treats rotations about the three axes
independently: exact for rotation about one fixed axis, an approximation (rotations do not
commute) once the relative rotation is large about several axes at once.
The spring stores :math:`U = \\tfrac12\\sum_d k_d \\theta_d^2`; the damper dissipates, per step,
the trapezoidal work :math:`-\\tfrac12 (M^n + M^{n+1})\\,\\Delta\\theta` about each axis.
Units: stiffness force·length/rad, damping force·length·s/rad, angles rad.

An effect unit (x3dpd.physics.effect_unit): its bundle :class:`RotationalSprings`, its
rotations advanced in the step loop's slot ``follow`` (after the rigid slaves have their
velocities), its moments in ``force`` and its energy in ``energy``; the model's
``rotational_*`` arrays (x3dpd.model.build_structure) are its data.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.physics.effect_unit import L_DDAMP, EffectUnit, StateArray


class RotationalSprings(NamedTuple):
    """The MATID type 3 elements (Q of them)."""

    nodes: np.ndarray        # (Q, 2) node indices (-1: ground)
    k: np.ndarray            # (Q, 3) stiffness about x, y, z [force*length/rad]
    c: np.ndarray            # (Q, 3) damping [force*length*s/rad]
    theta: np.ndarray        # (Q, 3) relative rotations since t0 [rad] (state)
    md_prev: np.ndarray      # (Q, 3) damper moments at the last step (state)


@step_kernel
def _rotational_spring_drift(vel, nodes, theta, dt):
    """theta += dt (omega_a - omega_b) with the half-step angular velocities ``vel[:, 3:6]``."""
    for s in range(nodes.shape[0]):
        a = nodes[s, 0]
        b = nodes[s, 1]
        for d in range(3):
            w = vel[a, 3 + d]
            if b >= 0:
                w -= vel[b, 3 + d]
            theta[s, d] += dt * w


@step_kernel
def _rotational_spring_moments(vel, nodes, k, c, theta, force, md_prev, dt):
    """Add the rotational spring and damper moments to ``force[:, 3:6]``; return the damper
    dissipation of this step.

    ``k``, ``c`` (S, 3) per axis; ``theta`` (S, 3) the elements' relative rotations;
    ``md_prev`` (S, 3) carries each damper's moment between steps (updated in place).
    """
    dissipated = 0.0
    for s in range(nodes.shape[0]):
        a = nodes[s, 0]
        b = nodes[s, 1]
        for d in range(3):
            dw = vel[a, 3 + d]
            if b >= 0:
                dw -= vel[b, 3 + d]
            ms = -k[s, d] * theta[s, d]
            md = -c[s, d] * dw
            m = ms + md
            force[a, 3 + d] += m
            if b >= 0:
                force[b, 3 + d] -= m
            dissipated -= 0.5 * (md_prev[s, d] + md) * dw * dt
            md_prev[s, d] = md
    return dissipated


@kernel
def _rotational_spring_energy(k, theta):
    """U = 1/2 sum k_d theta_d^2 over all rotational elements [energy]."""
    u_total = 0.0
    for s in range(theta.shape[0]):
        for d in range(3):
            u_total += 0.5 * k[s, d] * theta[s, d] * theta[s, d]
    return u_total


@step_kernel
def follow_hook(u, nodes, rigid, stepping, t):
    """Slot ``follow``: the rotations advance as positions do."""
    _rotational_spring_drift(nodes.vel, u.nodes, u.theta, stepping.dt)


@step_kernel
def force_hook(u, nodes, rigid, stepping, t):
    """Slot ``force``: the elements' moments; their dampers' dissipation to the ledger."""
    stepping.ledger[L_DDAMP] += _rotational_spring_moments(nodes.vel, u.nodes, u.k, u.c, u.theta,
                                                           nodes.force, u.md_prev, stepping.dt)


@step_kernel
def energy_hook(u, nodes, en):
    """Slot ``energy``: the springs' energy into U_spring."""
    en[3] += _rotational_spring_energy(u.k, u.theta)
    return 0.0


def _setup(model, dt, nodes) -> dict:
    return {"nodes": np.ascontiguousarray(model.rotational_nodes, np.int64).reshape(-1, 2),
            "k": np.ascontiguousarray(model.rotational_k, np.float64).reshape(-1, 3),
            "c": np.ascontiguousarray(model.rotational_c, np.float64).reshape(-1, 3)}


def _stiffness(c) -> list:
    """The rotational DOFs, with the nodes' rotary inertias."""
    return [(c["nodes"], np.abs(c["k"]), 3)]


UNIT = EffectUnit(
    name="rotational_spring", flag="rotational_springs", effects=("rotational_springs",),
    cards=("MATID", "ELEMENTS"), bundle=RotationalSprings, setup=_setup,
    hooks={"follow": "follow_hook", "force": "force_hook", "energy": "energy_hook"},
    state=(StateArray("theta", "rotational_theta", "nodes", (3,)),
           StateArray("md_prev", "rotational_md_prev", "nodes", (3,))),
    stiffness=_stiffness, doc="MATID type 3: rotational spring-dampers about the global axes")
