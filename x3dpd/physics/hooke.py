"""Linear spring-dashpot normal contact with a restitution coefficient (the ``hooke`` law of
LAMMPS and LIGGGHTS), a deck extension (``HOOKE`` card, docs/deck-reference.md).

For an approach (overlap) ``a`` growing at the rate ``da/dt`` the normal force is

.. math::  F = k_n a + c_n \\dot a, \\qquad c_n = 2\\zeta\\sqrt{m^* k_n},
           \\qquad \\zeta = \\frac{-\\ln e}{\\sqrt{\\pi^2 + \\ln^2 e}},

with the effective mass :math:`m^*` (a sphere on a rigid wall: its mass; two spheres:
:math:`m_i m_j/(m_i + m_j)`) and :math:`e` the coefficient of restitution. The force is **not**
clamped at zero (as in LAMMPS's ``hooke``): near the end of a contact the dashpot may pull, and
the contact ends when the approach returns to zero. A head-on impact is then a damped oscillator
over half a period, with the closed forms

.. math::  t_c = \\pi/\\omega_d, \\quad \\omega_d = \\omega_n\\sqrt{1-\\zeta^2},
           \\quad \\omega_n = \\sqrt{k_n/m^*}, \\qquad v_{out} = e\\,v_{in}.

Stored elastic energy :math:`U = \\tfrac12 k_n a^2`; the dashpot's work is dissipated. Two
particle groups with different stiffness meet with the harmonic mean
:math:`2 k_i k_j/(k_i + k_j)` (equal groups: :math:`k_n`), and the mean of their damping ratios.
Units: any consistent set (in, lbf, s: k_n in lbf/in).

The functions the step loop calls (``wall_force``, ``pair_force``, ``stored_energy``) share their
signatures with every normal law (x3dpd.physics.normal_laws).
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd._jit import step_kernel

__all__ = ["CLAMPED", "USES_RATE", "DAMPED", "CONTACT_NAME", "CARD", "PARAMS", "WALL_STIFFNESS",
           "damping_ratio", "dashpot", "hooke_impact", "hooke_tables", "law_tables", "kind_keys",
           "contact_time",
           "wall_force", "pair_force", "stored_energy", "stiffness_shape",
           "tangential_stiffness", "tangential_damping"]

#: The applied force is F itself, not max(0, F).
CLAMPED = False
#: The law reads the approach rate da/dt.
USES_RATE = True
#: The law dissipates energy (the ledger reports W_N - U as viscous dissipation).
DAMPED = True
#: How messages name an impact under this law (x3dpd check, the stop's diagnosis).
CONTACT_NAME = "HOOKE"
#: The deck card that selects the law, and its per-particle constants: a record per PDMP group
#: (NODLIM KN E; x3dpd.model.build_particles, docs/deck-reference.md).
CARD = "HOOKE"
PARAMS = ("KN", "E")
#: The card's field that gives the wall stiffness directly (a wall material, WALLMAT, has
#: nothing to act on).
WALL_STIFFNESS = "KN"


def damping_ratio(e: float) -> float:
    """zeta = -ln e / sqrt(pi^2 + ln^2 e) for a restitution coefficient 0 < e <= 1."""
    if not 0.0 < e <= 1.0:
        raise ValueError(f"restitution coefficient must be in (0, 1]; got {e}")
    le = math.log(e)
    return -le / math.sqrt(math.pi**2 + le * le)


def dashpot(k: float, zeta: float, m_eff: float) -> float:
    """c_n = 2 zeta sqrt(m* k_n) [force*s/length]."""
    return 2.0 * zeta * math.sqrt(m_eff * k)


def hooke_impact(m_eff: float, k: float, e: float, v: float) -> tuple[float, float]:
    """Closed-form head-on impact at speed ``v``: (contact time pi/omega_d [s], exit speed e v)."""
    zeta = damping_ratio(e)
    omega_d = math.sqrt(k / m_eff) * math.sqrt(1.0 - zeta * zeta)
    return math.pi / omega_d, e * v


def _contact_constants(i, j) -> tuple[float, float, float]:
    """(m*, k_n, zeta) of particle ``i`` on a wall (``j`` None) or on ``j``, as the step loop
    forms them (:func:`hooke_tables`)."""
    if j is None:
        return i.mass, i.law[0], damping_ratio(i.law[1])
    return (i.mass * j.mass / (i.mass + j.mass),
            2.0 * i.law[0] * j.law[0] / (i.law[0] + j.law[0]),
            0.5 * (damping_ratio(i.law[1]) + damping_ratio(j.law[1])))


def contact_time(i, j, v: float) -> float:
    """Duration [s] of a head-on impact of particle ``i`` on a rigid flat wall (``j`` None) or
    on particle ``j`` (x3dpd.physics.normal_laws.ContactBody): half a damped period,
    pi/omega_d, omega_d = sqrt(k_n/m*) sqrt(1 - zeta^2), with the constants the step loop
    uses (:func:`hooke_tables`): on a wall m* = m_i, k_n = k_i, zeta from e_i; between two
    particles m* = m_i m_j/(m_i + m_j), k_n = 2 k_i k_j/(k_i + k_j) and the mean of the two
    zetas. A linear contact lasts as long at any speed: ``v`` is not used."""
    m_eff, k, zeta = _contact_constants(i, j)
    return math.pi / (math.sqrt(k / m_eff) * math.sqrt(1.0 - zeta * zeta))


def tangential_stiffness(i, j) -> float:
    """Tangential spring k_t [force/length] of a HOOKE contact (x3dpd.physics.mindlin):
    Mindlin's ratio k_t/k_n = 2(1 - nu)/(2 - nu) of a Hertz contact times the k_n the loop
    uses (on a wall k_i; between particles the harmonic mean, with the mean of the ratios)."""
    def ratio(b):
        return 2.0 * (1.0 - b.poisson) / (2.0 - b.poisson)
    if j is None:
        return ratio(i) * i.law[0]
    kn = 2.0 * i.law[0] * j.law[0] / (i.law[0] + j.law[0])
    return 0.5 * (ratio(i) + ratio(j)) * kn


def tangential_damping(i, j) -> float:
    """The constant eta [sqrt(mass)] of the tangential dashpot c_t = eta sqrt(k_t) of a HOOKE
    contact (x3dpd.physics.mindlin): the normal dashpot's damping ratio and effective mass,
    eta = 2 zeta sqrt(m*), so that c_t = 2 zeta sqrt(m* k_t) = c_n sqrt(k_t/k_n) -- the
    tangential form of Tsuji, Tanaka & Ishida (1992) that EDEM's and Kratos DEM's Hertz-Mindlin
    use (the same zeta, the same m*). m* and zeta as the normal law's (:func:`hooke_tables`):
    on a wall m_i and zeta_i, between particles m_i m_j/(m_i + m_j) and the mean zeta."""
    m_eff, _, zeta = _contact_constants(i, j)
    return 2.0 * zeta * math.sqrt(m_eff)


def peak_approach(i, j, v: float) -> float:
    """Largest approach of an impact: a linear contact's stiffness does not depend on it
    (``stiffness_shape`` is 1), so 0 serves [length]."""
    return 0.0


@step_kernel
def stiffness_shape(a):
    """A linear contact's stiffness does not change with the approach: 1."""
    return 1.0


