# Over 400 lines: the modes' step, its coefficients and its effect unit are one law, kept together.
"""A linear structure given by its modes (the MODAL card, our extension; docs/deck-reference.md).

Node motion about the deck's coordinates is a sum over mass-normalised modes,

.. math::  \\mathbf u_i = \\sum_k \\boldsymbol\\phi_{ik}\\, q_k, \\qquad
           \\ddot q_k + 2\\zeta_k\\omega_k\\dot q_k + \\omega_k^2 q_k = f_k
           = \\sum_i \\boldsymbol\\phi_{ik}^{\\mathsf T}\\mathbf F_i ,

where :math:`\\mathbf F_i` is every force and moment on modal node *i* (contacts gathered through
its rigid body, USRFRC forces, springs, gravity on the mass the deck adds there). Shapes have
units 1/sqrt(mass) (translations) and 1/(sqrt(mass) length) (rotations); q has sqrt(mass) length.

**Integration** (one step :math:`h`, :math:`\\mathbf E = e^{\\mathsf M h}` of
:math:`\\mathsf M = [[0, 1, 0, 0], [-\\omega^2, -2\\zeta\\omega, 1, 0], [0, 0, 0, 1], [0,0,0,0]]`,
the oscillator driven by a force :math:`f(t) = f_n + (t/h)(f_{n+1} - f_n)`):

.. math::  q_{n+1} = E_{00} q_n + E_{01} p_n + E_{02} f_n, \\qquad
           p_{n+1} = E_{10} q_n + E_{11} p_n + (E_{12} - E_{13}/h) f_n + (E_{13}/h) f_{n+1}.

The velocity is the exact response to a force varying linearly over the step, the position the
exact response to the force held at its start value (the position must be known before the
force at the step's end can be evaluated). Free motion is exact for any :math:`\\omega h`: a mode
far above the step's Nyquist frequency neither limits the step nor goes unstable, and a constant
force gives its exact static deflection whatever :math:`\\omega h` (no impulse resonance). For
:math:`\\omega h \\to 0` the scheme is velocity Verlet (central difference), the scheme of every
other node: second order. The step's force is evaluated with the modal nodes moving at their
displacement over the step divided by h (Verlet's half-step velocity is that too).

**Ledger.** Kinetic :math:`\\tfrac12\\sum p_k^2` and strain :math:`\\tfrac12\\sum\\omega_k^2 q_k^2`
energy; the damping's dissipation over a step is the exact integral
:math:`\\int 2\\zeta\\omega\\dot q^2\\,dt` of the same linearly driven oscillator, a quadratic form
of :math:`(q_n, p_n, f_n, f_{n+1})` precomputed per mode (Van Loan's block exponential). Damping
that couples modes (left by mass the deck adds, see x3dpd.model.build_modal) acts as the force
:math:`-\\mathsf C_{\\mathrm{off}}\\,p^*`, booked as damper dissipation.

**An effect unit** (x3dpd.physics.effect_unit): its bundle :class:`Modal`; its slots ``drift``
(the first part of a step, the modal nodes placed), ``kick`` (the second part, from the step's
forces), ``place`` (full-step velocities) and ``energy``; its ``start`` projects the forces of
a state onto the modes. Its nodes leave velocity Verlet (its ``setup``: the modes carry them,
and the rigid bodies whose masters they are).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from x3dpd._jit import step_kernel
from x3dpd.physics.effect_unit import L_DDAMP, EffectUnit, StateArray
from x3dpd.physics.rigid_rotation import rodrigues

__all__ = ["step_coefficients", "dissipation_forms", "receptance", "modal_energy",
           "COEF_COLUMNS"]

#: Columns of the per-mode step coefficients (:func:`step_coefficients`).
COEF_COLUMNS = ("A11", "A12", "A21", "A22", "BQ", "BP0", "BP1", "omega2")


class Modal(NamedTuple):
    """A structure given by its modes (MODAL card): N modal nodes, M modes (both 0 in a scene
    without one)."""

    nodes: np.ndarray        # (N,) node index of each modal node
    shape: np.ndarray        # (N, 6, M) mass-normalised shapes at its 6 DOFs
    body: np.ndarray         # (N,) rigid body the node is master of, or -1
    coef: np.ndarray         # (M, 8) step coefficients (COEF_COLUMNS)
    diss: np.ndarray         # (M, 10) the damping's dissipation per step, a quadratic form
    coupling: np.ndarray     # (M, M) damping coupling the modes, or (0, 0)
    q: np.ndarray            # (M,) modal coordinates [sqrt(mass) length] (state)
    p: np.ndarray            # (M,) their rates (p* between the two parts of a step) (state)
    f: np.ndarray            # (M,) modal forces of the last force evaluation (state)
    q_old: np.ndarray        # (M,) scratch: q at the step's start
    p_old: np.ndarray        # (M,) scratch: p at the step's start
    f_new: np.ndarray        # (M,) scratch: the forces being projected
    rate: np.ndarray         # (M,) scratch: (q_{n+1} - q_n) / dt, the rate over the step


def _generator(omega: float, zeta: float) -> np.ndarray:
    return np.array([[0.0, 1.0, 0.0, 0.0],
                     [-omega * omega, -2.0 * zeta * omega, 1.0, 0.0],
                     [0.0, 0.0, 0.0, 1.0],
                     [0.0, 0.0, 0.0, 0.0]])


def _free_motion(omega: float, zeta: float, h: float) -> tuple[float, float, float, float] | None:
    """The exact free-motion matrix in closed form for 0 <= zeta < 1 (rotation times decay: its
    determinant is exp(-2 zeta omega h) to rounding, so an undamped mode keeps its energy);
    None when overdamped or critically damped."""
    if omega == 0.0:
        return 1.0, h, 0.0, 1.0
    if zeta >= 1.0:
        return None
    sigma = zeta * omega
    wd = omega * math.sqrt(1.0 - zeta * zeta)
    e = math.exp(-sigma * h)
    c, s = math.cos(wd * h), math.sin(wd * h)
    return (e * (c + sigma / wd * s), e * s / wd, -e * omega * omega / wd * s,
            e * (c - sigma / wd * s))


def step_coefficients(omega: np.ndarray, zeta: np.ndarray, h: float) -> np.ndarray:
    """(M, 8) step coefficients A11 A12 A21 A22 BQ BP0 BP1 omega^2 of every mode (module
    docstring) for circular frequencies ``omega`` [rad/s], damping ratios ``zeta`` and step
    ``h`` [s]."""
    omega = np.asarray(omega, dtype=np.float64).reshape(-1)
    zeta = np.asarray(zeta, dtype=np.float64).reshape(-1)
    out = np.zeros((omega.shape[0], len(COEF_COLUMNS)))
    for k, (w, z) in enumerate(zip(omega, zeta)):
        e = _expm(_generator(w, z) * h)
        free = _free_motion(float(w), float(z), h)
        out[k, :4] = free if free is not None else (e[0, 0], e[0, 1], e[1, 0], e[1, 1])
        out[k, 4] = e[0, 2]
        out[k, 5] = e[1, 2] - e[1, 3] / h
        out[k, 6] = e[1, 3] / h
        out[k, 7] = w * w
    return out


def dissipation_forms(omega: np.ndarray, zeta: np.ndarray, h: float) -> np.ndarray:
    """(M, 10) upper triangle (row by row: 00 01 02 03 11 12 13 22 23 33) of the symmetric G
    with D = z^T G z = int_0^h 2 zeta omega qdot^2 dt, z = (q_n, p_n, f_n, f_{n+1}), for the
    oscillator driven by the force varying linearly from f_n to f_{n+1} [energy]."""
    omega = np.asarray(omega, dtype=np.float64).reshape(-1)
    zeta = np.asarray(zeta, dtype=np.float64).reshape(-1)
    out = np.zeros((omega.shape[0], 10))
    to_ends = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 1.0, 0], [0, 0, -1.0 / h, 1.0 / h]])
    iu = np.triu_indices(4)
    for k, (w, z) in enumerate(zip(omega, zeta)):
        c = 2.0 * z * w
        if c == 0.0:
            continue
        m = _generator(w, z)
        q = np.zeros((4, 4))
        q[1, 1] = c
        block = np.zeros((8, 8))
        block[:4, :4] = -m.T
        block[:4, 4:] = q
        block[4:, 4:] = m
        big = _expm(block * h)
        g = big[4:, 4:].T @ big[:4, 4:]          # int_0^h e^{M^T t} Q e^{M t} dt
        g = 0.5 * (g + g.T)
        g = to_ends.T @ g @ to_ends
        out[k] = np.where(iu[0] == iu[1], 1.0, 2.0) * g[iu]
    return out


def receptance(freq_hz: np.ndarray, omega: np.ndarray, zeta: np.ndarray, phi_out: np.ndarray,
               phi_in: np.ndarray, coupling: np.ndarray | None = None) -> np.ndarray:
    """Complex receptance X/F [length/force] at ``freq_hz`` between an input DOF with shape
    values ``phi_in`` (M,) and an output DOF ``phi_out`` (M,):

    .. math::  H(\\Omega) = \\boldsymbol\\phi_{out}^{\\mathsf T}
               (\\mathrm{diag}(\\omega^2) - \\Omega^2 \\mathsf I + i\\Omega\\mathsf C)^{-1}
               \\boldsymbol\\phi_{in}, \\quad \\mathsf C = \\mathrm{diag}(2\\zeta\\omega)
               + \\mathsf C_{\\mathrm{off}}.
    """
    f = np.atleast_1d(np.asarray(freq_hz, dtype=np.float64))
    omega = np.asarray(omega, dtype=np.float64)
    damping = np.diag(2.0 * np.asarray(zeta) * omega)
    if coupling is not None and coupling.size:
        damping = damping + coupling
    out = np.empty(f.shape[0], dtype=complex)
    for j, fj in enumerate(f):
        big = 2.0 * math.pi * fj
        dyn = np.diag(omega**2 - big * big).astype(complex) + 1j * big * damping
        out[j] = phi_out @ np.linalg.solve(dyn, phi_in.astype(complex))
    return out


def modal_energy(q: np.ndarray, p: np.ndarray, omega2: np.ndarray) -> tuple[float, float]:
    """(kinetic, strain) energy 1/2 sum p^2, 1/2 sum omega^2 q^2 [energy]."""
    return 0.5 * float(np.dot(p, p)), 0.5 * float(np.dot(omega2 * q, q))


# ---- step kernels (inlined into the step loop) ----------------------------------------------

@step_kernel
def _modal_drift(modal, x, x0, vel, rot, dt):
    """First part of a step: (q, p) from (q_n, p_n, f_n) -- q_{n+1} and p* -- then every
    modal node placed: x = x0 + phi q, a rigid master's rotation from its rotational shape
    values, and the velocity phi (q_{n+1} - q_n)/dt over the step (as every other node's
    velocity at the force evaluation is its displacement over the step / dt: the work of a
    force is then 1/2 (f_n + f_{n+1}) times the displacement, for modal nodes too)."""
    q, p, f, coef, rate = modal.q, modal.p, modal.f, modal.coef, modal.rate
    q_old, p_old = modal.q_old, modal.p_old
    for k in range(q.shape[0]):
        qk = q[k]
        pk = p[k]
        q_old[k] = qk
        p_old[k] = pk
        q[k] = coef[k, 0] * qk + coef[k, 1] * pk + coef[k, 4] * f[k]
        p[k] = coef[k, 2] * qk + coef[k, 3] * pk + coef[k, 5] * f[k]
        rate[k] = (q[k] - qk) / dt
    _modal_place(modal, x, x0, vel, rot, rate, True)


@step_kernel
def _modal_place(modal, x, x0, vel, rot, p, positions_too):
    """Modal nodes at x0 + phi q (when ``positions_too``) moving with phi p (``p``: modal
    rates); the rotation of a modal rigid master is R = exp([theta]x), theta = phi_rot q
    (Rodrigues)."""
    q, shape, nodes, body = modal.q, modal.shape, modal.nodes, modal.body
    nm = q.shape[0]
    for j in range(nodes.shape[0]):
        i = nodes[j]
        for d in range(6):
            v = 0.0
            for k in range(nm):
                v += shape[j, d, k] * p[k]
            vel[i, d] = v
        if not positions_too:
            continue
        for d in range(3):
            u = 0.0
            for k in range(nm):
                u += shape[j, d, k] * q[k]
            x[i, d] = x0[i, d] + u
        b = body[j]
        if b >= 0:
            t0 = 0.0
            t1 = 0.0
            t2 = 0.0
            for k in range(nm):
                t0 += shape[j, 3, k] * q[k]
                t1 += shape[j, 4, k] * q[k]
                t2 += shape[j, 5, k] * q[k]
            _rotation_matrix(rot, b, t0, t1, t2)


@step_kernel
def _rotation_matrix(rot, b, t0, t1, t2):
    """rot[b] = exp([theta]x) for the rotation vector theta (Rodrigues)."""
    th = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    if th == 0.0:
        # (``row``/``col``, not ``c``: the step loop is typed without SSA, one type a name)
        for row in range(3):
            for col in range(3):
                rot[b, row, col] = 1.0 if row == col else 0.0
        return
    q00, q01, q02, q10, q11, q12, q20, q21, q22 = rodrigues(t0, t1, t2, th)
    rot[b, 0, 0] = q00
    rot[b, 0, 1] = q01
    rot[b, 0, 2] = q02
    rot[b, 1, 0] = q10
    rot[b, 1, 1] = q11
    rot[b, 1, 2] = q12
    rot[b, 2, 0] = q20
    rot[b, 2, 1] = q21
    rot[b, 2, 2] = q22


@step_kernel
def _modal_forces(modal, force):
    """f_k = sum over modal nodes and DOFs of phi * F (F: the node's force and moment rows,
    a rigid master's after its slaves were gathered), less the coupling damping C_off qdot
    (qdot the rate over the step). Written into ``modal.f_new``; returns the coupling damping's
    dissipation rate qdot.C_off qdot [energy/s]."""
    shape, nodes, fn, p = modal.shape, modal.nodes, modal.f_new, modal.rate
    nm = fn.shape[0]
    for k in range(nm):
        fn[k] = 0.0
    for j in range(nodes.shape[0]):
        i = nodes[j]
        for d in range(6):
            fd = force[i, d]
            if fd != 0.0:
                for k in range(nm):
                    fn[k] += shape[j, d, k] * fd
    rate = 0.0
    cpl = modal.coupling
    for k in range(cpl.shape[0]):
        fc = 0.0
        for m in range(cpl.shape[1]):
            fc -= cpl[k, m] * p[m]
        fn[k] += fc
        rate -= fc * p[k]
    return rate


@step_kernel
def _modal_kick(modal, force, h2):
    """Second part of a step: f_{n+1} from the forces, p_{n+1} = p* + BP1 f_{n+1}; returns the
    step's damping dissipation (the exact quadratic form plus the coupling's) [energy].
    ``h2`` is the step (the coupling's dissipation rate times it)."""
    rate = _modal_forces(modal, force)
    q, p, f, fn, coef, g = modal.q, modal.p, modal.f, modal.f_new, modal.coef, modal.diss
    q0, p0 = modal.q_old, modal.p_old
    dissipated = rate * h2
    for k in range(q.shape[0]):
        a = q0[k]
        b = p0[k]
        c = f[k]
        d = fn[k]
        dissipated += (g[k, 0] * a * a + g[k, 1] * a * b + g[k, 2] * a * c + g[k, 3] * a * d
                       + g[k, 4] * b * b + g[k, 5] * b * c + g[k, 6] * b * d
                       + g[k, 7] * c * c + g[k, 8] * c * d + g[k, 9] * d * d)
        p[k] += coef[k, 6] * d
        f[k] = d
    return dissipated


@step_kernel
def _modal_energies(modal):
    """(kinetic, strain, sum f^2) of the modes now [energy, energy, force^2/mass]."""
    q, p, f, coef = modal.q, modal.p, modal.f, modal.coef
    ke = 0.0
    u = 0.0
    ff = 0.0
    for k in range(q.shape[0]):
        ke += 0.5 * p[k] * p[k]
        u += 0.5 * coef[k, 7] * q[k] * q[k]
        ff += f[k] * f[k]
    return ke, u, ff


# ---- the effect unit ------------------------------------------------------------------------

@step_kernel
def drift_hook(u, nodes, rigid, stepping, t):
    """Slot ``drift``: modal nodes (and a modal master's rotation) from the modes."""
    _modal_drift(u, nodes.x, nodes.x0, nodes.vel, rigid.rot, stepping.dt)


@step_kernel
def kick_hook(u, nodes, rigid, stepping, t):
    """Slot ``kick``: the modal forces of this step complete the modes' step (and the
    damping's work, to the ledger)."""
    stepping.ledger[L_DDAMP] += _modal_kick(u, nodes.force, stepping.dt)


@step_kernel
def place_hook(u, nodes, rigid, stepping, t):
    """Slot ``place``: the modal nodes' full-step velocities."""
    _modal_place(u, nodes.x, nodes.x0, nodes.vel, rigid.rot, u.p, False)


@step_kernel
def energy_hook(u, nodes, en):
    """Slot ``energy``: the modes' kinetic energy into KE_trans, their strain energy into
    U_spring; returns their forces' sum f^2 (modal mass 1) for S."""
    ke, strain, ff = _modal_energies(u)
    en[0] += ke
    en[3] += strain
    return ff


def _setup(model, dt, nodes) -> dict:
    """The modes' constants for the step ``dt``; the modal nodes leave velocity Verlet (zero
    inverse mass, no kinetic mass: the modes carry it), so do the rigid bodies whose masters
    they are. With the housing included in the modes, the deck's mass on modal nodes does not
    weigh."""
    ms = model.modal
    if ms is None:
        return {"nodes": np.zeros(0, np.int64), "shape": np.zeros((0, 6, 0)),
                "body": np.zeros(0, np.int64), "coef": np.zeros((0, len(COEF_COLUMNS))),
                "diss": np.zeros((0, 10)), "coupling": np.zeros((0, 0))}
    modal_nodes = np.ascontiguousarray(ms.nodes, np.int64)
    for name in ("inv_m", "kin_mass", "kin_inertia"):
        nodes[name][modal_nodes] = 0.0
    for b in ms.body[ms.body >= 0]:
        nodes["rig_free_rot"][b] = False
    if ms.housing == "included":
        nodes["mass"][modal_nodes] = 0.0
        for b in ms.body[ms.body >= 0]:
            nodes["mass"][model.rigid_slaves[model.rigid_ptr[b]:model.rigid_ptr[b + 1]]] = 0.0
    return {"nodes": modal_nodes, "shape": np.ascontiguousarray(ms.shape, np.float64),
            "body": np.ascontiguousarray(ms.body, np.int64),
            "coef": step_coefficients(ms.omega, ms.zeta, dt),
            "diss": dissipation_forms(ms.omega, ms.zeta, dt),
            "coupling": np.ascontiguousarray(ms.coupling, np.float64).reshape(ms.coupling.shape)}


def _start(u, force) -> None:
    """The modal forces f = sum phi^T F of the forces ``force`` of a state, less the coupling
    damping: what the modes' first step starts from."""
    if u.nodes.shape[0] == 0:
        return
    f = u.f
    f[:] = np.einsum("jdk,jd->k", u.shape, force[u.nodes])
    if u.coupling.size:
        f -= u.coupling @ u.p


def _turns(c) -> np.ndarray:
    """The rigid bodies the modes turn: those of modal nodes with rotational shape values."""
    body = c["body"][np.any(c["shape"][:, 3:, :] != 0.0, axis=(1, 2))]
    return body[body >= 0]


UNIT = EffectUnit(
    name="modal", flag="modal", effects=("modal_structure",), cards=("MODAL",), bundle=Modal,
    setup=_setup, hooks={"drift": "drift_hook", "kick": "kick_hook", "place": "place_hook",
                         "energy": "energy_hook"},
    state=(StateArray("q", "mq", "coef"), StateArray("p", "mp", "coef"),
           StateArray("f", "mf", "coef")),
    scratch=(("q_old", "q"), ("p_old", "p"), ("f_new", "f"), ("rate", "f")),
    start=_start, turns=_turns, kernels=("_modal_place",),
    doc="MODAL: a linear structure given by its modes")


def _expm(a: np.ndarray) -> np.ndarray:
    """The matrix exponential e^A (scipy.linalg.expm, imported here: scipy.linalg's import
    costs every x3dpd process half a second, and only scenes with modes need it)."""
    from scipy.linalg import expm

    return expm(a)
