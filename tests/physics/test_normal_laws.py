"""The normal-law functions the step loop runs (x3dpd.physics.normal_laws), called directly with
the loop's own bundle, against the closed forms of their modules' docstrings."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from x3dpd.deck.cards import Deck, Hooke
from x3dpd.physics import hooke, maxwell
from x3dpd.physics.hertz import (
    effective_modulus_pair,
    effective_modulus_wall,
    effective_radius,
    hertz_constant,
    hertz_energy,
)
from x3dpd.physics.mixing import pair_constant_table, particle_kinds
from x3dpd.physics.normal_laws import (
    NORMAL_LAW_API,
    NORMAL_LAW_CHECKS,
    NORMAL_LAW_SETUP,
    NORMAL_LAWS,
)
from x3dpd.solver.bundles import Particles
from x3dpd.solver.contact_lists import S_H

R, E0, E1, NU, TAU, DT = 0.0625, 3.0e7, 1.0e7, 0.3, 2e-6, 1e-8
MASS = 7.5e-7


def _particles(e_terms=(E0,), taus=(math.inf,), hooke_law=None) -> Particles:
    """Two identical particles, the constants arranged as x3dpd.solver.state builds them."""
    moduli = np.array([e_terms, e_terms], dtype=float)
    ep = moduli / (1.0 - NU**2)
    radius = np.full(2, R)
    kw = 4.0 / 3.0 * ep * math.sqrt(R)
    decay, half = np.ones_like(moduli), np.ones_like(moduli)
    for k, tau in enumerate(taus[1:], start=1):
        decay[:, k], half[:, k] = maxwell.maxwell_step_factors(tau, DT)
    inv_mt = np.full(2, 1.0 / MASS + R**2 / (0.4 * MASS * R**2))
    mu = np.zeros(2)
    kind, rep = particle_kinds(radius, ep.sum(axis=1), inv_mt, mu)
    pair_c = pair_constant_table(radius, ep.sum(axis=1), inv_mt, mu, rep)
    law_wall, law_pair = np.zeros((2, 2)), np.zeros((1, 1, 2))
    if hooke_law is not None:
        kn, e = hooke_law
        law_wall, law_pair = hooke.hooke_tables(
            np.full(2, kn), np.full(2, e), np.full(2, MASS), rep
        )
    return Particles(
        0,
        radius,
        kw,
        ep,
        kind,
        pair_c,
        decay,
        half,
        mu,
        inv_mt,
        np.zeros(2, np.int64),
        law_wall,
        law_pair,
        np.zeros((2, 4)),
        np.zeros((1, 1, 4)),
    )


def test_every_registered_law_provides_the_loop_api():
    for name, module in NORMAL_LAWS.items():
        wanted = NORMAL_LAW_API + NORMAL_LAW_CHECKS + NORMAL_LAW_SETUP
        missing = [a for a in wanted if not hasattr(module, a)]
        assert not missing, f"{name}: {missing}"


def test_a_law_with_a_card_is_read_by_its_card_and_params():
    """The model builder finds a law's records as the deck's field named after its CARD and
    each record's constants by its PARAMS (x3dpd.model.build_particles._normal_law): the names
    must be the deck reader's. One law, the default, has no card."""
    deck_fields = {f.name: f for f in dataclasses.fields(Deck)}
    assert [name for name, law in NORMAL_LAWS.items() if law.CARD is None] == ["lee_radok"]
    for name, law in NORMAL_LAWS.items():
        if law.CARD is None:
            assert law.PARAMS == () and law.WALL_STIFFNESS is None
            continue
        assert law.CARD.lower() in deck_fields, name
        record = {"HOOKE": Hooke}[law.CARD]
        assert {p.lower() for p in law.PARAMS} <= {f.name for f in dataclasses.fields(record)}
        assert law.WALL_STIFFNESS in (None, *law.PARAMS)


def test_the_hooke_tables_from_its_card_constants():
    """law_tables and kind_keys as the solver's setup calls them: k_n and c_n = 2 zeta
    sqrt(m* k_n) per particle on a wall and per pair of kinds (harmonic mean of k, mean of
    zeta), zeta from e (computed here), and the constants that tell kinds apart."""
    params = np.array([[1e4, 0.8], [3e4, 0.5]])
    mass = np.array([2e-3, 5e-3])
    wall, pair = hooke.law_tables(params, mass, np.array([0, 1]))

    def zeta(e):
        return -math.log(e) / math.sqrt(math.pi**2 + math.log(e) ** 2)

    assert wall[1, 0] == 3e4
    assert wall[1, 1] == pytest.approx(2 * zeta(0.5) * math.sqrt(5e-3 * 3e4), rel=1e-14)
    k01 = 2 * 1e4 * 3e4 / 4e4
    m01 = 2e-3 * 5e-3 / 7e-3
    assert pair[0, 1, 0] == pytest.approx(k01, rel=1e-15)
    assert pair[0, 1, 1] == pytest.approx(
        2 * 0.5 * (zeta(0.8) + zeta(0.5)) * math.sqrt(m01 * k01), rel=1e-14
    )
    keys = hooke.kind_keys(params, mass)
    assert [list(k) for k in keys] == [[1e4, 3e4], [0.8, 0.5], list(mass)]


