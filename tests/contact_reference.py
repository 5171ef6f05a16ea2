"""Slow, obviously correct integrations of single contacts, the references of the contact-law
tests (tests/physics/test_mindlin.py, test_chung_ooi.py)."""

from __future__ import annotations

import math


def hertz_mindlin_impact(mass, radius, young, nu, mu, vn, vt, h):
    """A solid sphere (``mass``, ``radius``, Young's modulus and Poisson's ratio) hits a rigid
    floor at normal speed ``vn`` and tangential speed ``vt`` without spin: the Hertz normal
    force and Mindlin's tangential spring under x3dpd.physics.mindlin's rules (force history,
    rescaled on unloading, Coulomb's limit with one ``mu``), on the rigid-body equations, by
    symplectic Euler at step ``h``. Returns the contact point's slip u + w R, the normal speed
    and the spin w after the impact."""
    inertia = 0.4 * mass * radius * radius
    k = 4.0 / 3.0 * young / (1.0 - nu**2) * math.sqrt(radius)
    g_star = young / (2.0 * (1.0 + nu)) / (2.0 - nu)
    d, d_dot, u, w, f, k_old = 0.0, vn, vt, 0.0, 0.0, 0.0
    while d >= 0.0 or d_dot > 0.0:
        fn = k * max(d, 0.0) ** 1.5
        kt = 8.0 * g_star * math.sqrt(radius * max(d, 0.0))
        if kt < k_old:
            f *= kt / k_old
        k_old = kt
        f -= kt * (u + w * radius) * h          # the contact point slips at u + w R
        if abs(f) > mu * fn:
            f = math.copysign(mu * fn, f)
        d_dot -= fn / mass * h
        d += d_dot * h
        u += f / mass * h
        w += f * radius / inertia * h
    return u + w * radius, -d_dot, w
