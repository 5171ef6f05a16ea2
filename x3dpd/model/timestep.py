"""Time step of an explicit run: what the contacts and the structure allow (report 7.3).

The step must resolve the shortest impact -- the scene's normal law's ``contact_time``
(x3dpd.physics.normal_laws: Hertz's :func:`hertz_contact_time` for the report's law, half a
damped period for HOOKE), at a characteristic impact speed -- with :data:`STEPS_PER_CONTACT`
steps and stay a safe fraction of the explicit
stability limit 2/omega_max of the stiffest structural DOF. :func:`recommended_time_step`
returns both limits and the binding one; :func:`peak_force_error` says what a coarser step costs
in peak contact force. ``x3dpd check`` reports them (x3dpd.model.check).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from x3dpd.geometry.shapes import SHAPES
from x3dpd.model.check_shapes import shape_extent
from x3dpd.model.model import Model
from x3dpd.model.magnitudes import safe_norms
from x3dpd.physics.hertz import (  # noqa: F401  (re-exported)
    effective_modulus_pair,
    effective_modulus_wall,
    effective_radius,
    hertz_contact_time,
)
from x3dpd.physics.normal_laws import NORMAL_LAWS
from x3dpd.physics.normal_laws import scene_bodies
from x3dpd.physics.tangential_laws import DEFAULT_LAW, TANGENTIAL_LAWS

#: Steps per Hertz contact the recommendation asks for (see :func:`recommended_time_step`).
STEPS_PER_CONTACT = 50

#: Fewer steps per contact than this is a warning: the peak contact force then errs by more than
#: about 2 % (see :func:`peak_force_error`) -- the accuracy below which damping predictions are
#: no longer trustworthy. Between this and :data:`STEPS_PER_CONTACT` the summary only notes the
#: expected error (the report's own decks, at 5e-7 s, resolve a fall across the cavity in ~10).
MIN_STEPS_PER_CONTACT = 8
#: Fraction of the explicit stability limit used for the structure.
STRUCTURE_SAFETY = 0.2
#: Floor of the characteristic impact speed [length/s] (1 in/s in the report's units).
MIN_IMPACT_SPEED = 1.0
_AXES = "xyz"


def peak_force_error(steps_per_contact):
    r"""Worst relative error [%] of the peak force of a Hertz impact resolved in ``n`` steps.

    Measured with velocity Verlet (central difference) over all phases of the first step
    relative to the moment of contact: 3.4 % (6 steps), 1.29 % (10), 0.34 % (20), 0.055 % (50);
    fitted by :math:`1.35\,\% \cdot (10/n)^2`. Contact duration and restitution errors are
    smaller (0.55 % and 0.26 % at 10 steps). ``tests/model/test_model_timestep.py`` re-measures it.
    """
    if not steps_per_contact > 1e-100:
        return math.inf
    return 1.35 * (10.0 / steps_per_contact) ** 2


@dataclass(frozen=True)
class TimeStepAdvice:
    """Recommended time step and the limits behind it (all times in s).

    ``binding`` is ``"contact"``, ``"structure"`` or ``"none"``; ``contact_kind`` says which
    contact is shortest (``"particle-wall"`` or ``"particle-particle"``) and ``contact_law``
    how its law names it (``"Hertz"``, ``"HOOKE"``: the law module's CONTACT_NAME);
    ``omega_node`` and ``omega_dof`` name the structural DOF with the highest frequency
    estimate.
    """

    dt_deck: float
    dt_recommended: float
    binding: str
    t_contact: float
    impact_speed: float
    contact_kind: str
    steps_per_contact: int
    dt_contact: float
    omega_max: float
    omega_node: int
    omega_dof: str
    dt_structure: float
    contact_law: str = "Hertz"

    @property
    def deck_steps_per_contact(self) -> float:
        return self.t_contact / self.dt_deck

    @property
    def knows_peak_force_error(self) -> bool:
        """Whether :func:`peak_force_error` (measured on Hertz impacts) applies to the shortest
        contact: not to a HOOKE contact, whose dashpot jumps to c_n v at the onset."""
        return self.contact_law == "Hertz"


def characteristic_speed(model: Model) -> float:
    r"""Impact speed for the contact time estimate [length/s].

    :math:`v_c = \max(\sqrt{2|\mathbf g|L},\ \max|\mathbf v_0|,\ v_\mathrm{min})`: a fall across the
    largest cavity extent :math:`L` under the BODY acceleration, the fastest initial velocity of
    any node, and a floor :data:`MIN_IMPACT_SPEED`. A slower impact lasts longer
    (:math:`t_c \propto v^{-1/5}`), so a high :math:`v_c` is the conservative choice; the floor
    keeps a gravity-free deck at rest from recommending an unbounded step. Without walls,
    :math:`L` is the extent of the particle cloud plus a diameter.
    """
    pts = model.x0[model.tri_nodes.reshape(-1)]
    if model.shape_kind.shape[0]:  # analytic walls: their bounding boxes
        pts = np.concatenate(
            [pts] + [np.stack(shape_extent(model, w)) for w in range(model.shape_kind.shape[0])]
        )
    if pts.shape[0] == 0 and model.n_particles:
        pts = model.x0[model.particle_start :]
        extra = 2.0 * float(model.radius.max())
    else:
        extra = 0.0
    length = float(np.max(np.ptp(pts, axis=0))) + extra if pts.shape[0] else 0.0
    fall = math.sqrt(2.0 * math.hypot(*model.body_accel)) * math.sqrt(length)
    fastest = float(np.max(safe_norms(model.v0[:, :3]), initial=0.0))
    return max(fall, fastest, MIN_IMPACT_SPEED)


def _contact_limit(model: Model) -> tuple[float, float, str]:
    """Shortest contact (t_c, v_c, kind) over the contacts the model can have, by the scene's
    normal law's ``contact_time`` (x3dpd.physics.normal_laws) and its tangential law's, if
    it has one (a spring: x3dpd.physics.tangential_laws)."""
    v = characteristic_speed(model)
    best = (math.inf, v, "none")
    if not model.n_particles:
        return best
    law = NORMAL_LAWS[model.normal_law]
    # a tangential law with a spring (the FRICTION card's) has a period of its own
    spring = getattr(
        TANGENTIAL_LAWS[model.friction_law or DEFAULT_LAW].module, "contact_time", None
    )
    bodies = scene_bodies(model)
    # a concave analytic wall (cylinder, capsule) is softer than a flat one (a larger relative
    # radius): the flat wall's contact time bounds its contacts from below
    if "wall_contact" in model.effects or any(s.effect in model.effects for s in SHAPES):
        for g, body in bodies.items():
            if np.any((model.particle_group == g) & (model.particle_cavity >= 0)):
                best = min(best, (law.contact_time(body, None, v), v, "particle-wall"))
                if spring is not None:
                    best = min(
                        best, (spring(law, body, None, v), v, "particle-wall tangential spring")
                    )
    if "pair_contact" in model.effects:
        for g, bi in bodies.items():
            for h, bj in bodies.items():
                if h < g or (h == g and np.sum(model.particle_group == g) < 2):
                    continue
                best = min(best, (law.contact_time(bi, bj, v), v, "particle-particle"))
                if spring is not None:
                    best = min(
                        best, (spring(law, bi, bj, v), v, "particle-particle tangential spring")
                    )
    return best


def _translational_springs(model: Model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(nodes, k, c) of every element acting on translations, per global axis: type 1 as it
    is, and an axial element (type 2) as k and c along each axis. That bounds it whatever its
    direction: its stiffness k e e^T is at most k I (in the PSD order), so the network's
    highest frequency is at most that of the axis-aligned stand-in."""
    nodes = np.concatenate([model.spring_nodes, model.axial_nodes]).reshape(-1, 2)
    k = np.concatenate([model.spring_k, np.repeat(model.axial_k[:, None], 3, axis=1)])
    c = np.concatenate([model.spring_c, np.repeat(model.axial_c[:, None], 3, axis=1)])
    return nodes, k.reshape(-1, 3), c.reshape(-1, 3)


def _gershgorin_rows(pairs, ks, cs, rep, fixed) -> tuple[np.ndarray, np.ndarray]:
    """Row sums of |K| and |C| per node and axis over the free DOFs (``fixed`` (n, 3) of the
    DOFs concerned): an element counts k at an end whose other end is ground or fixed, 2k where
    both ends are free; elements on fixed DOFs count nothing."""
    n = fixed.shape[0]
    ksum = np.zeros((n, 3))
    csum = np.zeros((n, 3))
    for (a, b), k, c in zip(pairs, ks, cs):
        ra = rep[a]
        rb = rep[b] if b >= 0 else -1
        for ax in range(3):
            ends = [(ra, rb)] + ([(rb, ra)] if rb >= 0 else [])
            for r, q in ends:
                if r == q or fixed[r, ax]:
                    continue
                factor = 2.0 if q >= 0 and not fixed[q, ax] else 1.0
                ksum[r, ax] += factor * k[ax]
                csum[r, ax] += factor * c[ax]
    return ksum, csum


def _structure_limit(model: Model) -> tuple[float, float, int, str]:
    r"""Critical step, omega, node id and DOF of the stiffest free structural DOF.

    Each free translational DOF (of a node, or of a rigid body through its master) gets the
    Gershgorin bound on the eigenvalues of :math:`M^{-1}K`: :math:`\omega^2 \le (K_{ii} +
    \sum_j|K_{ij}|)/m_i`, i.e. a spring to ground or to a fixed DOF counts :math:`k`, a spring
    to another free DOF :math:`2k`, and springs on fixed DOFs count nothing (an axial spring,
    MATID type 2, counts as k along each axis: :func:`_translational_springs`). Damping enters
    the central-difference limit :math:`\Delta t_\mathrm{crit} = 2/(\sqrt{\omega^2+\beta^2}+\beta)`,
    :math:`\beta = c/2m` (:math:`= (2/\omega)(\sqrt{1+\zeta^2}-\zeta)`). The free rotational DOFs
    of nodes with rotary inertia I get the same bound from the rotational springs (type 3), with
    I for m. A rigid body with free rotations adds :math:`\omega^2 \le 2(\sum k|\mathbf r|^2 +
    \sum k_\theta)/\lambda_\mathrm{min}(J)` (translational springs k at lever r, rotational
    springs k_theta).
    """
    n = model.n_nodes
    rep = np.arange(n)
    for b, mnode in enumerate(model.rigid_master):
        rep[model.rigid_slaves[model.rigid_ptr[b] : model.rigid_ptr[b + 1]]] = mnode
    mass = model.mass.copy()
    mass[model.rigid_master] = model.rigid_mass
    sp_nodes, sp_k, sp_c = _translational_springs(model)
    ksum, csum = _gershgorin_rows(sp_nodes, sp_k, sp_c, rep, model.fixed[:, :3])
    rsum, rcsum = _gershgorin_rows(
        model.rotational_nodes, model.rotational_k, model.rotational_c, rep, model.fixed[:, 3:]
    )
    best = (math.inf, 0.0, 0, "")
    structural = np.arange(model.particle_start)
    masters = set(model.rigid_master.tolist())
    for i in structural[(rep[structural] == structural)]:
        # (DOF 0..5, mass or inertia, row sums of K and C, name)
        dofs = [(ax, mass[i], ksum[i, ax], csum[i, ax], _AXES[ax]) for ax in range(3)]
        if i not in masters:  # a rigid body's rotation: below
            dofs += [
                (3 + ax, model.inertia[i, ax], rsum[i, ax], rcsum[i, ax], "r" + _AXES[ax])
                for ax in range(3)
            ]
        for dof, m, kk, cc, name in dofs:
            if model.fixed[i, dof] or m <= 0.0 or (kk == 0 and cc == 0):
                continue
            omega = math.sqrt(kk / m)
            beta = cc / (2.0 * m)
            crit = 2.0 / (math.sqrt(omega**2 + beta**2) + beta)
            best = min(best, (crit, omega, int(model.node_ids[i]), name))
    for b, mnode in enumerate(model.rigid_master):
        if np.all(model.fixed[mnode, 3:]):
            continue
        lam = float(np.linalg.eigvalsh(model.rigid_inertia[b])[0])
        on = np.isin(rep[sp_nodes], [mnode]) & (sp_nodes >= 0)
        r2 = np.sum((model.x0[sp_nodes] - model.x0[mnode]) ** 2, axis=-1)
        kr = 2.0 * float(np.sum(on * r2 * sp_k.max(axis=1, initial=0.0)[:, None]))
        rot_on = np.isin(rep[model.rotational_nodes], [mnode]) & (model.rotational_nodes >= 0)
        kr += 2.0 * float(np.sum(rot_on * model.rotational_k.max(axis=1, initial=0.0)[:, None]))
        if kr > 0.0 and lam > 0.0:
            omega = math.sqrt(kr / lam)
            best = min(best, (2.0 / omega, omega, int(model.node_ids[mnode]), "rotation"))
    return best


def recommended_time_step(
    model: Model, steps_per_contact: int = STEPS_PER_CONTACT
) -> TimeStepAdvice:
    r"""Largest time step that resolves the contacts and keeps the structure stable.

    (a) Contact: :math:`\Delta t \le t_c/n` with :math:`t_c` the scene's normal law's
    ``contact_time`` (x3dpd.physics.normal_laws; HOOKE: half a damped period, at any speed)
    for the shortest contact the model can have; for the report's law
    :func:`hertz_contact_time`, using the instantaneous modulus
    :math:`E_0+E_1+\dots` (the stiffest response) at the speed of :func:`characteristic_speed`.
    EDEM asks for at least 6-10 steps per Hertz contact (help.altair.com, "Estimate simulation
    time"); that is a lower bound for following an impact at all, not an accuracy target: at 10
    steps the peak force of a single elastic impact is off by up to 1.3 %
    (:func:`peak_force_error`). :math:`n = 50` gives 0.06 % for that impact and keeps a margin to
    the 0.5 % level for what resolves worse than a lone impact: in a resting column of particles
    the highest contact mode is up to twice the single-contact frequency (25 effective steps:
    about 0.2 %), and ``characteristic_speed`` is only an estimate of the impact speed. The
    Maxwell update (:mod:`x3dpd.physics.maxwell`) uses exponential decay factors, stable for any
    :math:`\Delta t/\tau`, so :math:`\tau_1 < t_c` (Appendix A: 2 µs) sets no stability limit of
    its own; its second-order accuracy is one more reason for a generous :math:`n`.

    (b) Structure: :math:`\Delta t \le 0.2\cdot\Delta t_\mathrm{crit}`, with
    :math:`\Delta t_\mathrm{crit} = 2/\omega_\mathrm{max}` (undamped) from the free DOFs only; see
    :func:`_structure_limit`. Springs on fixed DOFs do not count (Appendix A's
    1e12 lbf/in springs act on y and z, which BOUNDARY fixes).
    """
    t_c, v_c, kind = _contact_limit(model)
    crit, omega, node, dof = _structure_limit(model)
    dt_contact = t_c / steps_per_contact
    dt_structure = STRUCTURE_SAFETY * crit
    dt = min(dt_contact, dt_structure)
    binding = (
        "none" if math.isinf(dt) else ("contact" if dt_contact <= dt_structure else "structure")
    )
    return TimeStepAdvice(
        float(model.dt),
        float(dt),
        binding,
        float(t_c),
        float(v_c),
        kind,
        int(steps_per_contact),
        float(dt_contact),
        float(omega),
        int(node),
        dof,
        float(dt_structure),
        NORMAL_LAWS[model.normal_law].CONTACT_NAME,
    )


def time_step_is_a_problem(ts: TimeStepAdvice) -> bool:
    """A warning when the structure's step limit is exceeded or a contact gets < 8 steps (or
    the advice itself is not a positive number: a deck at the edge of double precision)."""
    if ts.binding != "none" and not (ts.dt_recommended > 0.0):
        return True
    if ts.dt_deck <= ts.dt_recommended * (1.0 + 1e-9):
        return False
    if ts.dt_deck > ts.dt_structure * (1.0 + 1e-9):
        return True
    return ts.deck_steps_per_contact < MIN_STEPS_PER_CONTACT


def time_step_warning(ts: TimeStepAdvice, model: Model) -> str:
    ratio = ts.dt_deck / ts.dt_recommended if ts.dt_recommended > 0.0 else math.inf
    text = (
        f"time step: DTMAX {ts.dt_deck:.3g} s is {ratio:.3g} times the recommended "
        f"{ts.dt_recommended:.3g} s. "
    )
    if ts.binding == "contact":
        n = ts.deck_steps_per_contact
        text += (
            f"A {ts.contact_law} {ts.contact_kind} impact at {ts.impact_speed:.3g} "
            f"length/s lasts {ts.t_contact:.3g} s, so the deck resolves it in {n:.3g} steps: "
        )
        if n < 6:
            text += (
                "too few to follow a contact (at least 6-10 are needed); expect missed or "
                "exploding impacts. "
            )
        elif not ts.knows_peak_force_error:
            text += f"fewer than the recommended {ts.steps_per_contact} follow it coarsely. "
        else:
            text += (
                f"expect peak contact forces off by up to about {peak_force_error(n):.2g} % "
                f"(about {peak_force_error(ts.steps_per_contact):.2g} % at "
                f"{ts.steps_per_contact} steps). "
            )
    else:
        crit = ts.dt_structure / STRUCTURE_SAFETY
        text += (
            f"The stiffest structural DOF (node {ts.omega_node} {ts.omega_dof}) has "
            f"omega <= {ts.omega_max:.4g} rad/s; explicit integration is unstable above "
            f"{crit:.3g} s"
        )
        text += (
            ", so this run will blow up. "
            if ts.dt_deck > crit
            else f", so the run is stable but its periods err by about "
            f"{(ts.omega_max * ts.dt_deck) ** 2 / 24 * 100:.2g} %. "
        )
    return text + f"Set DTMAX <= {ts.dt_recommended:.3g}."