@pytest.mark.parametrize("a", [1e-7, 3e-5, 2e-4])
def test_lee_radok_without_maxwell_terms_is_hertz(a):
    p = _particles()
    states = np.zeros((1, S_H + 1))
    k_wall = hertz_constant(effective_modulus_wall(E0, NU), effective_radius(R))
    f = maxwell.wall_force(a, 0.0, 0.0, 0, p, states, 0, S_H, 0)
    # K a^{3/2} in two roundings: 4 ulp
    assert f == pytest.approx(k_wall * a**1.5, rel=1e-15 * 4)
    k_pair = hertz_constant(effective_modulus_pair(E0, NU, E0, NU), effective_radius(R, R))
    f = maxwell.pair_force(a, 0.0, 0.0, 0, 1, 0, 0, p, states, 0, S_H, 0)
    # the pair factor is built from sqrt and products in another order: 1e-14
    assert f == pytest.approx(k_pair * a**1.5, rel=1e-14)
    # stored energy 2/5 F a is Hertz's 2/5 K a^{5/2}
    assert maxwell.stored_energy(k_wall * a**1.5, a, 0.0) == pytest.approx(
        hertz_energy(a, k_wall), rel=1e-14
    )


def test_lee_radok_relaxes_at_constant_approach():
    """Approach jumps to a and stays: the Maxwell term's force decays as e^{-t/tau} from
    e^{-dt/2tau} K_1 a^{3/2} (the report's midpoint weight), the Hertz term stays K_0 a^{3/2}."""
    p = _particles((E0, E1), (math.inf, TAU))
    states = np.zeros((1, S_H + 1))
    a = 5e-5
    k0 = hertz_constant(effective_modulus_wall(E0, NU), effective_radius(R))
    k1 = hertz_constant(effective_modulus_wall(E1, NU), effective_radius(R))
    f = maxwell.wall_force(a, 0.0, 0.0, 0, p, states, 0, S_H, 1)
    for n in range(1, 400):
        f = maxwell.wall_force(a, a, 0.0, 0, p, states, 0, S_H, 1)
        want = k0 * a**1.5 + math.exp(-DT / (2 * TAU)) * k1 * a**1.5 * math.exp(-n * DT / TAU)
        # n steps of a product of rounded factors: n ulp of the history, 1e-13 covers 400
        assert f == pytest.approx(want, rel=1e-13)


def test_lee_radok_pair_carries_both_bodies_histories():
    p = _particles((E0, E1), (math.inf, TAU))
    states = np.zeros((1, S_H + 2))
    a = 4e-5
    maxwell.pair_force(a, 0.0, 0.0, 0, 1, 0, 0, p, states, 0, S_H, 1)
    # identical bodies: equal histories, together the series modulus E1/(2(1-nu^2)) of Eq. 24
    assert states[0, S_H] == states[0, S_H + 1]
    k1 = hertz_constant(effective_modulus_pair(E1, NU, E1, NU), effective_radius(R, R))
    # each body's term carries the weight c_i c_j/(c_i+c_j)^2 = 1/4 of identical bodies, so
    # the two histories add up to e^{-dt/2tau} K_1 a^{3/2} with the pair's K_1 (report Eq. 24)
    want = math.exp(-DT / (2 * TAU)) * k1 * a**1.5
    assert states[0, S_H] + states[0, S_H + 1] == pytest.approx(want, rel=1e-14)


def test_hooke_force_and_energy():
    kn, e = 1.0e4, 0.8
    p = _particles(hooke_law=(kn, e))
    zeta = -math.log(e) / math.sqrt(math.pi**2 + math.log(e) ** 2)
    c_wall = 2.0 * zeta * math.sqrt(MASS * kn)
    c_pair = 2.0 * zeta * math.sqrt(0.5 * MASS * kn)
    a, rate = 2e-5, -3.0
    states = np.zeros((1, S_H + 1))
    assert hooke.wall_force(a, 0.0, rate, 0, p, states, 0, S_H, 0) == pytest.approx(
        kn * a + c_wall * rate, rel=1e-15 * 4
    )
    assert hooke.pair_force(a, 0.0, rate, 0, 1, 0, 0, p, states, 0, S_H, 0) == pytest.approx(
        kn * a + c_pair * rate, rel=1e-15 * 4
    )
    assert hooke.stored_energy(123.0, a, kn) == pytest.approx(0.5 * kn * a * a, rel=1e-15)
    assert not hooke.CLAMPED and maxwell.CLAMPED


def test_hooke_rejects_a_restitution_outside_0_1():
    for bad in (0.0, -0.1, 1.2):
        with pytest.raises(ValueError):
            hooke.damping_ratio(bad)
    assert hooke.damping_ratio(1.0) == 0.0
