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
        f -= kt * (u + w * radius) * h  # the contact point slips at u + w R
        if abs(f) > mu * fn:
            f = math.copysign(mu * fn, f)
        d_dot -= fn / mass * h
        d += d_dot * h
        u += f / mass * h
        w += f * radius / inertia * h
    return u + w * radius, -d_dot, w


def hooke_oblique_beta(kn, e, nu, m_n, inv_mt, mu, vn, slip_in, steps, dashpot_rests=True):
    """beta = -v_s'/v_s of a HOOKE contact (k_n a + c_n da/dt, unclamped, c_n = 2 zeta
    sqrt(m_n k_n)) met at normal speed ``vn`` with the contact points slipping at ``slip_in``:
    the tangential spring k_t = 2(1-nu)/(2-nu) k_n with its dashpot c_t = c_n sqrt(k_t/k_n),
    Coulomb's limit mu |F_N|, on the relative normal motion (mass ``m_n``) and the relative slip
    (1/m_t = ``inv_mt``), by symplectic Euler at ``steps`` steps per contact. Sliding, the
    spring takes the limited force (``dashpot_rests``: x3dpd.physics.mindlin) or the limited
    force minus the dashpot's (LAMMPS's linear_history)."""
    le = math.log(e)
    zeta = -le / math.sqrt(math.pi**2 + le * le)
    cn = 2.0 * zeta * math.sqrt(m_n * kn)
    kt = 2.0 * (1.0 - nu) / (2.0 - nu) * kn
    ct = cn * math.sqrt(kt / kn)
    h = math.pi / (math.sqrt(kn / m_n) * math.sqrt(1.0 - zeta * zeta)) / steps
    a, a_dot, slip, spring = 0.0, vn, slip_in, 0.0
    while True:
        a += a_dot * h
        if a <= 0.0:
            return -slip / slip_in
        fn = kn * a + cn * a_dot
        spring -= kt * slip * h
        f = spring - ct * slip
        if abs(f) > mu * abs(fn):
            f = math.copysign(mu * abs(fn), f)
            spring = f if dashpot_rests else f + ct * slip
        a_dot -= fn / m_n * h
        slip += inv_mt * f * h
