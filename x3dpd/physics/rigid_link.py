"""Rigid links (RBEL): slave nodes follow their master's rigid motion.

A slave at body-frame offset :math:`\\mathbf r_0 = \\mathbf x_{s,0} - \\mathbf x_{m,0}` sits at
:math:`\\mathbf x_s = \\mathbf x_m + \\mathsf R\\,\\mathbf r_0` and moves with
:math:`\\mathbf v_s = \\mathbf v_m + \\boldsymbol\\omega_m\\times(\\mathsf R\\,\\mathbf r_0)`,
:math:`\\boldsymbol\\omega_s = \\boldsymbol\\omega_m`. Forces on slaves gather to the master as a
force and a moment :math:`\\mathbf M = \\sum (\\mathbf x_s - \\mathbf x_m)\\times\\mathbf f_s`.
The master carries the body's mass and inertia tensor (parallel-axis theorem, built with the
model); the rotation :math:`\\mathsf R` advances by Rodrigues' formula with
:math:`\\Delta t\\,\\omega`.

The bodies are an effect unit (x3dpd.physics.effect_unit) whose hooks sit at the integrator's
own slots: their rotation's half kicks (``first_half_kick``, ``second_half_kick``), their turn
after the drift (``drift``, first), their slaves following (``follow``, first; ``place``) and
the slaves' forces gathered onto their masters after the contacts (``gather``); the
rotation's law (Euler's equations, the turn) is x3dpd.physics.rigid_rotation's. Their masses
are lumped on the masters before the inverse masses are formed (``lump``), their inverse
inertia formed after the other units took their DOFs (``finish``). Their bundle
:class:`RigidBodies` is the one every hook gets as ``rigid``: the modes turn a modal master,
the prescribed motions move a driven one, and the walls ride the bodies.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from x3dpd._jit import shared_kernel, step_kernel
from x3dpd.physics.effect_unit import EffectUnit, StateArray
from x3dpd.physics.rigid_rotation import _rigid_angular_kick, _rotate


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


def _lump(model, nodes: dict) -> dict:
    """The bodies' constants of ``model`` by bundle field (the RBEL card's bodies, built with
    the model: masters, slaves, each body's mass and inertia tensor about its master). Each
    master carries its body's mass and principal inertia in ``nodes["kin_mass"]`` (n,) and
    ``nodes["kin_inertia"]`` (n, 3), its slaves none and are ``carried``; a body turns about the
    master's rotational DOFs that ``nodes["fixed"]`` (n, 6) leaves free
    (``nodes["rig_free_rot"]``, which the units that drive a master clear). ``inv_ib`` is zero
    until :func:`_finish`."""
    fixed, kin_mass, kin_inertia = nodes["fixed"], nodes["kin_mass"], nodes["kin_inertia"]
    nb = model.rigid_master.shape[0]
    free_rot = np.zeros((nb, 3), dtype=np.bool_)
    r0 = np.zeros((model.rigid_slaves.shape[0], 3))
    ib = np.ascontiguousarray(model.rigid_inertia, dtype=np.float64).reshape(nb, 3, 3).copy()
    slave = nodes["carried"]
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
    nodes["rig_free_rot"] = free_rot
    return {"master": np.ascontiguousarray(model.rigid_master, dtype=np.int64),
            "ptr": np.ascontiguousarray(model.rigid_ptr, dtype=np.int64),
            "slaves": np.ascontiguousarray(model.rigid_slaves, dtype=np.int64),
            "r0": r0, "inv_ib": np.zeros((nb, 3, 3)), "ib": ib, "free_rot": free_rot}


def _setup(model, dt, nodes) -> dict:
    """Nothing beyond what :func:`_lump` built."""
    return {}


def _finish(constants: dict, nodes: dict) -> None:
    """After the other units took their DOFs (a driven or modal master's rotation is not
    free): a body with a free rotational DOF turns under the full inertia tensor, in a kick of
    its own (x3dpd.physics.rigid_rotation): ``inv_ib`` its inverse, and the master's rotational
    inverse masses in ``nodes["inv_m"]`` (n, 6) zero (velocity Verlet leaves them alone)."""
    for b in range(constants["master"].shape[0]):
        if constants["free_rot"][b].any():
            constants["inv_ib"][b] = np.linalg.inv(constants["ib"][b])
            nodes["inv_m"][int(constants["master"][b]), 3:6] = 0.0


def _rotations_at_start(rows: int) -> np.ndarray:
    """Every body's rotation since t0 at t0: the identity."""
    return np.tile(np.eye(3), (rows, 1, 1)) if rows else np.zeros((0, 3, 3))


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


