"""One call of the compiled force kernel against a plain-numpy reference (tests/reference.py:
contact_forces): gravity, Hertz normal forces and regularised Coulomb friction (with spin) at every
particle-wall and particle-particle contact, reactions on the walls' nodes -- for random
configurations with overlaps, two particle materials (dissimilar radii, moduli, Poisson's ratios,
friction coefficients, densities), elastic (E1 = 0, so no history), in an axis-aligned and in a
rotated box.

The reference computes the physics from its own definitions (1/E* = sum (1-nu^2)/E,
1/R* = sum 1/R, m_t from 1/m + R^2/I, barycentric weights from areas) with no x3dpd import, and
finds contacts by brute force over all particle pairs and all faces.
"""

from __future__ import annotations


import numpy as np
import pytest


import reference as ref
from factories import STEEL_E, STEEL_NU, STEEL_R, STEEL_RHO, G, closed_box_deck, sphere_mass

from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation

MAT_A = {"radius": STEEL_R, "e0": STEEL_E, "nu": STEEL_NU, "mu": 0.3, "density": STEEL_RHO}
MAT_B = {"radius": 0.04, "e0": 10.0e6, "nu": 0.25, "mu": 0.5, "density": 2.5e-4}
DT = 1e-9  # with these overlaps both branches of the regularised friction law occur


def _rotation(seed: int) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def _configuration(seed: int, radius_b: float = MAT_B["radius"]):
    """Particles in the unit box (local coordinates) with random overlaps: 2 per face against a
    wall, 2 along edges against two walls, pairs and triangles of touching particles inside, and
    some free ones. Every group of intended contacts is redrawn until it keeps 0.005 in of
    clearance from everything placed before. Returns (local positions A, local positions B)."""
    rng = np.random.default_rng(seed)
    rad = (MAT_A["radius"], radius_b)
    placed: list = []  # (group, position)

    def depth(r):
        return rng.uniform(0.01, 0.1) * r  # overlaps of 1 % ... 10 % of the radius

    def clear(members):
        for g, p in members:
            for h, q in placed:
                if np.linalg.norm(p - q) < rad[g] + rad[h] + 0.005:
                    return False
        return True

    def place(draw):
        for _ in range(1000):
            members = draw()
            if clear(members):
                placed.extend(members)
                return
        raise AssertionError("could not place a contact group")

    def wall(axes):
        g = int(rng.integers(2))
        r = rad[g]
        p = rng.uniform(0.2, 0.8, 3)  # the centre's projection well inside the face
        for axis, side in axes:
            p[axis] = r - depth(r) if side == 0 else 1.0 - r + depth(r)
        return [(g, p)]

    def cluster(size):
        while True:
            members = [(int(rng.integers(2)), rng.uniform(0.3, 0.7, 3))]
            while len(members) < size:
                g0, c0 = members[-1]
                g = int(rng.integers(2))
                u = rng.normal(size=3)
                u /= np.linalg.norm(u)
                members.append((g, c0 + (rad[g0] + rad[g] - depth(min(rad[g0], rad[g]))) * u))
            # in a chain of three the ends must not touch by accident
            (g0, p0), (g2, p2) = members[0], members[-1]
            if size < 3 or np.linalg.norm(p0 - p2) > rad[g0] + rad[g2] + 0.005:
                return members

    for axis in range(3):
        for side in (0, 1):
            for _ in range(2):
                place(lambda axis=axis, side=side: wall([(axis, side)]))
    for _ in range(2):  # edges: two walls at once
        place(lambda: wall([(a, 0) for a in rng.permutation(3)[:2]]))
    for k in range(6):  # pairs and chains of three inside
        place(lambda k=k: cluster(2 + k % 2))
    for _ in range(3):  # free particles
        place(lambda: [(int(rng.integers(2)), rng.uniform(0.15, 0.85, 3))])
    a_pos = np.array([p for g, p in placed if g == 0])
    b_pos = np.array([p for g, p in placed if g == 1])
    return a_pos, b_pos


def _velocities(rng, n):
    """Translational and angular velocities whose magnitudes span 1e-3 ... 300 in/s and
    1e-2 ... 3e3 rad/s (so both branches of the regularised friction law occur)."""
    v = rng.normal(size=(n, 3))
    v *= (10 ** rng.uniform(-3, 2.5, n) / np.linalg.norm(v, axis=1))[:, None]
    w = rng.normal(size=(n, 3)) * 10 ** rng.uniform(-2, 3.5, (n, 1))
    return np.hstack([v, w])


