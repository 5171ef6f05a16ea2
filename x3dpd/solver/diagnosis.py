"""Why did energy appear from nowhere? A too-large step, or energy the ledger does not count.

When the energy residual exceeds its tolerance, two causes are possible and they call for
opposite fixes. Either the step is too coarse for the fastest oscillator -- a contact
resolved in fewer than :data:`MIN_STEPS_PER_CONTACT` steps, or a structural DOF with
``omega dt > 2`` -- and a smaller step cures it; or the step resolves everything and energy
entered (or left) through a channel the ledger does not count, a bookkeeping failure that no
step cures. :func:`step_limit_text` tells them apart from the state at the failure:

* contacts: the contact time ``t_c`` of the shortest particle-wall impact at the fastest
  particle's current speed, by the scene's normal law (:func:`wall_contact_time`: Hertz's for
  the report's law, report Section 7.2.3; half a damped period for HOOKE), compared with the
  step: ``t_c / dt`` steps per contact;
* structure: Gershgorin's bound on the highest frequency of the spring network,
  ``omega_max^2 <= max_i (1/m_i) sum_j |K_ij|`` (a ground spring adds ``k`` to its node's row, a
  two-node spring ``2k`` to each end's), against velocity Verlet's limit ``omega dt < 2``.

Between "cannot follow an impact" and "resolves everything" lies a step that follows every
impact but coarsely: fewer than the :data:`RECOMMENDED_STEPS_PER_CONTACT` steps ``x3dpd check``
recommends, or a Maxwell term relaxing in fewer than :data:`MIN_MAXWELL_STEPS` steps. Each
impact then makes or loses a little energy (velocity Verlet's error is of order
``(dt / t_c)^2`` of the impact's energy), and a bed with thousands of impacts adds it up to the
ledger's tolerance: :func:`coarse_step_text` names that, and the advice is a run at half the
step, which shrinks such a residual about fourfold and leaves a bookkeeping one as it is
(tests/physics/test_hooke_ledger.py measures the fourfold on an oblique HOOKE impact; a
first-order residual, halved by half the step, is a bookkeeping one: the HOOKE onset booked
from a = 0 was one).
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.physics.effect_units import UNITS
from x3dpd.physics.normal_laws import NORMAL_LAWS, scene_bodies
from x3dpd.solver.state import Setup

#: Fewer steps per contact than this and the contact itself can make or lose energy (EDEM
#: asks for 6-10 steps to follow an impact at all; x3dpd check recommends 50).
MIN_STEPS_PER_CONTACT = 6

#: Steps per contact ``x3dpd check`` recommends (x3dpd.model.timestep).
RECOMMENDED_STEPS_PER_CONTACT = 50

#: Steps per Maxwell relaxation time below which its incremental update is coarse.
MIN_MAXWELL_STEPS = 3


def structure_omega_bound(setup: Setup) -> float:
    """Upper bound [rad/s] on the spring network's highest circular frequency (Gershgorin).

    An axial spring (MATID type 2) counts as k along each axis (its k e e^T is at most k I);
    rotational springs (type 3) bound the rotational DOFs with the nodes' rotary inertias."""
    n = setup.inv_m.shape[0]
    rows = np.zeros((n, 6))
    # each effect unit's linear elements (x3dpd.physics.effect_unit: ``stiffness``)
    groups = [g for u in UNITS if u.stiffness is not None
              for g in u.stiffness(setup.units[u.name])]
    for nodes, ks, col in groups:
        for s in range(nodes.shape[0]):
            a, b = int(nodes[s, 0]), int(nodes[s, 1])
            k = ks[s]
            rows[a, col:col + 3] += k if b < 0 else 2.0 * k
            if b >= 0:
                rows[b, col:col + 3] += 2.0 * k
    bound = float(np.max(setup.inv_m * rows, initial=0.0))
    return math.sqrt(bound)


def wall_contact_time(model, v: float) -> float:
    """The shortest particle-wall contact [s] at impact speed ``v`` [length/s] under the
    model's normal law: its ``contact_time`` (x3dpd.physics.normal_laws) of each particle
    group on its stiffest flat wall (rigid, or WALLMAT's); inf without particles or at no speed."""
    bodies = scene_bodies(model)
    if not bodies or not v > 0.0:
        return math.inf
    law = NORMAL_LAWS[model.normal_law]
    return min(law.contact_time(b, None, v) for b in bodies.values())


