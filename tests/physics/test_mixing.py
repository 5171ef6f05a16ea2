"""Pair constants by particle kind (x3dpd.physics.mixing) against the mixing rules written out."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.physics.mixing import pair_constant_table, particle_kinds


def test_kinds_are_numbered_by_first_appearance():
    radius = [2.0, 1.0, 2.0, 1.0, 3.0]
    kind, rep = particle_kinds(radius, [5.0] * 5, [1.0] * 5, [0.3] * 5)
    assert kind.tolist() == [0, 1, 0, 1, 2]
    assert rep.tolist() == [0, 1, 4]


def test_any_differing_property_makes_a_new_kind():
    ones = [1.0, 1.0]
    for column in range(4):
        props = [list(ones) for _ in range(4)]
        props[column][1] = 1.0 + 2.0**-52  # one ulp apart is another kind
        kind, _ = particle_kinds(*props)
        assert kind.tolist() == [0, 1], column
    assert particle_kinds([], [], [], [])[0].shape == (0,)


def test_identical_spheres_give_the_report_hertz_constant():
    r, e, nu = 0.0625, 30e6, 0.33
    c = e / (1 - nu**2)  # plane-strain modulus of one body
    kind, rep = particle_kinds([r, r], [c, c], [7.0, 7.0], [0.3, 0.3])
    table = pair_constant_table([r, r], [c, c], [7.0, 7.0], [0.3, 0.3], rep)
    assert table.shape == (1, 1, 3)
    k, m_t, mu = table[0, 0]
    # the loop forms k (E_i + E_j)/(1 - nu^2) a^{3/2}; Hertz: 4/3 E* sqrt(R*), E* = E/(2(1-nu^2))
    assert k * 2 * c == pytest.approx(4 / 3 * e / (2 * (1 - nu**2)) * math.sqrt(r / 2), rel=1e-15)
    assert m_t == pytest.approx(1 / 14, rel=1e-15) and mu == pytest.approx(0.3, rel=1e-15)


def test_dissimilar_spheres_follow_the_series_rules():
    radius, cinst, inv_mt, mu = [1.0, 3.0], [2.0, 6.0], [4.0, 12.0], [0.2, 0.6]
    _, rep = particle_kinds(radius, cinst, inv_mt, mu)
    table = pair_constant_table(radius, cinst, inv_mt, mu, rep)
    k, m_t, mu_ab = table[0, 1]
    # springs in series: k (c_i + c_j) = 4/3 sqrt(R*) / (1/c_i + 1/c_j)
    r_star = 1 / (1 / 1.0 + 1 / 3.0)
    assert k * (2.0 + 6.0) == pytest.approx(
        4 / 3 * math.sqrt(r_star) / (1 / 2.0 + 1 / 6.0), rel=1e-15
    )
    assert m_t == pytest.approx(1 / 16, rel=1e-15) and mu_ab == pytest.approx(0.4, rel=1e-15)
    np.testing.assert_array_equal(table[0, 1], table[1, 0])  # symmetric, bit for bit
