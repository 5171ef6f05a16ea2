"""Hertz normal contact between elastic spheres and between a sphere and a rigid flat wall.

Report Section 7.2.1 (Eqs. 4-7) and 7.2.2. For an approach ``a`` (overlap, length) the normal
force is

.. math::  F = K a^{3/2}, \\qquad K = \\tfrac{4}{3} E^* \\sqrt{R^*},

with the effective radius :math:`1/R^* = 1/R_i + 1/R_j` (a flat wall: :math:`R^* = R`) and the
effective modulus :math:`1/E^* = (1-\\nu_i^2)/E_i + (1-\\nu_j^2)/E_j` (a rigid wall:
:math:`E^* = E/(1-\\nu^2)`). Identical spheres give :math:`R^* = R/2`,
:math:`E^* = E/(2(1-\\nu^2))`, which reproduces the report's
:math:`\\mathrm dF/\\mathrm da = E\\sqrt{R^*}a^{1/2}/(1-\\nu^2)`
(the coefficient of its Eq. 24). The stored elastic energy is :math:`U = \\tfrac{2}{5} K a^{5/2}`.

Closed forms of a head-on impact (used by the validation tests and by ``x3dpd check``): with
effective mass :math:`m^*` and impact speed :math:`v`, the maximum approach is
:math:`a_{max} = (5 m^* v^2 / (4K))^{2/5}`, reached after
:math:`t_{max} = (a_{max}/v)\\int_0^1 (1-x^{5/2})^{-1/2}\\,dx = 1.4716\\,a_{max}/v`, and the contact
lasts :math:`2 t_{max}` (1.4716 = 2/5 B(2/5, 1/2)); the peak force is :math:`K a_{max}^{3/2}`.
Units: any consistent set (the report uses in, lbf, s; modulus in psi).
"""

from __future__ import annotations

import math

from x3dpd._jit import kernel, step_kernel

#: :math:`\\int_0^1 (1-x^{5/2})^{-1/2} dx = \\tfrac25 B(\\tfrac25, \\tfrac12)`, the dimensionless
#: time to maximum compression.
HERTZ_TIME_FACTOR = 0.4 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)

__all__ = [
    "HERTZ_TIME_FACTOR", "effective_modulus_pair", "effective_modulus_wall", "effective_radius",
    "hertz_constant", "hertz_contact_time", "hertz_force", "hertz_energy", "hertz_impact",
    "three_halves", "stored_energy_of_force",
]


def effective_radius(r_i: float, r_j: float | None = None) -> float:
    """R* = R_i R_j / (R_i + R_j); a flat wall (``r_j=None``) gives R_i [length]."""
    if r_j is None:
        return float(r_i)
    return r_i * r_j / (r_i + r_j)


def effective_modulus_pair(e_i: float, nu_i: float, e_j: float, nu_j: float) -> float:
    """E* = 1 / ((1-nu_i^2)/E_i + (1-nu_j^2)/E_j) [pressure]."""
    return 1.0 / ((1.0 - nu_i**2) / e_i + (1.0 - nu_j**2) / e_j)


def effective_modulus_wall(e: float, nu: float) -> float:
    """E* = E / (1 - nu^2) for a sphere on a rigid flat wall (report 7.2.2) [pressure]."""
    return e / (1.0 - nu**2)


def hertz_constant(e_star: float, r_star: float) -> float:
    """K = 4/3 E* sqrt(R*) so that F = K a^{3/2} [force / length^{3/2}]."""
    return 4.0 / 3.0 * e_star * math.sqrt(r_star)


@kernel
def hertz_force(a: float, k: float) -> float:
    """F = K a^{3/2} for a > 0, else 0 [force]."""
    if a <= 0.0:
        return 0.0
    return k * a * math.sqrt(a)


@kernel
def hertz_energy(a: float, k: float) -> float:
    """U = 2/5 K a^{5/2} for a > 0, else 0 [energy]."""
    if a <= 0.0:
        return 0.0
    return 0.4 * k * a * a * math.sqrt(a)


@step_kernel
def three_halves(a: float) -> float:
    """a^{3/2} = a sqrt(a) for a >= 0: the step loop's Hertz force is K times this [length^1.5]."""
    return a * math.sqrt(a)


@step_kernel
def stored_energy_of_force(fn: float, a: float) -> float:
    """U = 2/5 F a, the energy stored in a Hertz contact carrying F = K a^{3/2} [energy]."""
    return 0.4 * fn * a


def hertz_impact(m_eff: float, k: float, v: float) -> tuple[float, float, float]:
    """Closed-form head-on Hertz impact: (a_max [length], t_max [s], F_max [force]).

    ``t_max`` is the time of maximum compression; the contact lasts ``2 * t_max``.
    """
    a_max = (5.0 * m_eff * v * v / (4.0 * k)) ** 0.4
    t_max = HERTZ_TIME_FACTOR * a_max / v
    return a_max, t_max, k * a_max**1.5


def hertz_contact_time(m_eff, r_eff, e_star, v):
    r"""Duration of an elastic Hertz impact, :math:`t_c = 2.868\,(m^2/(R E^{*2} v))^{1/5}` [s].

    Derivation. With the approach :math:`\delta`, Hertz's law (report Eq. 5; Johnson, *Contact
    Mechanics* §4.2) is :math:`F = K\delta^{3/2}`, :math:`K = \tfrac43 E^*\sqrt{R}`. Energy
    conservation :math:`\tfrac12 m\dot\delta^2 + \tfrac25 K\delta^{5/2} = \tfrac12 m v^2` gives
    the largest approach :math:`\delta_m = (5mv^2/4K)^{2/5}` and the duration
    :math:`t_c = 2\int_0^{\delta_m} d\delta/\dot\delta = (2\delta_m/v)\int_0^1(1-x^{5/2})^{-1/2}dx
    = 2.9432\,\delta_m/v`. Substituting :math:`K`:
    :math:`t_c = 2.9432\,(15/16)^{2/5}\,(m^2/(R E^{*2} v))^{1/5} = 2.868\,(m^2/(R E^{*2} v))^{1/5}`.
    :math:`R` enters to the first power (:math:`m^2/(R E^{*2} v)` has units of time^5), not
    squared. The report's Table 3 (two steel spheres, R = 0.0625 in) lists :math:`t_c/2`; this
    function reproduces it within 0.5 % (the table's last digit is not always rounded).

    Effective values: sphere on a rigid flat wall :math:`m, R, E^* = E/(1-\nu^2)` (report
    §7.2.2); two identical spheres :math:`m/2, R/2, E^* = E/(2(1-\nu^2))`; in general
    :math:`m = m_1m_2/(m_1+m_2)`, :math:`R = R_1R_2/(R_1+R_2)`,
    :math:`1/E^* = (1-\nu_1^2)/E_1 + (1-\nu_2^2)/E_2` (:mod:`x3dpd.physics.hertz`).

    Parameters
    ----------
    m_eff : effective mass [mass]
    r_eff : effective radius [length]
    e_star : effective modulus [force/length^2]
    v : normal impact speed [length/s]
    """
    # written as 2 F (5 m / 4 K)^(2/5) v^(-1/5) (F = HERTZ_TIME_FACTOR; the same number as
    # 2 F a_max / v of hertz_impact), so that no intermediate under- or overflows for extreme
    # decks (a speed of 1e300, a density of 1e-300)
    k = hertz_constant(e_star, r_eff)
    return 2.0 * HERTZ_TIME_FACTOR * (1.25 * m_eff / k) ** 0.4 * v ** -0.2
