"""Viscoelastic normal force: the report's modified Lee & Radok law (Section 7.2.3, Eqs. 18-26).

The particle material is a generalized Maxwell solid with relaxation function
:math:`\\Psi(t) = E_0 + \\sum_{k\\ge1} E_k e^{-t/\\tau_k}` (three-parameter model: E0, E1, tau1;
five-parameter: add E2, tau2). Lee & Radok replace the modulus in Hertz's law by the relaxation
operator; with :math:`g(t) = \\tfrac43\\sqrt{R^*}\\,a(t)^{3/2}` the force is the hereditary integral

.. math::  F(t) = \\sum_k F_k(t), \\qquad F_k(t) = \\int_0^t E^*_k e^{-(t-t')/\\tau_k}\\,\\dot g(t')\\,dt'.

Incremental form (Eqs. 23-26), one history value per Maxwell term and contact:

.. math::  F_k(t+\\Delta t) = F_k(t)\\,e^{-\\Delta t/\\tau_k}
           + e^{-\\Delta t/(2\\tau_k)}\\,E^*_k\\,[g(t+\\Delta t) - g(t)],

i.e. the report's midpoint rule for the exponential kernel. We integrate :math:`\\dot g` exactly over
the step (the increment of :math:`a^{3/2}`) where the report takes :math:`a^{1/2}\\,da` at the
midpoint; both are second order, and ours makes the long-term term (:math:`\\tau_0 = \\infty`)
*exactly* Hertz: :math:`F_0 = \\tfrac43 E^*_0\\sqrt{R^*}a^{3/2}` needs no history. The applied force
is :math:`\\max(0, \\sum_k F_k)` (the report's "force set to zero when negative"); the history starts
at zero when a contact starts and is dropped when the approach returns to zero.

Contact moduli :math:`E^*_k`: a rigid wall gives :math:`E_k/(1-\\nu^2)`. Two particles i, j with
plane-strain instantaneous moduli :math:`c = \\sum_k E_k/(1-\\nu^2)` give each Maxwell term of
either body the weight :math:`s = c_i c_j/(c_i+c_j)^2`, i.e. body i contributes
:math:`s\\,E_{ik}/(1-\\nu_i^2)` with its own :math:`\\tau_{ik}`. This is exact for identical
materials (:math:`E_k/(2(1-\\nu^2))`, report Eq. 24) and for the instantaneous response of any
pair (series springs); for dissimilar materials the long-time modulus is an approximation.
"""

from __future__ import annotations

import math

from x3dpd._jit import kernel

__all__ = ["maxwell_step_factors", "pair_term_weight", "maxwell_update"]


def maxwell_step_factors(tau: float, dt: float) -> tuple[float, float]:
    """(e^{-dt/tau}, e^{-dt/(2 tau)}): decay of the history and midpoint weight of the increment."""
    return math.exp(-dt / tau), math.exp(-0.5 * dt / tau)


def pair_term_weight(c_i: float, c_j: float) -> float:
    """s = c_i c_j / (c_i + c_j)^2, the share of each body's Maxwell terms in a pair contact."""
    return c_i * c_j / (c_i + c_j) ** 2


@kernel
def maxwell_update(f_k: float, decay: float, half: float, k_k: float, a32_new: float,
                   a32_old: float) -> float:
    """One step of a Maxwell term: F_k <- F_k e^{-dt/tau} + e^{-dt/2tau} K_k (a_new^{3/2} - a_old^{3/2}).

    ``K_k = 4/3 E*_k sqrt(R*)`` [force/length^{3/2}]; returns the new F_k [force].
    """
    return f_k * decay + half * k_k * (a32_new - a32_old)
