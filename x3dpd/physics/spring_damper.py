"""Discrete spring-dampers (MATID type 1 + ELEMENTS), to ground or between two nodes.

Along each global axis d (x, y, z) an element between nodes a and b (b = ground when -1) exerts on a

.. math::  f_{a,d} = -k_d\\,(u_{a,d} - u_{b,d}) - c_d\\,(v_{a,d} - v_{b,d}),

and the opposite on b, where :math:`u = x - x_0` is the displacement from the deck's coordinates.
The spring stores :math:`U = \\tfrac12\\sum_d k_d (u_{a,d}-u_{b,d})^2`; the damper dissipates, per
step, the trapezoidal work :math:`-\\tfrac12 (f^n + f^{n+1})\\cdot\\Delta(u_a-u_b)`.
Units: stiffness force/length, damping force·s/length.
"""

from __future__ import annotations

from x3dpd._jit import kernel, step_kernel


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