# The unit's hooks in the step loop's slots (x3dpd.physics.effect_unit, "The slots"); ``u`` is
# the bodies' bundle (the one every hook gets as ``rigid``), ``rotating`` the variant's
# HAS_RIGID_ROTATION (some master has a free rotational DOF: else R = I and omega = 0). The
# kicks and the turn are compiled only with it (``only_with``): a loop whose bodies cannot turn
# holds none of their code, as the loop's own branches did before the bodies were a unit.


@step_kernel
def first_half_kick_hook(u, nodes, rigid, stepping, t, rotating):
    """omega(n+1/2) = omega(n) + dt/2 alpha(n), explicit (x3dpd.physics.rigid_rotation)."""
    _rigid_angular_kick(nodes, u, 0.5 * stepping.dt, False)


@step_kernel
def drift_hook(u, nodes, rigid, stepping, t, rotating):
    """The bodies' turn after the drift: R(n+1) = exp(dt [omega(n+1/2)]x) R(n)."""
    _rotate(u.rot, u.master, nodes.vel, stepping.dt)


@step_kernel
def follow_hook(u, nodes, rigid, stepping, t, rotating):
    """The slaves placed on their drifted, turned masters; their largest speed is the bound
    of the wall nodes' displacement the contact lists' skin must cover (``stepping.nbr[5]``,
    x3dpd.solver._advance_template._lists_upkeep)."""
    v = _update_slaves(nodes.x, nodes.vel, u.master, u.ptr, u.slaves, u.r0, u.rot, True,
                       rotating)
    if not v <= stepping.nbr[5]:
        stepping.nbr[5] = v


@step_kernel
def gather_hook(u, nodes, rigid, stepping, t, rotating):
    """The slaves' forces moved onto their masters as force and moment (after the contacts)."""
    _gather_slaves(nodes.x, nodes.force, u.master, u.ptr, u.slaves, rotating)


@step_kernel
def second_half_kick_hook(u, nodes, rigid, stepping, t, rotating):
    """omega(n+1) = omega(n+1/2) + dt/2 alpha(n+1), implicit in the gyroscopic term."""
    _rigid_angular_kick(nodes, u, 0.5 * stepping.dt, True)


@step_kernel
def place_hook(u, nodes, rigid, stepping, t, rotating):
    """The slaves' full-step velocities from their masters' (positions stay)."""
    _update_slaves(nodes.x, nodes.vel, u.master, u.ptr, u.slaves, u.r0, u.rot, False, rotating)


UNIT = EffectUnit(
    name="rigid_links", flag="rigid", effects=("rigid_links",), cards=("RBEL",),
    bundle=RigidBodies, lump=_lump, setup=_setup, finish=_finish,
    hooks={"first_half_kick": "first_half_kick_hook", "drift": "drift_hook",
           "follow": "follow_hook", "gather": "gather_hook",
           "second_half_kick": "second_half_kick_hook", "place": "place_hook"},
    first=("drift", "follow"), variant_args=("HAS_RIGID_ROTATION",),
    only_with={"first_half_kick": "rigid_rotation", "drift": "rigid_rotation",
               "second_half_kick": "rigid_rotation"},
    state=(StateArray("rot", "rot", "master", (3, 3), initial=_rotations_at_start),),
    kernels=("_update_slaves",),
    doc="RBEL: rigid bodies, slave nodes carried by their master's translation and turn")
