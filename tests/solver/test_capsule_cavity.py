"""The analytic capsule cavity through the solver (CAPSULE card, x3dpd.geometry.capsule):
head-on impacts on a hemispherical end and on the cylindrical part against Hertz's closed
form; the same trajectory as a finely triangulated capsule within the facet error; a free
capsule that turns conserves angular momentum (the lever terms of the reaction) and balances
its energy ledger."""

from __future__ import annotations

import math

import numpy as np
import pytest


from bore_scenes import (
    BIG_R,
    LENGTH,
    V,
    angular_momentum,
    bore_deck,
    check_against_hertz,
    head_on_impact,
)
from factories import STEEL_R

from x3dpd.geometry.capsule import capsule_mesh
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation


def _segment_distance(x, a, b):
    """Distance of points (N, 3) to the segment a-b (the capsule's axis)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    u = b - a
    t = np.clip((x - a) @ u / (u @ u), 0.0, 1.0)
    return np.linalg.norm(x - a - t[:, None] * u, axis=1)


def _approach(x):
    """Overlap r + |p - q| - R of a sphere at p with the capsule wall (q: nearest axis point)."""
    return STEEL_R + _segment_distance(x, [0, 0, 0], [LENGTH, 0, 0]) - BIG_R


@pytest.mark.parametrize("end", ["A", "B"])
def test_head_on_impact_on_a_hemispherical_end_matches_hertz(end):
    """Sphere touching at C + (R - r) e, C the cap centre (A = origin or B), e a unit vector
    off the axis pointing beyond C (e . x < 0 at A, > 0 at B), moving along e: the wall normal
    there is e all through the contact."""
    if end == "A":
        c, e = np.zeros(3), np.array([-0.48, 0.6, -0.64])
    else:
        c, e = np.array([LENGTH, 0.0, 0.0]), np.array([0.48, 0.6, 0.64])
    check_against_hertz(*head_on_impact("capsule", c + (BIG_R - STEEL_R) * e, V * e, _approach))


def test_head_on_impact_on_the_cylindrical_part_matches_hertz():
    e = np.array([0.0, 0.6, 0.8])  # radial direction, off the axes
    pos = np.array([0.4, 0.0, 0.0]) + (BIG_R - STEEL_R) * e
    check_against_hertz(*head_on_impact("capsule", pos, V * e, _approach))


# --- the same scene, analytic and triangulated -------------------------------------------------

#: The beam decks' spheres (radius 0.03125 in) in a capsule of the beam cylinder's radius.
SMALL_R = 0.03125
CAP_L = 0.6
CAP_R = 0.372 / math.sqrt(math.pi)
FACETS = 32
SPEED = 20.0


def facet_error(big_r: float, n: int) -> float:
    """Largest depth of capsule_mesh's facets below the wall, R (1 - cos(pi/n) cos(pi/(4 m))),
    m = max(2, n // 4) latitude rings per hemisphere (checked against the mesh in
    tests/geometry/test_capsule.py: each facet's plane is no deeper)."""
    m = max(2, n // 4)
    return big_r * (1.0 - math.cos(math.pi / n) * math.cos(math.pi / (4 * m)))


def _aim():
    """The meshed capsule's plane of mirror symmetry through the middle of a facet and the
    direction nu of a facet of the hemisphere at B in that plane, ~60 degrees from the axis:
    a sphere moving from B along nu hits that facet and the analytic wall head-on (normal nu
    both), comes back through B and zigzags towards A in the plane, meeting facets of the
    cylindrical part at their middle line (there the facets' normal is the radial direction,
    as the wall's). Returns nu, the unit normal of the plane, and the depth of nu's facet."""
    b = np.array([CAP_L, 0.0, 0.0])
    verts, tris = capsule_mesh([0, 0, 0], b, CAP_R, FACETS)
    ring = verts[np.abs(verts[:, 0] - CAP_L) < 1e-12] - b  # the equator at B, radial
    ring = ring[np.argsort(np.arctan2(ring[:, 2], ring[:, 1]))]
    mids = 0.5 * (ring + np.roll(ring, -1, axis=0))
    mids /= np.linalg.norm(mids, axis=1)[:, None]
    e = mids[0]
    assert np.min(np.linalg.norm(mids + e, axis=1)) < 1e-12  # -e: a facet's middle too
    plane = np.cross([1.0, 0.0, 0.0], e)
    p0, p1, p2 = (verts[tris[:, k]] for k in range(3))
    normal = np.cross(p1 - p0, p2 - p0)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    beyond = np.min(np.stack([p0[:, 0], p1[:, 0], p2[:, 0]]), axis=0) >= CAP_L - 1e-12
    cand = np.flatnonzero(beyond & (np.abs(normal @ plane) < 1e-12) & (normal @ e > 0))
    k = cand[np.argmin(np.abs(normal[cand, 0] - 0.5))]
    nu = normal[k]
    depth = CAP_R - nu @ (p0[k] - b)
    # the foot of the normal from B lies inside the facet, a planar trapezoid of two coplanar
    # triangles (both rings' chords are perpendicular to the mirror plane), away from its outer
    # edges (by more than 0.1 of its size; the contact patch, sqrt(r a_max) ~ 2e-3 in, is
    # smaller): the sphere meets a face, not a crease. It may lie near the shared diagonal.
    foot = b + (CAP_R - depth) * nu
    twins = np.flatnonzero(beyond & (np.linalg.norm(normal - nu, axis=1) < 1e-9))
    assert len(twins) == 2
    shared = set(tris[twins[0]].tolist()) & set(tris[twins[1]].tolist())
    margins = []
    for j in twins:
        c0, c1, c2 = p0[j], p1[j], p2[j]
        w1, w2, _ = np.linalg.solve(np.stack([c1 - c0, c2 - c0, nu], axis=1), foot - c0)
        w = np.array([1.0 - w1 - w2, w1, w2])
        if w.min() >= 0.0:
            margins.append(min(w[q] for q in range(3) if tris[j, q] in shared))
    assert margins and max(margins) > 0.1, margins
    return nu, plane, depth


def _zigzag(facets, tmax=0.062, itrac=100):
    """One sphere with friction from B along nu at 20 in/s, no gravity: one head-on impact on
    the hemisphere at B, then two oblique ones on the cylindrical part, in 0.062 s. 32 facets
    around (8 latitude rings per hemisphere, 1024 triangles): the cylinder test's 128
    would make 16384 triangles, minutes of model building."""
    nu, _, _ = _aim()
    deck = bore_deck(
        "capsule",
        [[CAP_L, 0.0, 0.0]],
        [SPEED * nu],
        dt=2e-7,
        tmax=tmax,
        mu=0.3,
        facets=facets,
        itrac=itrac,
        radius=SMALL_R,
        e=27.5e6,
        length=CAP_L,
        big_r=CAP_R,
    )
    return Simulation(build_model(deck))


@pytest.mark.validate  # its own compiled loop; CI covers the same code through the
# cylinder's test of it and the capsule's locator tests (`python -m pytest -m validate`)
def test_analytic_and_triangulated_capsules_agree_within_the_facet_error():
    nu, plane, depth_h = _aim()
    runs = []
    for facets in (None, FACETS):
        sim = _zigzag(facets)
        block = sim.advance(310_000)
        runs.append(block.data[:, 1])
    analytic, meshed = runs
    # the sphere did what the scene says: one head-on impact on the hemisphere at B (its
    # centre beyond B), then two on the cylindrical part, all in the mirror plane, never near
    # the hemisphere at A. An impact is a maximum of the centre's distance from the axis
    # segment, within 4e-4 of R - r (20 in/s over the 2e-5 s between outputs).
    x = analytic[:, :3]
    dist = _segment_distance(x, [0, 0, 0], [CAP_L, 0, 0])
    peaks = np.flatnonzero((dist[1:-1] > dist[:-2]) & (dist[1:-1] >= dist[2:])) + 1
    assert len(peaks) == 3, peaks
    assert np.all(dist[peaks] > CAP_R - SMALL_R - 4e-4), dist[peaks]
    assert x[peaks[0], 0] > CAP_L and np.all(x[peaks[1:], 0] < CAP_L - SMALL_R)
    assert x[:, 0].min() > SMALL_R
    assert np.abs(np.concatenate([analytic, meshed])[:, :3] @ plane).max() < 1e-9
    # Facet error. A facet's plane lies inside the wall by d <= delta, the claimed largest
    # facet depth (delta_c = R (1 - cos(pi/n)) on the cylindrical part, exactly, for these
    # facets met at their middle line). Here every impact has the same normal in both runs
    # (head-on along nu, then the radial direction), so the two tracks differ by a shift D:
    # - the head-on impact comes d_h / v early and sends the sphere back 2 d_h ahead: |D| is
    #   2 d_h, along nu;
    # - an oblique one mirrors both tracks in parallel planes delta_c apart: D's normal part
    #   D_n flips and grows by 2 delta_c; friction's tangential impulse (|dv_t| <= mu |dv_n|
    #   = 2 mu v_n) comes (|D_n| + delta_c) / v_n early, so D's tangential part grows by at
    #   most 2 mu (|D_n| + delta_c).
    # The bound below runs that recursion over the two oblique impacts.
    delta_c = CAP_R * (1.0 - math.cos(math.pi / FACETS))
    assert 0.0 < depth_h <= facet_error(CAP_R, FACETS) + 1e-15
    d_n = 2.0 * depth_h * math.sqrt(1.0 - nu[0] ** 2)  # radial part of the first shift
    d_t = 2.0 * depth_h * abs(nu[0])  # axial part
    for _ in peaks[1:]:
        d_t += 2 * 0.3 * (d_n + delta_c)
        d_n += 2.0 * delta_c
    bound = d_n + d_t
    diff = np.max(np.linalg.norm(analytic[:, :3] - meshed[:, :3], axis=1))
    assert diff <= bound, (diff, bound)
    # ...and not trivially: the two do differ (the facets are there), by more than the
    # head-on impact's share alone
    assert diff > 2.0 * depth_h, (diff, depth_h)


# --- a capsule that turns ---------------------------------------------------------------------


def _turning(dt, chunk):
    """A light capsule free to move and turn (no springs, no gravity) hit by two spheres with
    friction, run for 0.03 s in chunks of ``chunk`` steps. Returns the angular momentum's
    drift relative to its size, the energy rows, the cavity's last angular velocity, and the
    axial fraction t of the nearest axis point of each sphere while it touches the wall
    (the centre farther than R - r from the moving axis segment) at the chunks' ends."""
    e1 = np.array([0.0, 0.6, 0.8])
    e2 = np.array([0.0, -0.8, 0.6])
    pos = [[0.3, 0.0, 0.0] + 0.1 * e1, [0.7, 0.0, 0.0] - 0.1 * e2]
    # the second sphere heads beyond B = (0.8, 0, 0): it meets the rounded end there
    vel = [15.0 * e1 + [4.0, 0.0, 0.0], -12.0 * e2 + [9.0, 0.0, 0.0]]
    free = {
        "structure_mass": 1e-5,
        "rotary_inertia": 1e-7,
        "stiffness": 0.0,
        "damping": 0.0,
        "transverse_stiffness": 0.0,
    }
    deck = bore_deck(
        "capsule",
        pos,
        vel,
        dt=dt,
        tmax=1.0,
        mu=0.4,
        free_dofs=(1, 2, 3, 4, 5, 6),
        itrac=1000,
        structure=free,
    )
    model = build_model(deck)
    assert {"rigid_rotation", "capsule_contact"} <= model.effects
    ids = model.node_ids.tolist()
    ia, ib = ids.index(2), ids.index(3)  # the cap centres (deck nodes 2, 3)
    sim = Simulation(model)
    energy = [sim.snapshot().energy]
    l0 = angular_momentum(model, sim.state)
    touches = []
    for _ in range(round(0.03 / dt) // chunk):
        block = sim.advance(chunk)
        energy.append(block.energy)
        x = sim.state.x
        a, b = x[ia], x[ib]
        p = x[model.particle_start : model.n_nodes]
        t = np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
        dist = np.linalg.norm(p - a - t[:, None] * (b - a), axis=1)
        touches += [(k, t[k]) for k in np.flatnonzero(dist > BIG_R - STEEL_R)]
    drift = np.linalg.norm(angular_momentum(model, sim.state) - l0) / np.linalg.norm(l0)
    m = int(model.rigid_master[0])
    return drift, np.concatenate(energy), sim.state.vel[m, 3:], touches


@pytest.mark.validate  # its own compiled loop; CI covers the same code through the
# cylinder's test of it and the capsule's locator tests (`python -m pytest -m validate`)
def test_a_turning_capsule_conserves_momentum_and_energy():
    """A light capsule free to move and turn hit by spheres with friction, one of them on the
    rounded end at B: no external force or moment acts, so the total angular momentum stays
    put -- only if the reaction's moment l x F goes to the cavity and the wall point moves with
    omega x l. The energy ledger balances (the friction's work is formed from the same
    velocities as its power on the cavity), within the integration error.

    Tolerances, the cylinder's (tests/solver/test_cylinder_cavity.py): angular momentum
    constant to 2e-5 of its size (second-order drift of the rigid body's rotation kicks);
    1e-3 separates that from a missing lever by far. The energy residual below 1e-4 of the
    initial energy (elastic Hertz contacts: only friction dissipates) -- here at half the
    cylinder test's step: the impact on the rounded end of the spinning capsule leaves
    3.8e-4 at dt = 2e-7 s. That this is integration error, not a missing term in the ledger,
    shows in its convergence: halving the step divides the residual by more than 3 (second
    order: 4); a term missing from the ledger would not shrink."""
    runs = {dt: _turning(dt, chunk) for dt, chunk in ((2e-7, 25), (1e-7, 50))}
    residual = {}
    for dt, (drift, energy, omega, touches) in runs.items():
        assert drift < 1e-3, (dt, drift)
        assert energy[-1, 7] > 0.05 * energy[0, 10]  # friction did work: the spheres hit walls
        assert np.linalg.norm(omega) > 1.0  # the cavity turns (rad/s)
        # both spheres met the wall; the second on the rounded end (nearest axis point B)
        assert {k for k, _ in touches} == {0, 1}
        assert any(k == 1 and t == 1.0 for k, t in touches), touches
        residual[dt] = np.abs(energy[:, 11]).max() / energy[0, 10]
    assert residual[1e-7] < 1e-4, residual
    assert residual[1e-7] < residual[2e-7] / 3, residual
