"""Broad phase: x3dpd.geometry.cells.find_pairs against an O(N^2) numpy reference, and the
solver's Verlet pair list against the same reference during a run.

The reference (tests/reference.py: brute_pairs) decides |x_i - x_j|^2 < (R_i + R_j + skin)^2 with
the same floating-point operations as the kernels, so the lists must agree exactly, order included
(sorted by i, then j).
"""

from __future__ import annotations


import numpy as np
import pytest


import reference as ref
from factories import STEEL_E, STEEL_NU, STEEL_R, closed_box_deck

from x3dpd.geometry.cells import find_pairs
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation


def _cloud(
    n: int,
    seed: int,
    fill: float = 0.4,
    r_lo: float = 0.02,
    r_hi: float = 0.05,
    shape=(1.0, 1.0, 1.0),
):
    """n random centres (overlaps allowed) in a box sized for volume fraction ~fill."""
    rng = np.random.default_rng(seed)
    r = rng.uniform(r_lo, r_hi, n)
    vol = (4.0 / 3.0 * np.pi * r**3).sum() / fill
    box = np.asarray(shape, float) * (vol / np.prod(shape)) ** (1.0 / 3.0)
    return rng.uniform(0.0, 1.0, (n, 3)) * box, r


@pytest.mark.parametrize("n", [2, 10, 100, 1000, 5000])
@pytest.mark.parametrize("skin_factor", [0.0, 0.1, 0.5])
@pytest.mark.parametrize("ncav", [1, 3])
def test_cells_equal_brute_force(n, skin_factor, ncav):
    x, r = _cloud(n, seed=n + 7 * ncav + int(100 * skin_factor))
    cav = np.random.default_rng(n).integers(0, ncav, n)
    skin = skin_factor * r.max()
    got = find_pairs(x, r, cav, skin=skin, method="cells")
    want = ref.brute_pairs(x, r, cav, skin=skin)
    assert n < 100 or len(want) > n / (2 * ncav)  # dense: many pairs within each label
    np.testing.assert_array_equal(got, want)
    # "auto" (brute force below 64 particles) and "brute" agree too
    np.testing.assert_array_equal(find_pairs(x, r, cav, skin=skin), want)
    if n <= 1000:
        np.testing.assert_array_equal(find_pairs(x, r, cav, skin=skin, method="brute"), want)