@pytest.mark.parametrize(
    "seed, rotated, mixed",
    [
        (1, False, True),
        (2, False, True),
        (3, True, True),
        (4, True, True),
        (5, False, False),
        (6, True, False),
    ],
)
def test_forces_match_reference(seed, rotated, mixed):
    """``mixed``: two materials; else all particles are of material A, and the step loop reads
    their constants once (the variant flag one_particle_kind) instead of per contact."""
    mat_b = MAT_B if mixed else MAT_A
    local_a, local_b = _configuration(seed, mat_b["radius"])
    rot = _rotation(seed) if rotated else np.eye(3)
    origin = np.array([0.3, -0.2, 0.1]) if rotated else np.zeros(3)
    world_a = origin + local_a @ rot.T
    world_b = origin + local_b @ rot.T
    rng = np.random.default_rng(100 + seed)
    vel_a = _velocities(rng, len(world_a))
    vel_b = _velocities(rng, len(world_b))
    deck = closed_box_deck(
        world_a,
        vel_a,
        dt=DT,
        rotation=rot,
        origin=origin,
        gravity=G,
        groups=[(world_b, vel_b, mat_b)],
        **MAT_A,
    )
    model = build_model(deck)
    sim = Simulation(model, penetration_limit=0.25)
    sim.initialize()
    assert sim.variant.friction and sim.variant.walls and sim.variant.pairs
    assert sim.variant.one_particle_kind == (not mixed)
    assert not sim.variant.viscoelastic and sim.variant.friction_law == "regularized"

    # one evaluation of the compiled force kernel, on the state initialize() prepared
    assert sim.compute_forces(model.t0) == 0
    force = sim.state.force

    n_a, n_b = len(world_a), len(world_b)
    radius = np.r_[np.full(n_a, MAT_A["radius"]), np.full(n_b, mat_b["radius"])]
    e = np.r_[np.full(n_a, MAT_A["e0"]), np.full(n_b, mat_b["e0"])]
    nu = np.r_[np.full(n_a, MAT_A["nu"]), np.full(n_b, mat_b["nu"])]
    mu = np.r_[np.full(n_a, MAT_A["mu"]), np.full(n_b, mat_b["mu"])]
    mass = np.r_[
        np.full(n_a, sphere_mass(MAT_A["radius"], MAT_A["density"])),
        np.full(n_b, sphere_mass(mat_b["radius"], mat_b["density"])),
    ]
    x = np.vstack(
        [
            origin
            + (
                np.array(
                    [
                        [0, 0, 0],
                        [1, 0, 0],
                        [1, 1, 0],
                        [0, 1, 0],
                        [0, 0, 1],
                        [1, 0, 1],
                        [1, 1, 1],
                        [0, 1, 1],
                    ],
                    float,
                )
            )
            @ rot.T,
            world_a,
            world_b,
        ]
    )
    vel = np.vstack([np.zeros((8, 6)), vel_a, vel_b])
    node_mass = np.r_[np.zeros(8), mass]
    want, scale, info = ref.contact_forces(
        x,
        vel,
        p0=8,
        radius=radius,
        mass=mass,
        e=e,
        nu=nu,
        mu=mu,
        faces=ref.box_faces(x[:8]),
        gravity=(0.0, -G, 0.0),
        dt=DT,
        node_mass=node_mass,
    )
    print(f"\nseed {seed}: {info}")
    # the configuration exercises what it should
    assert info["wall"] >= 14 and info["pair"] >= 8
    assert info["stick"] >= 3 and info["slip"] >= 3
    # same node order: walls 1-8, then group A, then group B (ascending node ids)
    np.testing.assert_array_equal(model.node_ids, np.arange(1, 9 + n_a + n_b))
    # 1e-12 of the sum of the magnitudes of everything added at that node and component (the
    # brief's bound; rounding of the approach a = R - d, computed from coordinates of order 1,
    # is ~1e-16 / a <= 1e-13 here, and F ~ a^{3/2}); exact zeros where nothing acts.
    err = np.abs(force - want)
    assert np.all(err <= 1e-12 * scale), (
        f"worst relative mismatch {np.max(err / np.where(scale > 0, scale, 1)):.2e}"
    )
    print(f"worst relative mismatch {np.max(err / np.where(scale > 0, scale, 1)):.1e}")


def test_a_list_of_several_blocks_matches_the_reference():
    """A packed lattice of 512 spheres, every neighbour pressed in by 1-3 % of the radius:
    more candidates than one block of the pair passes (contact_lists.PAIR_BLOCK), so the
    filter, response and apply run block after block, each block's columns in the same
    scratch area, their sums chained through the blocks. Forces as the reference gives them."""
    from x3dpd.solver.contact_lists import PAIR_BLOCK

    r = MAT_A["radius"]
    rng = np.random.default_rng(7)
    axis = 0.98 * r + np.arange(8) * 1.96 * r
    lattice = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    pos = lattice + rng.uniform(-0.005, 0.005, lattice.shape) * r
    vel = _velocities(rng, len(pos))
    deck = closed_box_deck(pos, vel, dt=DT, gravity=G, **MAT_A)
    model = build_model(deck)
    sim = Simulation(model, penetration_limit=0.25)
    sim.initialize()
    assert sim.variant.one_particle_kind and sim.variant.friction_law == "regularized"
    assert int(sim.state.npl[0]) > PAIR_BLOCK
    assert sim.compute_forces(model.t0) == 0
    force = sim.state.force

    n = len(pos)
    mass = np.full(n, sphere_mass(r, MAT_A["density"]))
    box = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
        float,
    )
    want, scale, info = ref.contact_forces(
        np.vstack([box, pos]),
        np.vstack([np.zeros((8, 6)), vel]),
        p0=8,
        radius=np.full(n, r),
        mass=mass,
        e=np.full(n, MAT_A["e0"]),
        nu=np.full(n, MAT_A["nu"]),
        mu=np.full(n, MAT_A["mu"]),
        faces=ref.box_faces(box),
        gravity=(0.0, -G, 0.0),
        dt=DT,
        node_mass=np.r_[np.zeros(8), mass],
    )
    # every lattice neighbour touches (3 x 7 x 64 pairs), and so do the three low faces' layers
    assert info["pair"] == 3 * 7 * 64 and info["wall"] == 3 * 64
    assert info["stick"] >= 3 and info["slip"] >= 3
    err = np.abs(force - want)
    assert np.all(err <= 1e-12 * scale), (
        f"worst relative mismatch {np.max(err / np.where(scale > 0, scale, 1)):.2e}"
    )
