"""Viscoelastic normal force: the report's modified Lee & Radok law (Section 7.2.3, Eqs. 18-26).

The particle material is a generalized Maxwell solid with relaxation function
:math:`\\Psi(t) = E_0 + \\sum_{k\\ge1} E_k e^{-t/\\tau_k}` (three-parameter model: E0, E1, tau1;
five-parameter: add E2, tau2). Lee & Radok replace the modulus in Hertz's law by the relaxation
operator; with :math:`g(t) = \\tfrac43\\sqrt{R^*}\\,a(t)^{3/2}` the force is the hereditary integral

.. math::  F(t) = \\sum_k F_k(t), \\qquad F_k(t) = \\int_0^t E^*_k e^{-(t-t')/\\tau_k}\\,\\dot
           g(t')\\,dt'.

Incremental form (Eqs. 23-26), one history value per Maxwell term and contact:

.. math::  F_k(t+\\Delta t) = F_k(t)\\,e^{-\\Delta t/\\tau_k}
           + e^{-\\Delta t/(2\\tau_k)}\\,E^*_k\\,[g(t+\\Delta t) - g(t)],

i.e. the report's midpoint rule for the exponential kernel. We integrate :math:`\\dot g` exactly
over
the step (the increment of :math:`a^{3/2}`) where the report takes :math:`a^{1/2}\\,da` at the
midpoint; both are second order, and ours makes the long-term term (:math:`\\tau_0 = \\infty`)
*exactly* Hertz: :math:`F_0 = \\tfrac43 E^*_0\\sqrt{R^*}a^{3/2}` needs no history. The applied force
is :math:`\\max(0, \\sum_k F_k)` (the report's "force set to zero when negative"); the history
starts
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

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.physics.hertz import (effective_modulus_pair, effective_modulus_wall,
                                 effective_radius, hertz_contact_time, stored_energy_of_force,
                                 three_halves)
from x3dpd.physics.wall_material import (mixed_modulus, mixed_shear_modulus,
                                          plane_strain_modulus)

__all__ = ["maxwell_step_factors", "pair_term_weight", "maxwell_update", "maxwell_terms",
           "CLAMPED", "USES_RATE", "DAMPED", "CONTACT_NAME", "CARD", "PARAMS", "WALL_STIFFNESS",
           "law_tables", "kind_keys", "contact_time", "wall_force",
           "pair_force", "stored_energy", "stiffness_shape", "tangential_stiffness",
           "tangential_damping"]

#: The step loop's normal law "lee_radok" (x3dpd.physics.normal_laws): the applied force is
#: max(0, F) (report: "force set to zero when negative"); it does not read the approach rate;
#: its dissipation is reported when the scene has Maxwell terms (n_terms > 0).
CLAMPED = True
USES_RATE = False
DAMPED = False
#: How messages name an impact under this law (x3dpd check, the stop's diagnosis).
CONTACT_NAME = "Hertz"
#: The default law: no card selects it, its constants are PDMP's moduli (no PARAMS of its
#: own), and a wall material (WALLMAT) mixes with them.
CARD = None
PARAMS = ()
WALL_STIFFNESS = None


def law_tables(params, mass, rep) -> tuple[np.ndarray, np.ndarray]:
    """The step loop's per-law constant tables: none (zeros; x3dpd.physics.normal_laws)."""
    return np.zeros((mass.shape[0], 2)), np.zeros((rep.shape[0], rep.shape[0], 2))


def kind_keys(params, mass) -> tuple:
    """Nothing of its own distinguishes particle kinds (the moduli are shared keys)."""
    return ()


def contact_time(i, j, v: float) -> float:
    """Duration [s] of a head-on impact at normal speed ``v`` of particle ``i`` on a rigid flat
    wall (``j`` None) or on particle ``j`` (x3dpd.physics.normal_laws.ContactBody): the elastic
    Hertz contact time (:func:`x3dpd.physics.hertz.hertz_contact_time`) with the instantaneous
    modulus E0 + E1 + ..., the stiffest response, so the shortest contact the law can have
    (report Section 7.2.2: m*, R* and E* of a wall; of two spheres, Section 7.2.1). A
    compliant wall (``i.wall_e`` finite, WALLMAT) mixes its plane-strain modulus with the
    particle's (x3dpd.physics.wall_material)."""
    if j is None:
        e_star = effective_modulus_wall(i.modulus, i.poisson)
        if not math.isinf(i.wall_e):
            e_star = mixed_modulus(e_star, plane_strain_modulus(i.wall_e, i.wall_nu))
        return hertz_contact_time(i.mass, effective_radius(i.radius), e_star, v)
    return hertz_contact_time(i.mass * j.mass / (i.mass + j.mass),
                              effective_radius(i.radius, j.radius),
                              effective_modulus_pair(i.modulus, i.poisson, j.modulus, j.poisson),
                              v)


def tangential_stiffness(i, j) -> float:
    """Mindlin's tangential stiffness constant kappa = 8 G* sqrt(R*) [force/length^1.5]
    (k_t = kappa sqrt(a), x3dpd.physics.mindlin) of particle ``i`` on a rigid wall (``j``
    None; a WALLMAT wall mixes its G, x3dpd.physics.wall_material) or on particle ``j``
    (ContactBody), with the instantaneous moduli E0 + E1 + ..."""
    from x3dpd.physics.mindlin import effective_shear_modulus_pair, effective_shear_modulus_wall
    if j is None:
        if not math.isinf(i.wall_e):
            return 8.0 * mixed_shear_modulus(i.modulus, i.poisson, i.wall_e, i.wall_nu) \
                * math.sqrt(i.radius)
        return 8.0 * effective_shear_modulus_wall(i.modulus, i.poisson) * math.sqrt(i.radius)
    g = effective_shear_modulus_pair(i.modulus, i.poisson, j.modulus, j.poisson)
    return 8.0 * g * math.sqrt(effective_radius(i.radius, j.radius))


