"""Rigid links (RBEL): slave nodes follow their master's rigid motion.

A slave at body-frame offset :math:`\\mathbf r_0 = \\mathbf x_{s,0} - \\mathbf x_{m,0}` sits at
:math:`\\mathbf x_s = \\mathbf x_m + \\mathsf R\\,\\mathbf r_0` and moves with
:math:`\\mathbf v_s = \\mathbf v_m + \\boldsymbol\\omega_m\\times(\\mathsf R\\,\\mathbf r_0)`,
:math:`\\boldsymbol\\omega_s = \\boldsymbol\\omega_m`. Forces on slaves gather to the master as a
force and a moment :math:`\\mathbf M = \\sum (\\mathbf x_s - \\mathbf x_m)\\times\\mathbf f_s`.
The master carries the body's mass and inertia tensor (parallel-axis theorem, built with the
model); the rotation :math:`\\mathsf R` advances by Rodrigues' formula with
:math:`\\Delta t\\,\\omega`.

The bodies are part of the integrator, as the nodes are (docs/architecture.md, "What is not a
unit"): the step loop calls their kernels at the half kicks, after the drift and after the
contacts. This module holds their law, their kernels, their bundle :class:`RigidBodies` and
its builder from the model (:func:`rigid_body_arrays`, :func:`free_rotation_inverses`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from x3dpd._jit import shared_kernel, step_kernel


class RigidBodies(NamedTuple):
    """Rigid links (RBEL): masters, their slaves, rotations (B bodies)."""

    master: np.ndarray       # (B,) master node index
    ptr: np.ndarray          # (B+1,) CSR offsets into ``slaves``
    slaves: np.ndarray       # slave node indices
    r0: np.ndarray           # (len(slaves), 3) slave offsets from the master at t0
    rot: np.ndarray          # (B, 3, 3) rotation of each body since t0
    inv_ib: np.ndarray       # (B, 3, 3) inverse body inertia tensor
    ib: np.ndarray           # (B, 3, 3) body inertia tensor
    free_rot: np.ndarray     # (B, 3) bool: which rotations of the master are free


def rigid_body_arrays(model, fixed: np.ndarray, kin_mass: np.ndarray,
                      kin_inertia: np.ndarray) -> tuple[dict, np.ndarray]:
    """The rigid bodies' constant arrays of ``model`` (the RBEL card's bodies, built with the
    model: masters, slaves, each body's mass and inertia tensor about its master), by their
    Setup names (``rig_*``), and the slave mask (n,). Each master carries its body's mass and
    principal inertia in ``kin_mass`` (n,) and ``kin_inertia`` (n, 3), its slaves none (both
    changed in place); a body turns about the master's rotational DOFs that ``fixed`` (n, 6)
    leaves free. ``rig_inv_ib`` is zero until :func:`free_rotation_inverses`."""
    n, nb = fixed.shape[0], model.rigid_master.shape[0]
    free_rot = np.zeros((nb, 3), dtype=np.bool_)
    r0 = np.zeros((model.rigid_slaves.shape[0], 3))
    ib = np.ascontiguousarray(model.rigid_inertia, dtype=np.float64).reshape(nb, 3, 3).copy()
    slave = np.zeros(n, dtype=bool)
    for b in range(nb):
        m = int(model.rigid_master[b])
        sl = model.rigid_slaves[model.rigid_ptr[b]:model.rigid_ptr[b + 1]]
        slave[sl] = True
        r0[model.rigid_ptr[b]:model.rigid_ptr[b + 1]] = model.x0[sl] - model.x0[m]
        kin_mass[m] = model.rigid_mass[b]
        kin_inertia[m] = np.diag(ib[b])
        free_rot[b] = ~fixed[m, 3:6]
    kin_mass[slave] = 0.0
    kin_inertia[slave] = 0.0
    arrays = {"rig_master": np.ascontiguousarray(model.rigid_master, dtype=np.int64),
              "rig_ptr": np.ascontiguousarray(model.rigid_ptr, dtype=np.int64),
              "rig_slaves": np.ascontiguousarray(model.rigid_slaves, dtype=np.int64),
              "rig_r0": r0, "rig_ib": ib, "rig_inv_ib": np.zeros((nb, 3, 3)),
              "rig_free_rot": free_rot}
    return arrays, slave


def free_rotation_inverses(arrays: dict, inv_m: np.ndarray) -> None:
    """After the effect units took their DOFs (a driven or modal master's rotation is not
    free): a body with a free rotational DOF turns under the full inertia tensor, in a kick of
    its own (:func:`_rigid_angular_kick`): ``rig_inv_ib`` its inverse, and the master's
    rotational inverse masses in ``inv_m`` (n, 6) zero (velocity Verlet leaves them alone)."""
    for b in range(arrays["rig_master"].shape[0]):
        if arrays["rig_free_rot"][b].any():
            arrays["rig_inv_ib"][b] = np.linalg.inv(arrays["rig_ib"][b])
            inv_m[int(arrays["rig_master"][b]), 3:6] = 0.0




@shared_kernel
def _update_slaves(x, vel, masters, ptr, slaves, r0, rot, positions_too, rotating=True):
    """Place slaves (if ``positions_too``) and set their velocities from their masters.

    ``rotating=False`` (no master can turn, so R = I and omega = 0) skips the rotation products.
    Returns the largest slave speed (for the neighbour-list displacement bound).
    """
    vmax2 = 0.0
    for b in range(masters.shape[0]):
        m = masters[b]
        if not rotating:
            for q in range(ptr[b], ptr[b + 1]):
                s = slaves[q]
                if positions_too:
                    x[s, 0] = x[m, 0] + r0[q, 0]
                    x[s, 1] = x[m, 1] + r0[q, 1]
                    x[s, 2] = x[m, 2] + r0[q, 2]
                for d in range(6):
                    vel[s, d] = vel[m, d]
            v2 = vel[m, 0] ** 2 + vel[m, 1] ** 2 + vel[m, 2] ** 2
            if v2 > vmax2:
                vmax2 = v2
            continue
        for q in range(ptr[b], ptr[b + 1]):
            s = slaves[q]
            rx = rot[b, 0, 0] * r0[q, 0] + rot[b, 0, 1] * r0[q, 1] + rot[b, 0, 2] * r0[q, 2]
            ry = rot[b, 1, 0] * r0[q, 0] + rot[b, 1, 1] * r0[q, 1] + rot[b, 1, 2] * r0[q, 2]
            rz = rot[b, 2, 0] * r0[q, 0] + rot[b, 2, 1] * r0[q, 1] + rot[b, 2, 2] * r0[q, 2]
            if positions_too:
                x[s, 0] = x[m, 0] + rx
                x[s, 1] = x[m, 1] + ry
                x[s, 2] = x[m, 2] + rz
            wx = vel[m, 3]
            wy = vel[m, 4]
            wz = vel[m, 5]
            vel[s, 0] = vel[m, 0] + wy * rz - wz * ry
            vel[s, 1] = vel[m, 1] + wz * rx - wx * rz
            vel[s, 2] = vel[m, 2] + wx * ry - wy * rx
            vel[s, 3] = wx
            vel[s, 4] = wy
            vel[s, 5] = wz
            v2 = vel[s, 0] ** 2 + vel[s, 1] ** 2 + vel[s, 2] ** 2
            if v2 > vmax2:
                vmax2 = v2
    return math.sqrt(vmax2)


@shared_kernel
def _gather_slaves(x, force, masters, ptr, slaves, rotating=True):
    """Move slave forces to their master as force + moment; zero the slaves' rows.

    ``rotating=False`` (no master can turn) gathers forces only: the moments would act on
    fixed rotations.
    """
    for b in range(masters.shape[0]):
        m = masters[b]
        if not rotating:
            for q in range(ptr[b], ptr[b + 1]):
                s = slaves[q]
                for d in range(3):
                    force[m, d] += force[s, d]
                for d in range(6):
                    force[s, d] = 0.0
            continue
        for q in range(ptr[b], ptr[b + 1]):
            s = slaves[q]
            fx = force[s, 0]
            fy = force[s, 1]
            fz = force[s, 2]
            rx = x[s, 0] - x[m, 0]
            ry = x[s, 1] - x[m, 1]
            rz = x[s, 2] - x[m, 2]
            force[m, 0] += fx
            force[m, 1] += fy
            force[m, 2] += fz
            force[m, 3] += ry * fz - rz * fy + force[s, 3]
            force[m, 4] += rz * fx - rx * fz + force[s, 4]
            force[m, 5] += rx * fy - ry * fx + force[s, 5]
            for d in range(6):
                force[s, d] = 0.0


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
        kx = wx / th
        ky = wy / th
        kz = wz / th
        c = math.cos(th)
        s = math.sin(th)
        v = 1.0 - c
        q00 = c + kx * kx * v
        q01 = kx * ky * v - kz * s
        q02 = kx * kz * v + ky * s
        q10 = ky * kx * v + kz * s
        q11 = c + ky * ky * v
        q12 = ky * kz * v - kx * s
        q20 = kz * kx * v - ky * s
        q21 = kz * ky * v + kx * s
        q22 = c + kz * kz * v
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
def _rigid_angular_kick(vel, force, masters, rot, inertia_body_inv, inertia_body, free_rot, h,
                        implicit):
    """omega += h I_w^{-1} (M - omega x I_w omega), I_w = R I_b R^T, on free rotational DOFs.

    The first half kick of a step is explicit (the gyroscopic term at the step's spin); the
    second (``implicit``) takes it at the *new* spin, solved by fixed-point iteration. With the
    second kick explicit too, the pair of kicks is only first-order accurate for a spinning
    body (the gyroscopic term is velocity dependent); this makes it second order, like the rest
    of velocity Verlet.
    """
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