@pytest.mark.parametrize("case", ["flat", "line", "coincident", "scattered", "one_radius"])
def test_cells_on_awkward_clouds(case):
    """Degenerate extents (all in a plane or on a line), coincident centres, a few particles far
    away (the grid is capped at ~8 n cells), identical radii on a touching lattice."""
    rng = np.random.default_rng(11)
    n = 800
    r = rng.uniform(0.01, 0.03, n)
    if case == "flat":
        x = np.c_[rng.uniform(0, 1, n), np.full(n, 0.5), rng.uniform(0, 1, n)]
    elif case == "line":
        x = np.c_[rng.uniform(0, 3, n), np.zeros(n), np.zeros(n)]
    elif case == "coincident":
        x = np.repeat(rng.uniform(0, 1, (n // 4, 3)), 4, axis=0)
    elif case == "scattered":
        x = rng.uniform(0, 1, (n, 3))
        x[:5] = rng.uniform(-1e4, 1e4, (5, 3))
    else:
        g = np.arange(10) * 0.05
        x = np.array(np.meshgrid(g, g, g[:8], indexing="ij")).reshape(3, -1).T
        r = np.full(n, 0.025)  # neighbours exactly touching: d = R_i + R_j
    for skin in (0.0, 0.01):
        np.testing.assert_array_equal(
            find_pairs(x, r, skin=skin, method="cells"), ref.brute_pairs(x, r, skin=skin)
        )


# --- the solver's Verlet list ------------------------------------------------------------------


def _dense_gas(n: int, size: float, r: float, seed: int):
    """Random non-overlapping centres (sequential addition) with random velocities."""
    rng = np.random.default_rng(seed)
    pts: list = []
    while len(pts) < n:
        p = rng.uniform(r * 1.05, size - r * 1.05, 3)
        if not pts or np.min(np.linalg.norm(np.array(pts) - p, axis=1)) > 2.02 * r:
            pts.append(p)
    return np.array(pts), rng.normal(size=(n, 3)) * 30.0


def test_solver_pair_list_after_every_rebuild():
    """100 particles (more than the brute-force limit of 64, so the solver uses the cell list) in
    a closed box, packing fraction ~30 %. At every rebuild the list equals the reference pairs
    within R_i + R_j + skin at the positions of the rebuild; every pair in contact is always in the
    list; and while the solver's displacement bound d allows it (skin - 2 d >= 0) every pair
    closer than R_i + R_j + skin - 2 d is in it (the Verlet guarantee)."""
    r, size = 0.05, 0.62
    pos, vel = _dense_gas(100, size, r, seed=5)
    dt = 2e-7  # ~40 steps per contact at the fastest impacts here
    sim = Simulation(build_model(closed_box_deck(pos, vel, dt=dt, size=(size,) * 3, radius=r)))
    sim.snapshot()
    s, k = sim.state, sim.setup
    p0, skin = k.p0, k.skin
    radius = k.radius

    def listed():
        m = int(s.npl[0])
        return np.stack([s.pl_i[:m], s.pl_j[:m]], axis=1)

    # at t0 (initialisation rebuilds)
    np.testing.assert_array_equal(listed(), ref.brute_pairs(s.x[p0:], radius, skin=skin))
    rebuilds = 0
    contacts = 0
    for _ in range(3000):
        before = s.x[p0:].copy()
        count = s.nbr[2]
        sim.advance(1)
        have = {tuple(p) for p in listed()}
        if s.nbr[2] > count:  # rebuilt at the start of this step, from `before`
            rebuilds += 1
            np.testing.assert_array_equal(listed(), ref.brute_pairs(before, radius, skin=skin))
        touching = ref.brute_pairs(s.x[p0:], radius)
        assert {tuple(p) for p in touching} <= have
        contacts += len(touching)
        # the list is never used past its guarantee (see test_list_is_rebuilt_before_it_is_used)
        margin = skin - 2.0 * s.nbr[0]
        assert margin >= 0.0
        must = ref.brute_pairs(s.x[p0:], radius, skin=margin)
        assert {tuple(p) for p in must} <= have
    print(f"\n{rebuilds} rebuilds, {contacts} pair-contacts in 3000 steps")
    assert rebuilds >= 5 and contacts > 0


def test_list_is_rebuilt_before_it_is_used():
    """Regression guard: the rebuild test used to compare the displacement accumulated BEFORE a
    step's drift with the skin, while the forces are evaluated AFTER it. Two spheres approach
    head-on at 50 in/s each (dt v = 5e-6 in) from a gap of skin + 1e-6 (just outside the list
    built at t0); after 1563 steps they overlap by 4e-6 in, and the old check (2 d = 0.015620 <
    skin = 0.015625 at the start of that step) skipped their force K a^{3/2} = 0.032 lbf."""
    dt, v, eps = 1e-7, 50.0, 1e-6
    skin = 0.25 * STEEL_R  # the solver's default skin (a quarter of the radius)
    c = np.array([0.5, 0.5, 0.5])
    d0 = 2 * STEEL_R + skin + eps
    deck = closed_box_deck([c - [d0 / 2, 0, 0], c + [d0 / 2, 0, 0]], [(v, 0, 0), (-v, 0, 0)], dt=dt)
    sim = Simulation(build_model(deck))
    sim.snapshot()
    s, p0 = sim.state, sim.setup.p0
    assert sim.setup.skin == skin and s.npl[0] == 0
    sim.advance(1563)
    a = 2 * STEEL_R - (s.x[p0 + 1, 0] - s.x[p0, 0])
    assert a == pytest.approx(4e-6, rel=1e-6)
    k = ref.hertz_k(STEEL_E / (2 * (1 - STEEL_NU**2)), STEEL_R / 2)
    # the force on the left sphere pushes it back (-x) by K a^{3/2}
    assert s.force[p0, 0] == pytest.approx(-k * a**1.5, rel=1e-9)