def tangential_damping(i, j) -> float:
    """No tangential dashpot under Lee & Radok's law: 0 (x3dpd.physics.mindlin). The law
    loses energy by relaxation of the material (Maxwell terms, report 7.2.3), not by a
    dashpot; its consistent tangential counterpart would relax the shear modulus of the
    Mindlin spring with the same terms (the correspondence principle applied to Mindlin), not
    add a dashpot with a damping ratio the report's law does not have. The report's model has
    no tangential loss but Coulomb sliding, and its loss reaches the tangential force through
    F_N in the Coulomb limit."""
    return 0.0


def peak_approach(i, j, v: float) -> float:
    """Largest approach [length] of a head-on elastic Hertz impact at speed ``v`` (as
    :func:`contact_time`: instantaneous modulus, wall or pair values)."""
    from x3dpd.physics.hertz import hertz_constant, hertz_impact
    if j is None:
        m, r, e = i.mass, effective_radius(i.radius), effective_modulus_wall(i.modulus, i.poisson)
    else:
        m = i.mass * j.mass / (i.mass + j.mass)
        r = effective_radius(i.radius, j.radius)
        e = effective_modulus_pair(i.modulus, i.poisson, j.modulus, j.poisson)
    return hertz_impact(m, hertz_constant(e, r), v)[0]


@step_kernel
def stiffness_shape(a):
    """How a Hertz contact's stiffness grows with the approach: sqrt(a) (k_n = 2 E* sqrt(R* a),
    Mindlin's k_t = 8 G* sqrt(R* a)) [length^0.5]."""
    return math.sqrt(a)


def maxwell_step_factors(tau: float, dt: float) -> tuple[float, float]:
    """(e^{-dt/tau}, e^{-dt/(2 tau)}): decay of the history and midpoint weight of the increment."""
    return math.exp(-dt / tau), math.exp(-0.5 * dt / tau)


def pair_term_weight(c_i: float, c_j: float) -> float:
    """s = c_i c_j / (c_i + c_j)^2, the share of each body's Maxwell terms in a pair contact."""
    return c_i * c_j / (c_i + c_j) ** 2


@kernel
def maxwell_update(f_k: float, decay: float, half: float, k_k: float, a32_new: float,
                   a32_old: float) -> float:
    """One step of a Maxwell term: F_k <- F_k e^{-dt/tau} + e^{-dt/2tau} K_k (a_new^{3/2} -
    a_old^{3/2}).

    ``K_k = 4/3 E*_k sqrt(R*)`` [force/length^{3/2}]; returns the new F_k [force].
    """
    return f_k * decay + half * k_k * (a32_new - a32_old)


@step_kernel
def maxwell_terms(states, s, col, decay, half, moduli, p, scale, dg, n_terms):
    """Advance the ``n_terms`` Maxwell histories of body ``p`` in contact row ``s`` and return
    their sum: F_k <- F_k e^{-dt/tau_k} + e^{-dt/2tau_k} (scale * moduli[p, k]) dg (Eqs. 25-26,
    :func:`maxwell_update`); the histories sit in ``states[s, col:col + n_terms]``, the moduli
    and factors of term k in column k (column 0 is the long-term modulus)."""
    total = 0.0
    for k in range(n_terms):
        h = states[s, col + k] * decay[p, k + 1] + half[p, k + 1] * scale * moduli[p, k + 1] * dg
        states[s, col + k] = h
        total += h
    return total


@step_kernel
def wall_force(a, a_old, a_rate, p, particles, states, s, col, n_terms):
    """Normal force of particle ``p`` on a rigid wall at approach ``a`` > 0 (last step:
    ``a_old``): the long-term Hertz term K_0 a^{3/2} exactly, the Maxwell terms incrementally
    (histories in ``states[s, col:]``). ``particles.kw`` holds K_k = 4/3 E*_k sqrt(R) [force /
    length^1.5]. Not yet clamped at zero (the loop applies CLAMPED)."""
    a32 = three_halves(a)
    fn = particles.kw[p, 0] * a32
    if n_terms > 0:
        ao = a_old if a_old > 0.0 else 0.0
        fn += maxwell_terms(states, s, col, particles.decay, particles.half, particles.kw, p, 1.0,
                            a32 - three_halves(ao), n_terms)
    return fn


@step_kernel
def pair_force(a, a_old, a_rate, pi, pj, ki, kj, particles, states, s, col, n_terms):
    """Normal force between particles ``pi``, ``pj`` (kinds ``ki``, ``kj``): the pair's Hertz
    factor (x3dpd.physics.mixing) times sum_k (E_ik + E_jk)/(1-nu^2), long-term term exact, the
    Maxwell terms of i (``states[s, col:]``) and of j (after them) incrementally."""
    kfac = particles.pair_c[ki, kj, 0]
    ep = particles.ep
    a32 = three_halves(a)
    fn = kfac * (ep[pi, 0] + ep[pj, 0]) * a32
    if n_terms > 0:
        ao = a_old if a_old > 0.0 else 0.0
        da32 = a32 - three_halves(ao)
        fn += maxwell_terms(states, s, col, particles.decay, particles.half, ep, pi, kfac, da32,
                            n_terms)
        fn += maxwell_terms(states, s, col + n_terms, particles.decay, particles.half, ep, pj,
                            kfac, da32, n_terms)
    return fn


@step_kernel
def stored_energy(fn, a, k):
    """U = 2/5 F a of an open contact (exact for Hertz; the report's estimate with Maxwell
    terms) [energy]."""
    return stored_energy_of_force(fn, a)
