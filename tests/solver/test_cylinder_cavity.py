"""The analytic cylindrical cavity through the solver (CYLINDER card, x3dpd.geometry.cylinder):
head-on impacts on its curved wall and on an end cap against Hertz's closed form, the same
trajectory as a finely triangulated cylinder within the facet error, and faster than it; a
cavity that turns conserves angular momentum (the lever terms of the reaction)."""

from __future__ import annotations

import math

import numpy as np


from bore_scenes import (
    BIG_R,
    LENGTH,
    V,
    angular_momentum,
    bore_deck,
    check_against_hertz,
    head_on_impact,
)
from bench_solver import best_seconds_per_step
from factories import STEEL_R

from x3dpd.geometry.cylinder import cylinder_coordinates, cylinder_mesh
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation


def test_head_on_impact_on_the_curved_wall_matches_hertz():
    e = np.array([0.0, 0.6, 0.8])  # radial direction, off the axes
    pos = np.array([0.4, 0.0, 0.0]) + (BIG_R - STEEL_R) * e

    def approach(x):
        _, rho, _ = cylinder_coordinates(x, [0, 0, 0], [LENGTH, 0, 0])
        return STEEL_R + rho - BIG_R

    check_against_hertz(*head_on_impact("cylinder", pos, V * e, approach))


def test_head_on_impact_on_an_end_cap_matches_hertz():
    pos = np.array([LENGTH - STEEL_R, 0.05, -0.1])

    def approach(x):
        return x[:, 0] - (LENGTH - STEEL_R)

    check_against_hertz(*head_on_impact("cylinder", pos, [V, 0.0, 0.0], approach))


# --- the same scene, analytic and triangulated -------------------------------------------------

#: The beam decks' spheres (radius 0.03125 in) in a cylinder of beam_64's volume.
SMALL_R = 0.03125
BEAM_L = 0.263
BEAM_RC = 0.372 / math.sqrt(math.pi)
FACETS = 128


def _bouncer(facets, tmax=0.05, itrac=500):
    """One sphere with friction leaving the axis at 20 in/s towards the middle of a facet of
    the n-gon (where the facet's normal is the radial direction) and at 5 in/s along the axis,
    no gravity: three impacts on the curved wall and one on a cap in 0.05 s."""
    verts, _ = cylinder_mesh([0, 0, 0], [BEAM_L, 0, 0], BEAM_RC, FACETS)
    mid = 0.5 * (verts[0] + verts[1])
    e = mid / np.linalg.norm(mid)
    vel = 20.0 * e + [5.0, 0.0, 0.0]
    deck = bore_deck(
        "cylinder",
        [[BEAM_L / 2, 0.0, 0.0]],
        [vel],
        dt=2e-7,
        tmax=tmax,
        mu=0.3,
        facets=facets,
        itrac=itrac,
        radius=SMALL_R,
        e=27.5e6,
        length=BEAM_L,
        big_r=BEAM_RC,
    )
    return Simulation(build_model(deck))


def test_analytic_and_triangulated_cylinders_agree_within_the_facet_error():
    runs = []
    for facets in (None, FACETS):
        sim = _bouncer(facets)
        block = sim.advance(250_000)
        runs.append(block.data[:, 1])
    analytic, meshed = runs
    # the sphere did what the scene says: three radial reversals, one axial
    _, rho, _ = cylinder_coordinates(analytic[:, :3], [0, 0, 0], [BEAM_L, 0, 0])
    radial_speed = np.diff(rho)
    assert np.count_nonzero(np.diff(np.sign(radial_speed[radial_speed != 0])) != 0) == 5
    assert np.count_nonzero(np.diff(np.sign(analytic[:, 3])) != 0) == 1
    # Facet error: the facets' planes lie inside the analytic wall by at most the sagitta
    # delta = R (1 - cos(pi/n)) (6.3e-5 in for n = 128); at a facet's middle, where this
    # sphere hits, by exactly delta. Each of the three wall impacts then comes early by
    # delta / v_r and shifts the reflected track by 2 delta; along the axis friction's impulse
    # comes as early (a shift v_x delta / v_r, a quarter of delta). So the tracks may differ
    # by up to 3 x 2 delta = 6 delta, no more.
    delta = BEAM_RC * (1.0 - math.cos(math.pi / FACETS))
    diff = np.max(np.abs(analytic[:, :3] - meshed[:, :3]))
    assert diff <= 6.0 * delta, (diff, delta)
    # ...and not trivially: the two do differ (the facets are there)
    assert diff > 0.1 * delta


def test_analytic_cylinder_is_faster_than_the_triangulated_one():
    """Seconds per step of the same scene, the best of three interleaved windows each (the
    best of several filters out other processes' load). The triangulated cylinder has
    2 n + 2 wall nodes to move, n + 2 face planes and a list of facets near each particle;
    the analytic one three entries per particle."""
    sims = {f: _bouncer(f, tmax=1.0, itrac=10**9) for f in (None, FACETS)}
    for sim in sims.values():
        sim.advance(2000)
    best = best_seconds_per_step(sims, 20_000)
    print(
        f"\nper step: analytic {best[None] * 1e9:.0f} ns, {FACETS} facets "
        f"{best[FACETS] * 1e9:.0f} ns"
    )
    assert best[None] < best[FACETS]


def test_a_turning_cylinder_conserves_momentum_and_energy():
    """A light cavity free to move and turn (no springs, no gravity) hit by spheres with
    friction: no external force or moment acts, so the total angular momentum stays put --
    only if the reaction's moment l x F goes to the cavity and the wall point moves with
    omega x l (without them: 16 % lost here). The energy ledger balances either way (the
    friction's work is formed from the same velocities as its power on the cavity), within
    the integration error.

    Tolerances: angular momentum measured constant to 2e-5 of its size (second-order drift of
    the rigid body's rotation kicks); 1e-3 separates that from a missing lever by 100x. The
    energy residual stays below 1e-4 of the initial energy (elastic Hertz contacts: only
    friction dissipates)."""
    e1 = np.array([0.0, 0.6, 0.8])
    e2 = np.array([0.0, -0.8, 0.6])
    pos = [[0.3, 0.0, 0.0] + 0.1 * e1, [0.5, 0.0, 0.0] - 0.1 * e2]
    vel = [15.0 * e1 + [4.0, 0.0, 0.0], -12.0 * e2 + [-6.0, 0.0, 0.0]]
    free = dict(
        structure_mass=1e-5,
        rotary_inertia=1e-7,
        stiffness=0.0,
        damping=0.0,
        transverse_stiffness=0.0,
    )
    deck = bore_deck(
        "cylinder",
        pos,
        vel,
        dt=2e-7,
        tmax=1.0,
        mu=0.4,
        free_dofs=(1, 2, 3, 4, 5, 6),
        itrac=1000,
        structure=free,
    )
    model = build_model(deck)
    assert "rigid_rotation" in model.effects
    sim = Simulation(model)
    first = sim.snapshot()
    l0 = angular_momentum(model, sim.state)
    block = sim.advance(150_000)
    drift = np.linalg.norm(angular_momentum(model, sim.state) - l0) / np.linalg.norm(l0)
    assert drift < 1e-3, drift
    energy = np.concatenate([first.energy, block.energy])
    assert energy[-1, 7] > 0.05 * energy[0, 10]  # friction did work: the spheres hit walls
    assert np.linalg.norm(block.data[-1, 0, 6:9]) > 1.0  # the cavity turns (rad/s)
    residual = np.abs(energy[:, 11]).max()
    assert residual < 1e-4 * energy[0, 10], residual / energy[0, 10]
