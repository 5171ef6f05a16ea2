"""Hertz normal contact between elastic spheres and between a sphere and a rigid flat wall.

Report Section 7.2.1 (Eqs. 4-7) and 7.2.2. For an approach ``a`` (overlap, length) the normal force is

.. math::  F = K a^{3/2}, \\qquad K = \\tfrac{4}{3} E^* \\sqrt{R^*},

with the effective radius :math:`1/R^* = 1/R_i + 1/R_j` (a flat wall: :math:`R^* = R`) and the
effective modulus :math:`1/E^* = (1-\\nu_i^2)/E_i + (1-\\nu_j^2)/E_j` (a rigid wall:
:math:`E^* = E/(1-\\nu^2)`). Identical spheres give :math:`R^* = R/2`, :math:`E^* = E/(2(1-\\nu^2))`,
which reproduces the report's :math:`\\mathrm dF/\\mathrm da = E\\sqrt{R^*}a^{1/2}/(1-\\nu^2)`
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
    "hertz_constant", "hertz_force", "hertz_energy", "hertz_impact", "three_halves",
    "stored_energy_of_force",
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
