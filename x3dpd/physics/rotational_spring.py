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
"""

from __future__ import annotations

from x3dpd._jit import kernel, step_kernel


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
