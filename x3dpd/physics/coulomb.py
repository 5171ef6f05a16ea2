"""Tangential (shear) force: Coulomb friction with a stick regularisation (report 7.2.4).

Coulomb's law (Eq. 29): :math:`\\mathbf F_t = -\\mu |F_N|\\,\\hat{\\mathbf v}_t`, opposing the
relative tangential velocity at the contact point. Pure Coulomb chatters when the slip speed is
tiny: the force flips sign every step. The report quotes Haff & Werner's regularisation (Eq. 30)

.. math::  |\\mathbf F_t| = \\min(\\gamma_t m_t |\\mathbf v_t|,\\; \\mu |F_N|),

which we use **by default** with :math:`\\gamma_t = 1/(2\\Delta t)` and :math:`m_t` the true
tangential effective mass of the contact including rotation,
:math:`1/m_t = \\sum_{bodies} (1/m + R^2/I)` (= 2m/7 for a solid sphere on a wall). Then the
viscous branch removes half of the slip velocity per step (stable for any step, no extra parameter
to tune), and whenever the contact really slides
(:math:`|\\mathbf v_t| > 2\\Delta t\\,\\mu|F_N|/m_t`) the force is exactly Coulomb's: full
sliding is unchanged, sliding-to-rolling transitions land on rolling instead of chattering
around it. ``friction="coulomb"`` selects the bare Eq. 29.
Units: force, length/s, mass.
"""

from __future__ import annotations

import math

from x3dpd._jit import step_kernel

__all__ = ["coulomb_slip_coefficient", "regularized_coulomb_slip_coefficient",
           "regularized_tangential_force", "coulomb_tangential_force", "stored_energy",
           "N_HISTORY", "STORES_ENERGY", "SLIP_FLOOR"]

#: The tangential-law interface (x3dpd.physics.tangential_laws): Coulomb keeps no history of
#: its own (the last step's force, the state row's S_FT columns, is only used for the
#: trapezoidal slip work) and stores no elastic energy.
N_HISTORY = 0
STORES_ENERGY = False

#: Slip speeds at or below this [length/s] count as rolling (no friction force). The stick
#: regularisation halves the slip every step; without a floor a settled bed's slips -- and the
#: velocity components only friction acts on -- sink into subnormal numbers within ~1000 steps,
#: where every operation on them costs ~100 times more. 1e-100 is far below any physical slip
#: in any unit system and far above the subnormal range (its square, 1e-200, is still normal).
SLIP_FLOOR = 1e-100

# Both laws return the *slip coefficient* c = |F_t| / |v_t| [force*s/length], so that the contact
# loop forms F_t = -c v_t without dividing a force magnitude by |v_t| again: in the stick branch
# c is a constant (no division at all), in the sliding branch one division, mu |F_N| / |v_t|.
# ``gamma`` is the stick rate gamma_t = 1/(2 dt) [1/s], formed once per step by the caller. The
# caller guarantees |v_t| > 0 (it skips slip speeds below a floor). Both are inlined into the
# contact loops (measured: a settled 512-particle bed 64.9 -> 63.0 us/step).


@step_kernel
def regularized_coulomb_slip_coefficient(vt_norm: float, fn: float, mu: float, m_t: float,
                                         gamma: float) -> float:
    """|F_t| / |v_t| of min(gamma m_t |v_t|, mu |F_N|) (report Eq. 30) [force*s/length]."""
    stick = gamma * m_t
    limit = mu * abs(fn)
    return stick if stick * vt_norm < limit else limit / vt_norm


@step_kernel
def coulomb_slip_coefficient(vt_norm: float, fn: float, mu: float, m_t: float,
                             gamma: float) -> float:
    """|F_t| / |v_t| of bare Coulomb, mu |F_N| (report Eq. 29) [force*s/length]."""
    return mu * abs(fn) / vt_norm


@step_kernel
def regularized_tangential_force(vtx, vty, vtz, vt, nx, ny, nz, fn, a, m_t, mu_s, mu_k, kt,
                                 ct, dt, gamma, fox, foy, foz, h, row, col):
    """F_t = -c(|v_t|) v_t with c of :func:`regularized_coulomb_slip_coefficient` (report
    Eq. 30), zero at slip speeds up to SLIP_FLOOR, with the report's one mu = ``mu_s``
    (``mu_k``, ``kt``, ``ct``, the approach ``a``, the old force and the history are not used).
    Returns (F_tx, F_ty, F_tz, change of stored energy = 0): the tangential-law signature of
    x3dpd.physics.tangential_laws."""
    if vt > SLIP_FLOOR:
        mag = regularized_coulomb_slip_coefficient(vt, fn, mu_s, m_t, gamma)
        return -mag * vtx, -mag * vty, -mag * vtz, 0.0
    return 0.0, 0.0, 0.0, 0.0


@step_kernel
def coulomb_tangential_force(vtx, vty, vtz, vt, nx, ny, nz, fn, a, m_t, mu_s, mu_k, kt, ct,
                             dt, gamma, fox, foy, foz, h, row, col):
    """F_t = -mu |F_N| v_t/|v_t| (report Eq. 29), zero at slip speeds up to SLIP_FLOOR; as
    :func:`regularized_tangential_force`."""
    if vt > SLIP_FLOOR:
        mag = coulomb_slip_coefficient(vt, fn, mu_s, m_t, gamma)
        return -mag * vtx, -mag * vty, -mag * vtz, 0.0
    return 0.0, 0.0, 0.0, 0.0


@step_kernel
def stored_energy(fx, fy, fz, h, row, col):
    """Coulomb friction stores no energy [energy]."""
    return 0.0


def friction_time_scale(m_t: float, mu: float, fn: float) -> float:
    """Slip speed below which the regularised law departs from Coulomb, per unit dt [1/s]."""
    return 2.0 * mu * abs(fn) / m_t if m_t > 0 else math.inf