def _top_speed(setup: Setup, vel: np.ndarray) -> float:
    """The fastest particle's speed [length/s] (0 without particles; nan or inf if non-finite)."""
    vp = vel[setup.p0:, :3]
    return float(np.sqrt(np.max(np.sum(vp * vp, axis=1)))) if vp.shape[0] else 0.0


def step_limit_text(model, setup: Setup, vel: np.ndarray, dt: float) -> str | None:
    """Why ``dt`` [s] is too large for the current state, or None when it resolves everything.

    ``vel`` (n, 6) are the current velocities (the particles' speeds set the contact time of
    ``model``'s normal law, :func:`wall_contact_time`).
    """
    omega = structure_omega_bound(setup)
    if omega * dt > 2.0:
        return (f"the stiffest structural spring has omega up to {omega:.4g} rad/s and "
                f"omega*dt = {omega * dt:.3g} > 2, the explicit stability limit")
    vp = vel[setup.p0:, :3]
    if vp.shape[0] and not np.all(np.isfinite(vp)):
        return "particle velocities became non-finite"
    speed = _top_speed(setup, vel)
    if speed <= 0.0:
        return None
    t_c = wall_contact_time(model, speed)
    if t_c < MIN_STEPS_PER_CONTACT * dt:
        return (f"a particle at the current top speed {speed:.4g} length/s stays in a wall "
                f"contact for {t_c:.3g} s, only {t_c / dt:.3g} steps (at least "
                f"{MIN_STEPS_PER_CONTACT} are needed to follow an impact)")
    return None


def coarse_step_text(model, setup: Setup, vel: np.ndarray, dt: float) -> str | None:
    """Why ``dt`` [s] follows the contacts only coarsely (see the module docstring), or None."""
    reasons = []
    speed = _top_speed(setup, vel)
    if speed > 0.0 and math.isfinite(speed):
        t_c = wall_contact_time(model, speed)
        if t_c < RECOMMENDED_STEPS_PER_CONTACT * dt:
            reasons.append(f"a wall contact at the current top speed {speed:.4g} length/s lasts "
                           f"{t_c / dt:.3g} steps ({RECOMMENDED_STEPS_PER_CONTACT} recommended)")
    if setup.decay.shape[0] and setup.decay.shape[1] > 1:
        decay = setup.decay[:, 1:]
        live = (decay > 0.0) & (decay < 1.0)
        if np.any(live):
            steps = float(np.min(-1.0 / np.log(decay[live])))   # tau / dt
            if steps < MIN_MAXWELL_STEPS:
                reasons.append(f"a Maxwell term relaxes in {steps:.3g} steps (tau / dt; at "
                               f"least {MIN_MAXWELL_STEPS} keep its update accurate)")
    return "; ".join(reasons) if reasons else None


def energy_source_advice(model, setup: Setup, vel: np.ndarray, dt: float,
                         sources: list[str]) -> str:
    """The 'Likely cause' sentence of an energy-residual failure of a run of ``model``."""
    why = step_limit_text(model, setup, vel, dt)
    if why is not None:
        return (f"Likely cause: the time step {dt:.3g} s is too large: {why}; run "
                f"`x3dpd check` for a recommended step.")
    coarse = coarse_step_text(model, setup, vel, dt)
    if coarse is not None:
        return (f"Likely cause: the time step {dt:.3g} s follows the contacts only coarsely: "
                f"{coarse}, so every impact makes or loses a little energy and many impacts "
                f"add up. A run at half the step shrinks such a residual about fourfold; if it "
                f"does not, energy is crossing a channel the ledger does not count (please "
                f"report that with the deck and the command line). `x3dpd check` recommends "
                f"a step.")
    known = ", ".join(sources) if sources else "none"
    return (f"The time step {dt:.3g} s is not the likely cause: it resolves the fastest contact "
            f"and is within the structure's stability limit, so energy entered or left through "
            f"a channel the ledger does not count (a bookkeeping failure, not a physics one; "
            f"energy sources in this run: {known}). Please report it with the deck and the "
            f"command line.")
