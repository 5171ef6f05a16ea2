"""Tangential (shear) force: Coulomb friction with a stick regularisation (report 7.2.4).

Coulomb's law (Eq. 29): :math:`\\mathbf F_t = -\\mu |F_N|\\,\\hat{\\mathbf v}_t`, opposing the
relative tangential velocity at the contact point. Pure Coulomb chatters when the slip speed is
tiny: the force flips sign every step. The report quotes Haff & Werner's regularisation (Eq. 30)

.. math::  |\\mathbf F_t| = \\min(\\gamma_t m_t |\\mathbf v_t|,\\; \\mu |F_N|),

which we use **by default** with :math:`\\gamma_t = 1/(2\\Delta t)` and :math:`m_t` the true
tangential effective mass of the contact including rotation,
:math:`1/m_t = \\sum_{bodies} (1/m + R^2/I)` (= 2m/7 for a solid sphere on a wall). Then the
viscous branch removes half of the slip velocity per step (stable for any step, no extra parameter
to tune), and whenever the contact really slides (:math:`|\\mathbf v_t| > 2\\Delta t\\,\\mu|F_N|/m_t`)
the force is exactly Coulomb's: full sliding is unchanged, sliding-to-rolling transitions land on
rolling instead of chattering around it. ``friction="coulomb"`` selects the bare Eq. 29.
Units: force, length/s, mass.
"""

from __future__ import annotations

import math

from x3dpd._jit import kernel

__all__ = ["coulomb_force", "regularized_coulomb_force", "FRICTION_LAWS"]


@kernel
def regularized_coulomb_force(vt_norm: float, fn: float, mu: float, m_t: float,
                              dt: float) -> float:
    """Magnitude of the friction force: min(m_t |v_t| / (2 dt), mu |F_N|) [force]."""
    limit = mu * abs(fn)
    stick = 0.5 * m_t * vt_norm / dt
    return stick if stick < limit else limit


@kernel
def coulomb_force(vt_norm: float, fn: float, mu: float, m_t: float, dt: float) -> float:
    """Magnitude of the bare Coulomb force mu |F_N| (zero only when v_t is exactly zero) [force]."""
    if vt_norm == 0.0:
        return 0.0
    return mu * abs(fn)


FRICTION_LAWS = {"regularized": "regularized_coulomb_force", "coulomb": "coulomb_force"}


def friction_time_scale(m_t: float, mu: float, fn: float) -> float:
    """Slip speed below which the regularised law departs from Coulomb, per unit dt [1/s]."""
    return 2.0 * mu * abs(fn) / m_t if m_t > 0 else math.inf
