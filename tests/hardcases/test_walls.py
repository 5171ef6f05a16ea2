"""Impacts where walls meet: on the seam between a face's two triangles, into an edge and into a
corner of a closed box, and oblique/grazing impacts with friction.

Closed forms (Hertz on a rigid flat wall, Johnson §4.2; rigid-body impact with Coulomb friction):
each wall a sphere meets at normal speed v_n takes it to the approach
a_max = (5 m v_n^2 / 4K)^(2/5), K = 4/3 E/(1-nu^2) sqrt(R), and an elastic, frictionless impact
returns the velocity mirrored. A force counted twice (two triangles of one face, two faces meeting
at an edge) would stiffen the wall to 2K and shorten a_max by 2^(-2/5) = 0.76. With friction mu
and restitution 1: a sphere that reaches rolling leaves with v_t' = 5/7 v_t (when
2/7 v_t < 2 mu v_n), else it slides throughout: v_t' = v_t - 2 mu v_n, omega' R = 5 mu v_n.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import STEEL_E, STEEL_NU, STEEL_R, closed_box_deck, sphere_mass

from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation

V = 62.832
GAP = 1e-4


def a_max(vn, r=STEEL_R):
    k = 4.0 / 3.0 * STEEL_E / (1 - STEEL_NU**2) * math.sqrt(r)
    return (5.0 * sphere_mass(r) * vn * vn / (4.0 * k)) ** 0.4


def t_contact(vn, r=STEEL_R):
    m = sphere_mass(r)
    e_star = STEEL_E / (1 - STEEL_NU**2)
    return 2.868 * (m * m / (r * e_star**2 * vn)) ** 0.2


def run_box(pos, vel, *, friction="regularized", mu=0.0, steps_per_contact=200):
    vn = min(abs(c) for c in vel if c != 0.0)
    dt = t_contact(vn) / steps_per_contact
    deck = closed_box_deck([pos], [vel], dt=dt, mu=mu)
    sim = Simulation(build_model(deck), friction=friction)
    flight = GAP * math.sqrt(3) / vn
    block = sim.advance(int((2 * flight + 1.5 * t_contact(vn)) / dt) + 10)
    return block.data[:, 0, :]  # (T, 9) of the sphere


@pytest.mark.parametrize(
    "where, direction",
    [
        ("seam", (0.0, -1.0, 0.0)),  # floor y = 0 at x = z: the diagonal both triangles share
        ("edge", (1.0, 1.0, 0.0)),  # the edge x = 1, y = 1
        ("corner", (1.0, 1.0, 1.0)),  # the corner (1, 1, 1): three faces, each two triangles
    ],
)
def test_impacts_where_walls_meet_bounce_back_with_single_counted_forces(where, direction):
    d = np.asarray(direction) / np.linalg.norm(direction)
    target = {"seam": (0.3, 0.0, 0.3), "edge": (1.0, 1.0, 0.5), "corner": (1.0, 1.0, 1.0)}[where]
    pos = np.array(target, float)
    for ax in range(3):
        if d[ax] != 0.0:
            pos[ax] = target[ax] - np.sign(d[ax]) * (STEEL_R + GAP)
    vel = V * d
    h = run_box(tuple(pos), tuple(vel))
    x, v = h[:, :3], h[:, 3:6]
    assert np.all(np.isfinite(h))
    assert np.all((x > 0) & (x < 1))  # still inside the box
    np.testing.assert_allclose(v[-1], -vel, atol=2e-3 * V)  # mirrored, elastic
    for ax in np.flatnonzero(d):
        wall = target[ax]
        approach = STEEL_R - np.abs(wall - x[:, ax])
        # sampling the peak at 200 steps per contact errs by < (pi/200)^2/2 ~ 1e-4
        assert approach.max() == pytest.approx(a_max(V * abs(d[ax])), rel=2e-3)


@pytest.mark.parametrize("friction", ["regularized", "coulomb"])
@pytest.mark.parametrize("vt, vn", [(10.0, 10.0), (100.0, 10.0)], ids=["45deg", "grazing"])
def test_oblique_and_grazing_impacts_with_friction(friction, vt, vn):
    mu = 0.3
    pos = (0.3, STEEL_R + GAP, 0.5)
    h = run_box(pos, (vt, -vn, 0.0), friction=friction, mu=mu)
    v_out, w_out = h[-1, 3:6], h[-1, 6:9]
    assert v_out[1] == pytest.approx(vn, rel=5e-3)
    if 2.0 / 7.0 * vt < 2 * mu * vn:
        expect_t, expect_spin = 5.0 / 7.0 * vt, 5.0 / 7.0 * vt
    else:
        expect_t, expect_spin = vt - 2 * mu * vn, 5 * mu * vn
    assert v_out[0] == pytest.approx(expect_t, rel=1e-2)
    # rolling on the floor along +x spins about -z: omega_z R = -v_x
    assert -w_out[2] * STEEL_R == pytest.approx(expect_spin, rel=2e-2)
    m = sphere_mass()
    inertia = 0.4 * m * STEEL_R**2
    e_in = 0.5 * m * (vt**2 + vn**2)
    e_out = 0.5 * m * np.sum(v_out**2) + 0.5 * inertia * np.sum(w_out**2)
    assert e_out <= e_in * (1 + 1e-3)  # friction never adds energy (cf. LAMMPS PR #5007)
