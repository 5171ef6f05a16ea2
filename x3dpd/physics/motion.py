"""Prescribed motion of node DOFs, sinusoidal or band-limited random (shaker base excitation,
report Figure 9).

A spec ``node=N,dof=D,amp=A,hz=F|omega=W[,phase=P][,t0=T0][,ramp=TR]`` (CLI ``--motion``,
repeatable; an optional leading ``sine:`` is accepted) drives DOF ``D`` (1..6) of node ``N`` on

.. math::

    u(t) = A \\sin(\\omega (t - t_0) + \\varphi), \\quad
    \\dot u(t) = A \\omega \\cos(\\omega (t - t_0) + \\varphi), \\quad
    \\ddot u(t) = -A \\omega^2 \\sin(\\omega (t - t_0) + \\varphi)

for ``t >= t0``; before ``t0`` the DOF rests at ``u = A sin(phi)`` with zero velocity and
acceleration (continuous displacement; the velocity jumps to ``A omega cos(phi)`` at ``t0``).
``ramp=TR`` [s] starts smoothly instead: ``u`` is multiplied by
``h = (1 - cos(pi (t - t0) / TR)) / 2`` for ``t0 <= t < t0 + TR`` (``h = 0`` before, 1 after), so
the DOF rests at ``u = 0`` before ``t0`` and ``u`` and ``u'`` are continuous (no jump).
``u`` is a displacement from the initial coordinate [length] for DOFs 1-3 and a rotation [rad]
for DOFs 4-6; ``phase`` is in degrees unless suffixed ``rad``; ``hz`` in Hz, ``omega`` in rad/s.

``random:node=N,dof=D,rms=R|psd=P,band=LO:HI,seed=S[,t0=T0][,period=T][,ramp=TR]`` drives the
DOF on a band-limited random acceleration with a flat PSD (rms and psd are the acceleration's,
[length/s^2] and [(length/s^2)^2/Hz]); u and u' are its exact integrals, a smooth quintic
between tabulated knots (:mod:`x3dpd.physics.random_signal`), with the same rest before ``t0``
and the same ``ramp`` as the sine.

x3dpd keeps no rotation angles, so a rotational DOF is driven through its angular velocity only.

The actuator that imposes the motion does work on the system; over a step from ``t_n`` to
``t_n+1`` on a DOF of inertia ``M`` (mass, or moment of inertia for DOFs 4-6)

.. math::

    W = \\tfrac12 M (\\dot u_{n+1}^2 - \\dot u_n^2) - \\tfrac12 (f_n + f_{n+1}) (u_{n+1} - u_n)

(:func:`_motion_work`): the change of the DOF's kinetic energy minus the work the rest of the
system's forces ``f`` do on it. It is exact for a velocity jump (an impulse does
``1/2 M (v+^2 - v-^2)``) and for a linear spring on the DOF. At the start of a run the DOF
takes ``u(t_start)`` and ``u'(t_start)``; the change from the deck's velocity is the first
entry of the external work (:func:`start_motion`).

An effect unit (x3dpd.physics.effect_unit): its bundle :class:`PrescribedMotions` (the motion
table a run's specs make, given to the model as ``unit_data["motion"]["table"]``), its DOFs
out of velocity Verlet (``setup``: zero inverse mass), the step's positions and mean
velocities imposed in the slot ``drift`` (after the other units' drift, before the rigid
slaves follow), the actuators' work in ``kick`` and the full-step velocities in ``place``
(both before the other units' hooks there: ``first``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.errors import UsrfrcError
from x3dpd.physics.effect_unit import L_WEXT, EffectUnit, StateArray
from x3dpd.physics.random_signal import _random_motion_state, attach_blocks, parse_random
from x3dpd.physics.spec_fields import _node_dof, _node_ids, _number, _omega, _parse_pairs, _phase

#: Columns of a motion table. ``x_initial`` is the DOF's initial coordinate (0 for rotations or
#: when no coordinates were given); the kernel reads ``x0`` itself. A random row holds its RMS
#: acceleration in ``amp``, :data:`RANDOM` in ``omega`` and the first row of its knots in
#: ``phase``; after the last row, a row with ``node_index`` -1 and the knots follow
#: (x3dpd.physics.random_signal).
MOTION_COLUMNS = ("node_index", "dof_index", "amp", "omega", "phase", "t0", "x_initial", "ramp")
#: ``omega`` of a random row (a sine's is > 0).
RANDOM = -1.0

_REQUIRED = ("node", "dof", "amp")
_OPTIONAL = ("hz", "omega", "phase", "t0", "ramp")


@step_kernel
def _motion_state(t, table, r):
    """``(u, u', u'')`` of row ``r`` at time ``t`` (with the smooth start of a ``ramp`` > 0)."""
    amp, omega, phase, ramp = table[r, 2], table[r, 3], table[r, 4], table[r, 7]
    tau = t - table[r, 5]
    if omega == RANDOM:
        return _random_motion_state(tau, table, amp, int(phase), ramp)
    if tau < 0.0:
        return (0.0 if ramp > 0.0 else amp * math.sin(phase)), 0.0, 0.0
    arg = omega * tau + phase
    s = amp * math.sin(arg)
    c = amp * omega * math.cos(arg)
    if tau < ramp:
        # u = h(tau) A sin(.), h = (1 - cos(pi tau / T)) / 2: h, h' vanish at tau = 0
        k = math.pi / ramp
        h = 0.5 * (1.0 - math.cos(k * tau))
        h1 = 0.5 * k * math.sin(k * tau)
        h2 = 0.5 * k * k * math.cos(k * tau)
        return h * s, h1 * s + h * c, h2 * s + 2.0 * h1 * c - h * omega * omega * s
    return s, c, -omega * omega * s


@step_kernel
def _apply_motion(t, table, x0, x, vel):
    """Impose every prescribed DOF at time ``t``: ``x = x0 + u`` (DOFs 1-3 only), ``vel = u'``."""
    for r in range(table.shape[0]):
        if table[r, 0] < 0.0:  # random signals' knots follow the rows
            break
        i = int(table[r, 0])
        d = int(table[r, 1])
        u, v, _ = _motion_state(t, table, r)
        if d < 3:
            x[i, d] = x0[i, d] + u
        vel[i, d] = v


@step_kernel
def _apply_motion_step(t_prev, t, table, x0, x, vel):
    """Impose the prescribed DOFs for the force pass of the step ``t_prev -> t``.

    ``x = x0 + u(t)`` (DOFs 1-3) and ``vel = (u(t) - u(t_prev)) / (t - t_prev)``: the step's mean
    velocity, what the half-step velocity of an integrated DOF is (velocity Verlet), so that
    dampers and friction see ``dt * vel`` as the DOF's displacement, as for every other DOF.
    """
    for r in range(table.shape[0]):
        if table[r, 0] < 0.0:  # random signals' knots follow the rows
            break
        i = int(table[r, 0])
        d = int(table[r, 1])
        u0 = _motion_state(t_prev, table, r)[0]
        u1 = _motion_state(t, table, r)[0]
        if d < 3:
            x[i, d] = x0[i, d] + u1
        vel[i, d] = (u1 - u0) / (t - t_prev)


@step_kernel
def _motion_work(t_prev, t, table, kin_mass, kin_inertia, force, f_prev):
    """Work [force x length] of the actuators over the step ``t_prev -> t`` (see module doc).

    ``force`` (n, 6) holds the forces of the rest of the system at ``t``; ``f_prev`` (m,) those
    at ``t_prev`` on each driven DOF, replaced by the values at ``t``.
    """
    w = 0.0
    for r in range(table.shape[0]):
        if table[r, 0] < 0.0:  # random signals' knots follow the rows
            break
        i = int(table[r, 0])
        d = int(table[r, 1])
        u0, v0, _ = _motion_state(t_prev, table, r)
        u1, v1, _ = _motion_state(t, table, r)
        inertia = kin_mass[i] if d < 3 else kin_inertia[i, d - 3]
        f1 = force[i, d]
        w += 0.5 * inertia * (v1 * v1 - v0 * v0) - 0.5 * (f_prev[r] + f1) * (u1 - u0)
        f_prev[r] = f1
    return w


@kernel
def _motion_acceleration(t, table, acc):
    """Write ``u''(t)`` of every row into ``acc`` (m,) (for the motion's reaction force)."""
    for r in range(table.shape[0]):
        if table[r, 0] < 0.0:  # random signals' knots follow the rows
            break
        acc[r] = _motion_state(t, table, r)[2]


@kernel
def _motion_history(times, table, u, v, a):
    for j in range(times.shape[0]):
        for r in range(u.shape[1]):
            u[j, r], v[j, r], a[j, r] = _motion_state(times[j], table, r)


def motion_table(specs, model_or_node_ids, x0=None) -> np.ndarray:
    """Parse ``--motion`` specs into a ``(m, 8)`` float table (columns :data:`MOTION_COLUMNS`;
    with random motions, their knots follow the ``m`` rows: :func:`motion_count`).

    Parameters
    ----------
    specs : iterable of str
        ``node=N,dof=D,amp=A,hz=F|omega=W[,phase=P][,t0=T0][,ramp=TR]``, or
        ``random:node=N,dof=D,rms=R|psd=P,band=LO:HI,seed=S[,t0=T0][,period=T][,ramp=TR]``.
    model_or_node_ids : Model or (n,) int array
        Ascending user node ids; a Model also supplies ``x0`` for column ``x_initial``.
    x0 : (n, 3) array, optional
        Initial coordinates for column ``x_initial``.

    Raises
    ------
    UsrfrcError
        Naming the spec and the bad key, value or undefined node, or a DOF driven twice.
    """
    node_ids = _node_ids(model_or_node_ids)
    if x0 is None:
        x0 = getattr(model_or_node_ids, "x0", None)
    rows, seen, laws = [], {}, []
    for spec in specs:
        body = spec.strip()
        if body.lower().startswith("sine:"):
            body = body[5:]
        if body.lower().startswith("random:"):
            law = parse_random("motion spec", spec, body[7:], node_ids, motion=True)
            _check_once(spec, law.node, law.dof, node_ids, seen)
            xi = float(x0[law.node, law.dof]) if (x0 is not None and law.dof < 3) else 0.0
            laws.append((len(rows), law))
            rows.append([law.node, law.dof, law.rms, RANDOM, 0.0, law.t0, xi, law.ramp])
            continue
        pairs = _parse_pairs("motion spec", spec, body, _REQUIRED, _OPTIONAL)
        node, dof = _node_dof("motion spec", spec, pairs, node_ids)
        _check_once(spec, node, dof, node_ids, seen)
        amp = _number("motion spec", spec, "amp", pairs["amp"])
        omega = _omega("motion spec", spec, pairs)
        phase = _phase("motion spec", spec, pairs["phase"]) if "phase" in pairs else 0.0
        t0 = _number("motion spec", spec, "t0", pairs["t0"]) if "t0" in pairs else 0.0
        ramp = _number("motion spec", spec, "ramp", pairs["ramp"]) if "ramp" in pairs else 0.0
        if ramp < 0.0:
            raise UsrfrcError(f"motion spec {spec!r}: ramp={pairs['ramp']!r}: expected a "
                              f"duration >= 0 [s]")
        xi = float(x0[node, dof]) if (x0 is not None and dof < 3) else 0.0
        rows.append([node, dof, amp, omega, phase, t0, xi, ramp])
    return attach_blocks(rows, laws, 4, [-1.0] + [0.0] * (len(MOTION_COLUMNS) - 1))


def _check_once(spec, node, dof, node_ids, seen) -> None:
    if (node, dof) in seen:
        raise UsrfrcError(f"motion spec {spec!r}: node {int(node_ids[node])} dof {dof + 1} is "
                          f"already driven by {seen[node, dof]!r}")
    seen[node, dof] = spec


def motion_count(table) -> int:
    """Number of motions in a motion table (the rows before the knots of random motions)."""
    table = np.asarray(table)
    hit = np.flatnonzero(table[:, 0] < 0.0)
    return int(hit[0]) if hit.size else int(table.shape[0])


def motion_rows(table) -> np.ndarray:
    """The motions of a motion table, without the knots of random motions (a view)."""
    return np.asarray(table)[:motion_count(table)]


def _check_table(table) -> np.ndarray:
    table = np.ascontiguousarray(table, dtype=np.float64)
    if table.ndim != 2 or table.shape[1] != len(MOTION_COLUMNS):
        raise ValueError(f"a motion table has shape (m, {len(MOTION_COLUMNS)}); got {table.shape}")
    return table


def apply_motion(t: float, table, x0, x, vel) -> None:
    """Validate and impose the prescribed DOFs at time ``t`` [s] on ``x`` (n, 3), ``vel`` (n, 6)."""
    table = _check_table(table)
    for name, a, cols in (("x0", x0, 3), ("x", x, 3), ("vel", vel, 6)):
        if a.dtype != np.float64 or a.ndim != 2 or a.shape[1] != cols:
            raise ValueError(f"{name} must be (n, {cols}) float64; got {a.shape} {a.dtype}")
    rows = motion_rows(table)
    if rows.shape[0] and rows[:, 0].max() >= x.shape[0]:
        raise ValueError("the motion table refers to a node index outside the arrays")
    _apply_motion(float(t), table, x0, x, vel)


def start_motion(t: float, table, x0, x, vel, kin_mass, kin_inertia) -> float:
    """Put the driven DOFs on their motion at the start time ``t`` [s]; return the actuator's work.

    ``x`` (n, 3) and ``vel`` (n, 6) are changed in place. The work is the kinetic energy the
    velocity change gives each DOF, ``1/2 M (u'(t)^2 - v^2)`` with ``v`` its velocity before
    (an impulse); a displacement ``u(t) = A sin(phi)`` is part of the initial state.
    """
    table = _check_table(table)
    rows = motion_rows(table)[:, :2].astype(np.int64)
    before = vel[rows[:, 0], rows[:, 1]].copy()
    apply_motion(t, table, x0, x, vel)
    after = vel[rows[:, 0], rows[:, 1]]
    inertia = np.where(rows[:, 1] < 3, kin_mass[rows[:, 0]],
                       kin_inertia[rows[:, 0], np.maximum(rows[:, 1] - 3, 0)])
    return float(np.sum(0.5 * inertia * (after * after - before * before)))


def motion_history(times, table) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(u, u', u'')`` of every motion at every time, each ``(len(times), m)``."""
    times = np.atleast_1d(np.asarray(times, dtype=np.float64))
    table = _check_table(table)
    u, v, a = (np.empty((times.shape[0], motion_count(table))) for _ in range(3))
    _motion_history(times, table, u, v, a)
    return u, v, a


def prescribed_mask(table, n_nodes: int) -> np.ndarray:
    """``(n, 6)`` bool, True at the DOFs the motion table drives (the solver does not integrate
    them)."""
    table = motion_rows(_check_table(table))
    mask = np.zeros((n_nodes, 6), dtype=bool)
    mask[table[:, 0].astype(np.int64), table[:, 1].astype(np.int64)] = True
    return mask


class PrescribedMotions(NamedTuple):
    """The prescribed motions of a run (M of them)."""

    table: np.ndarray        # (M + knots, 8) the motion table (MOTION_COLUMNS)
    dofs: np.ndarray         # (M, 2) node index, DOF index of each motion
    prev: np.ndarray         # (M,) the rest of the system's force on each DOF at the last
    #                          step (state)


@step_kernel
def drift_hook(u, nodes, rigid, stepping, t, t_old):
    """Slot ``drift``: the driven DOFs at ``t`` with the step's mean velocities."""
    _apply_motion_step(t_old, t, u.table, nodes.x0, nodes.x, nodes.vel)


@step_kernel
def kick_hook(u, nodes, rigid, stepping, t, t_old):
    """Slot ``kick``: the actuators' work over the step, to the ledger."""
    stepping.ledger[L_WEXT] += _motion_work(t_old, t, u.table, nodes.kin_mass,
                                            nodes.kin_inertia, nodes.force, u.prev)


@step_kernel
def place_hook(u, nodes, rigid, stepping, t):
    """Slot ``place``: the driven DOFs' full-step positions and velocities."""
    _apply_motion(t, u.table, nodes.x0, nodes.x, nodes.vel)


def _setup(model, dt, nodes) -> dict:
    """The motion table of the model's ``unit_data["motion"]`` (none without); the driven DOFs
    leave velocity Verlet (zero inverse mass; a rigid master's driven rotation is not free)."""
    table = model.unit_data.get("motion", {}).get("table")
    table = np.zeros((0, len(MOTION_COLUMNS))) if table is None else _check_table(table)
    dofs = np.ascontiguousarray(motion_rows(table)[:, :2], np.int64)
    for i, d in dofs:
        nodes["inv_m"][i, d] = 0.0
        body = np.flatnonzero(model.rigid_master == i)
        if d >= 3 and body.size:
            nodes["rig_free_rot"][body[0], d - 3] = False
    return {"table": table, "dofs": dofs}


def _start(u, force) -> None:
    """The forces ``force`` of a state on the driven DOFs: the actuators' first step's."""
    u.prev[:] = force[u.dofs[:, 0], u.dofs[:, 1]]


UNIT = EffectUnit(
    name="motion", flag="motion", effects=("prescribed_motion",), cards=("--motion",),
    bundle=PrescribedMotions, setup=_setup,
    hooks={"drift": "drift_hook", "kick": "kick_hook", "place": "place_hook"},
    first=("kick", "place"), step_start=True,
    state=(StateArray("prev", "motion_prev", "dofs"),), start=_start,
    doc="--motion: node DOFs moved on a prescribed path (base excitation)")
