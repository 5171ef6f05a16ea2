"""A rigid body's rotation (RBEL masters with a free rotational DOF): Euler's equations.

The body's angular velocity omega [rad/s] (the master's rotational DOFs, space frame) changes
under the moment M [force x length] gathered on its master as

    I_w domega/dt = M - omega x I_w omega,    I_w = R I_b R^T,

with I_b the body's inertia tensor about its master in the body frame (built with the model,
parallel-axis theorem) and R its rotation since t0, which turns by Rodrigues' formula,
R <- exp(dt [omega]x) R. Velocity Verlet takes the first half kick explicit and the second
implicit in the gyroscopic term (:func:`_rigid_angular_kick`), which keeps the pair second
order for a spinning body. The kernels are the rigid bodies' unit's (x3dpd.physics.rigid_link):
its half kicks and its turn after the drift. Report Section 7.3 (the explicit step).
"""

from __future__ import annotations

import math

from x3dpd._jit import step_kernel


@step_kernel
def rodrigues(t0, t1, t2, th):
    """exp([theta]x) for the rotation vector theta = (t0, t1, t2) of length ``th`` > 0
    (Rodrigues' formula: I cos th + (1 - cos th) k k^T + sin th [k]x, k = theta / th), its nine
    entries row by row. The modes' rotation of a modal master is one too (x3dpd.physics.modal)."""
    kx = t0 / th
    ky = t1 / th
    kz = t2 / th
    c = math.cos(th)
    s = math.sin(th)
    v = 1.0 - c
    return (c + kx * kx * v, kx * ky * v - kz * s, kx * kz * v + ky * s,
            ky * kx * v + kz * s, c + ky * ky * v, ky * kz * v - kx * s,
            kz * kx * v - ky * s, kz * ky * v + kx * s, c + kz * kz * v)


@step_kernel
def _rotate(rot, masters, vel, dt):
    """R <- exp(dt [omega]x) R (Rodrigues) for every rigid body."""
    for b in range(masters.shape[0]):
        m = masters[b]
        wx = vel[m, 3] * dt
        wy = vel[m, 4] * dt
        wz = vel[m, 5] * dt
        th = math.sqrt(wx * wx + wy * wy + wz * wz)
        if th == 0.0:
            continue
        q00, q01, q02, q10, q11, q12, q20, q21, q22 = rodrigues(wx, wy, wz, th)
        for j in range(3):
            a0 = rot[b, 0, j]
            a1 = rot[b, 1, j]
            a2 = rot[b, 2, j]
            rot[b, 0, j] = q00 * a0 + q01 * a1 + q02 * a2
            rot[b, 1, j] = q10 * a0 + q11 * a1 + q12 * a2
            rot[b, 2, j] = q20 * a0 + q21 * a1 + q22 * a2


#: Fixed-point iterations of the implicit half kick: each multiplies the error by about
#: h |omega| (I_max/I_min), far below 1 for any stable step; three leave it below rounding.
IMPLICIT_ITERATIONS = 3


@step_kernel
def _times(m, b, x0, x1, x2):
    """m[b] @ x for a stack of 3x3 matrices ``m`` (written out: no array in the loop)."""
    return (m[b, 0, 0] * x0 + m[b, 0, 1] * x1 + m[b, 0, 2] * x2,
            m[b, 1, 0] * x0 + m[b, 1, 1] * x1 + m[b, 1, 2] * x2,
            m[b, 2, 0] * x0 + m[b, 2, 1] * x1 + m[b, 2, 2] * x2)


@step_kernel
def _times_transposed(m, b, x0, x1, x2):
    """m[b]^T @ x for a stack of 3x3 matrices ``m``."""
    return (m[b, 0, 0] * x0 + m[b, 1, 0] * x1 + m[b, 2, 0] * x2,
            m[b, 0, 1] * x0 + m[b, 1, 1] * x1 + m[b, 2, 1] * x2,
            m[b, 0, 2] * x0 + m[b, 1, 2] * x1 + m[b, 2, 2] * x2)


@step_kernel
def _angular_acceleration(b, w0, w1, w2, m0, m1, m2, rot, inertia_body_inv, inertia_body):
    """I_w^{-1} (M - omega x I_w omega) of body ``b``, I_w = R I_b R^T (Euler's equations in the
    space frame) [rad/s^2]."""
    # world-frame angular momentum R I_b R^T w
    wb0, wb1, wb2 = _times_transposed(rot, b, w0, w1, w2)
    lb0, lb1, lb2 = _times(inertia_body, b, wb0, wb1, wb2)
    l0, l1, l2 = _times(rot, b, lb0, lb1, lb2)
    t0 = m0 - (w1 * l2 - w2 * l1)
    t1 = m1 - (w2 * l0 - w0 * l2)
    t2 = m2 - (w0 * l1 - w1 * l0)
    tb0, tb1, tb2 = _times_transposed(rot, b, t0, t1, t2)
    ab0, ab1, ab2 = _times(inertia_body_inv, b, tb0, tb1, tb2)
    return _times(rot, b, ab0, ab1, ab2)


@step_kernel
def _kicked(b, w0, w1, w2, a0, a1, a2, h, free_rot):
    """omega + h alpha on the free rotational DOFs of body ``b`` (fixed ones keep omega)."""
    return (w0 + h * a0 if free_rot[b, 0] else w0, w1 + h * a1 if free_rot[b, 1] else w1,
            w2 + h * a2 if free_rot[b, 2] else w2)


@step_kernel
def _rigid_angular_kick(nodes, bodies, h, implicit):
    """omega += h I_w^{-1} (M - omega x I_w omega), I_w = R I_b R^T, on free rotational DOFs.

    The first half kick of a step is explicit (the gyroscopic term at the step's spin); the
    second (``implicit``) takes it at the *new* spin, solved by fixed-point iteration. With the
    second kick explicit too, the pair of kicks is only first-order accurate for a spinning
    body (the gyroscopic term is velocity dependent); this makes it second order, like the rest
    of velocity Verlet. ``nodes``: the nodes' bundle (``vel``, ``force``); ``bodies``: the
    rigid bodies' (x3dpd.physics.rigid_link.RigidBodies); ``h`` the half step [s].
    """
    vel, force, masters, rot = nodes.vel, nodes.force, bodies.master, bodies.rot
    inertia_body_inv, inertia_body, free_rot = bodies.inv_ib, bodies.ib, bodies.free_rot
    for b in range(masters.shape[0]):
        m = masters[b]
        w0 = vel[m, 3]
        w1 = vel[m, 4]
        w2 = vel[m, 5]
        a0, a1, a2 = _angular_acceleration(b, w0, w1, w2, force[m, 3], force[m, 4], force[m, 5],
                                           rot, inertia_body_inv, inertia_body)
        n0, n1, n2 = _kicked(b, w0, w1, w2, a0, a1, a2, h, free_rot)
        if implicit:
            for _ in range(IMPLICIT_ITERATIONS):
                a0, a1, a2 = _angular_acceleration(b, n0, n1, n2, force[m, 3], force[m, 4],
                                                   force[m, 5], rot, inertia_body_inv,
                                                   inertia_body)
                n0, n1, n2 = _kicked(b, w0, w1, w2, a0, a1, a2, h, free_rot)
        vel[m, 3] = n0
        vel[m, 4] = n1
        vel[m, 5] = n2