def law_tables(params, mass, rep) -> tuple[np.ndarray, np.ndarray]:
    """The step loop's constants ``(law_wall (P, 2), law_pair (K, K, 2))`` from the particles'
    card constants ``params`` (P, 2: k_n, e), their masses and the kinds' representatives
    ``rep`` (:func:`hooke_tables`)."""
    return hooke_tables(params[:, 0], params[:, 1], mass, rep)


def kind_keys(params, mass) -> tuple:
    """What distinguishes particle kinds under this law besides the shared keys
    (x3dpd.physics.mixing.particle_kinds): its own constants k_n and e, and the mass its
    dashpot uses."""
    return (params[:, 0], params[:, 1], mass)


def hooke_tables(k, e, mass, rep) -> tuple[np.ndarray, np.ndarray]:
    """The step loop's constants: ``(law_wall (P, 2), law_pair (K, K, 2))`` of (k_n, c_n) for
    every particle on a rigid wall and every pair of particle kinds (representatives ``rep``),
    from per-particle stiffness ``k``, restitution ``e`` and mass."""
    k, e, mass = (np.asarray(v, dtype=np.float64) for v in (k, e, mass))
    zeta = np.array([damping_ratio(float(x)) for x in e])
    wall = np.column_stack([k, [dashpot(float(a), float(z), float(m))
                                for a, z, m in zip(k, zeta, mass)]]) if k.size else np.zeros((0, 2))
    pair = np.zeros((rep.shape[0], rep.shape[0], 2))
    for a, p in enumerate(rep):
        for b, q in enumerate(rep):
            kn = 2.0 * k[p] * k[q] / (k[p] + k[q])
            m_eff = mass[p] * mass[q] / (mass[p] + mass[q])
            pair[a, b] = kn, dashpot(kn, 0.5 * (zeta[p] + zeta[q]), m_eff)
    return wall, pair


@step_kernel
def wall_force(a, a_old, a_rate, p, particles, states, s, col, n_terms):
    """F = k_n a + c_n da/dt of particle ``p`` on a wall (``particles.law_wall[p]`` = k_n, c_n)."""
    return particles.law_wall[p, 0] * a + particles.law_wall[p, 1] * a_rate


@step_kernel
def pair_force(a, a_old, a_rate, pi, pj, ki, kj, particles, states, s, col, n_terms):
    """F = k_n a + c_n da/dt of a pair of kinds ki, kj (``particles.law_pair[ki, kj]``)."""
    return particles.law_pair[ki, kj, 0] * a + particles.law_pair[ki, kj, 1] * a_rate


@step_kernel
def stored_energy(fn, a, k):
    """U = 1/2 k_n a^2 [energy] (``fn``, the applied force, includes the dashpot: unused)."""
    return 0.5 * k * a * a
