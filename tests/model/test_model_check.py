"""check_model and its geometry finders on hand-made and shipped decks."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from deckfactory import RADIUS, cube_deck, replace

from x3dpd.deck import read_deck
from x3dpd.model.build import build_model
from x3dpd.model.check import (
    MAX_LISTED,
    OutsideParticle,
    WallPenetration,
    check_model,
    faces_in_particle_cloud,
    particle_overlaps,
    particle_wall_penetrations,
    particles_outside,
)

DECKS = Path(__file__).resolve().parents[2] / "decks"


def model(particles, **kw):
    return build_model(cube_deck(particles=particles, **kw))


# -- penetrations -------------------------------------------------------------------------------


def test_penetration_depth_and_triangle():
    m = model([(0.7, 0.3, 0.05)])  # over triangle 1 (nodes 1 2 3, the part x > y of z = 0)
    assert particle_wall_penetrations(m) == [WallPenetration(0, 10, 0, pytest.approx(0.05))]


def test_touching_is_not_penetrating():
    assert particle_wall_penetrations(model([(0.7, 0.3, RADIUS)])) == []
    assert particle_wall_penetrations(model([(0.5, 0.5, 0.5)])) == []


def test_a_corner_particle_penetrates_three_faces():
    pen = particle_wall_penetrations(model([(0.05, 0.04, 0.03)]))
    depth = {m.triangle // 2: m.depth for m in pen}  # face = triangle // 2 in the cube deck
    assert depth == {0: pytest.approx(0.07), 2: pytest.approx(0.06), 4: pytest.approx(0.05)}


def test_min_depth_fraction_filters_shallow_penetrations():
    m = model([(0.7, 0.3, 0.05)])  # depth 0.05 = 0.5 R
    assert len(particle_wall_penetrations(m, min_depth_fraction=0.4)) == 1
    assert particle_wall_penetrations(m, min_depth_fraction=0.6) == []


def test_edge_tolerance_is_the_radius():
    """An open floor z = 0 over 0 <= x, y <= 1: a sphere just past its rim still touches it."""
    from deckfactory import Contact, Triangle, pos, slave_set

    floor = (
        Triangle(1, (1, 2, 3), pos(70)),
        Triangle(1, (1, 3, 4), pos(71)),
        Triangle(1, (5, 6, 7), pos(72)),
    )  # plus the lid, so the inside is known
    for x, hits in ((1.05, 1), (1.0 + 0.99 * RADIUS, 1), (1.0 + 1.01 * RADIUS, 0)):
        m = build_model(
            cube_deck(particles=[(x, 0.5, 0.05)], contacts=(Contact(floor, (slave_set([10]),)),))
        )
        assert len(particle_wall_penetrations(m)) == hits, x


# -- outside ------------------------------------------------------------------------------------


def test_particle_behind_a_wall_is_outside():
    m = model([(0.3, 0.6, -0.05), (0.5, 0.5, 0.5)])  # (0.3, 0.6) is over triangle 2 (1 3 4)
    assert particles_outside(m) == [OutsideParticle(0, 10, 1, pytest.approx(0.05))]


def test_particle_outside_the_box_but_over_no_wall():
    m = model([(1.5, 1.5, 0.5)])
    assert particles_outside(m) == [OutsideParticle(0, 10, -1, pytest.approx(0.5))]


def test_an_open_cavity_has_no_box_to_be_outside_of():
    """A lone floor z = 0 (a zero-thick box): a sphere above it is inside its cavity."""
    from deckfactory import Contact, Triangle, pos, slave_set

    floor = (Triangle(1, (1, 2, 3), pos(70)), Triangle(1, (1, 3, 4), pos(71)))
    above = model([(0.5, 0.5, 0.3)], contacts=(Contact(floor, (slave_set([10]),)),))
    assert particles_outside(above) == []
    report = check_model(above)
    assert report.cavities[0].closed is False
    assert "particles-outside" not in [w.code for w in report.warnings]
    # beyond the floor's rim, over no wall: still not "outside" (an open cavity has no box)
    assert (
        particles_outside(
            model(
                [(1.5, 0.5, 0.3), (0.5, 0.5, 0.3)],
                contacts=(Contact(floor, (slave_set([10, 11]),)),),
            )
        )
        == []
    )


# -- overlaps -----------------------------------------------------------------------------------


def test_overlapping_particles_by_node_id():
    pairs, depth = particle_overlaps(model([(0.3, 0.5, 0.5), (0.45, 0.5, 0.5), (0.8, 0.5, 0.5)]))
    assert pairs.tolist() == [[10, 11]]
    np.testing.assert_allclose(depth, [2 * RADIUS - 0.15])


def test_overlap_listing_is_capped():
    centres = [(0.15 + 0.05 * k, 0.5, 0.5) for k in range(15)]  # neighbours 0.05 apart
    report = check_model(model(centres))
    (w,) = [w for w in report.warnings if w.code == "particle-overlap"]
    n_pairs = sum(1 for i in range(15) for j in range(i + 1, 15) if 0.05 * (j - i) < 0.2)
    assert w.headline.startswith(f"{n_pairs} particle pairs start overlapping")
    assert len(w.details) == MAX_LISTED + 1
    assert w.details[-1] == f"... and {n_pairs - MAX_LISTED} more"


# -- faces inside the particle cloud ------------------------------------------------------------


def test_a_face_with_particles_on_both_sides_is_inside_the_cloud():
    m = model([(0.5, 0.5, 0.5), (0.5, 0.5, -0.05)])
    assert faces_in_particle_cloud(m) == [0]  # z = 0
    assert faces_in_particle_cloud(model([(0.5, 0.5, 0.5), (0.5, 0.5, 0.1)])) == []


def test_cloud_headline_is_found_from_geometry_not_the_file_name():
    """Move the x = 1 side of the cube to x = 0.5, through a row of particles."""
    deck = cube_deck(particles=[(0.3, 0.5, 0.5), (0.7, 0.5, 0.5)])
    deck = replace(
        deck,
        path="anything.inp",
        nodes=tuple(replace(nd, x=0.5) if nd.nid in (2, 3, 6, 7) else nd for nd in deck.nodes),
    )
    report = check_model(build_model(deck))
    first = report.warnings[0]
    assert first.code == "faces-in-particle-cloud"
    assert first.headline.startswith(
        "cavity set 1: two of the twelve contact triangles lie in the plane x = 0.5, inside the "
        "particle cloud (particle centres span x from 0.3 to 0.7 and y, z from 0.5 to 0.5)"
    )
    assert "1 of the 2 particles start outside the cavity they bound" in first.headline
    assert report.exit_status == 1


# -- report -------------------------------------------------------------------------------------


def test_report_of_a_clean_cube():
    centres = [(0.5, 0.5, 0.5), (0.2, 0.2, 0.2)]
    report = check_model(model(centres))
    (cav,) = report.cavities
    assert cav.closed and cav.consistent and cav.n_faces == 6 and cav.n_triangles == 12
    assert cav.volume == pytest.approx(1.0, rel=1e-14)
    assert cav.fill_ratio == pytest.approx(2 * 4 / 3 * math.pi * RADIUS**3, rel=1e-14)
    assert (cav.lo, cav.hi) == ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    assert report.n_nodes == 11 and report.n_particles == 2
    assert report.groups[0].nodes == "10-11"
    assert report.structure_mass == pytest.approx(1.5)
    assert report.warnings == () and report.exit_status == 0


def test_open_cavity_has_no_volume():
    from deckfactory import Contact, slave_set, triangles

    deck = cube_deck(contacts=(Contact(triangles()[:10], (slave_set([10]),)),))
    (cav,) = check_model(build_model(deck)).cavities
    assert not cav.closed and cav.volume is None and cav.fill_ratio is None


def test_particles_in_no_slave_set_are_reported():
    from deckfactory import Contact, slave_set, triangles

    deck = cube_deck(particles=[(0.3, 0.5, 0.5), (0.7, 0.5, 0.5), (0.5, 0.2, 0.5)])
    deck = replace(deck, contacts=(Contact(triangles(), (slave_set([10]),)),))
    report = check_model(build_model(deck))
    assert [w.headline for w in report.warnings if w.code == "no-cavity"] == [
        "2 particles are in no CONTACT slave set and will pass through every wall: nodes 11-12"
    ]


def test_appendix_a_headline():
    m = build_model(read_deck(DECKS / "appendix_a.inp"))
    report = check_model(m)
    head = report.warnings[0]
    assert head.code == "faces-in-particle-cloud"
    assert head.headline.startswith(
        "cavity set 1: the twelve contact triangles lie in the planes x = 0.0625, 0.1875, "
        "y = 0.0625, 0.1875, z = ±0.09375, inside the particle cloud (particle centres span "
        "x, y from 0.03125 to 0.21875 and z from -0.09375 to 0.09375), so no closed cavity holds "
        "the particles"
    )
    # outside: a centre in the outer ring x or y in {1/32, 7/32} lies behind the walls at
    # x, y = 1/16 and 3/16
    x = m.x0[m.particle_start :]
    ring = np.isin(x[:, 0], [0.03125, 0.21875]) | np.isin(x[:, 1], [0.03125, 0.21875])
    assert int(ring.sum()) == 38
    assert "38 of the 50 particles start outside the cavity they bound" in head.headline
    assert "decks/appendix_a_cube.inp" in head.headline
    outside = [o.node_id for o in particles_outside(m)]
    assert outside == (m.node_ids[m.particle_start :][ring]).tolist()
    # the four inner particles of the bottom layer have their centres on the plane z = -3/32
    (pen,) = [w for w in report.warnings if w.code == "wall-penetration"]
    assert pen.headline.startswith("4 particles inside their cavity start penetrating a wall")
    assert [d.split(":")[0] for d in pen.details] == [
        f"particle node {n}" for n in (31, 32, 35, 36)
    ]
    cav = report.cavities[0]
    assert not cav.closed and cav.volume is None
    assert report.exit_status == 1


def test_appendix_a_cube_geometry_is_clean():
    report = check_model(build_model(read_deck(DECKS / "appendix_a_cube.inp")))
    (cav,) = report.cavities
    assert cav.closed and cav.consistent
    assert cav.volume == pytest.approx(0.25**3, rel=1e-14)
    r = 0.03125
    assert cav.fill_ratio == pytest.approx(50 * 4 / 3 * math.pi * r**3 / 0.25**3, rel=1e-12)
    assert report.particle_mass == pytest.approx(50 * 7.32971e-4 * 4 / 3 * math.pi * r**3)
    assert report.structure_mass == pytest.approx(3.002e-3 + 0.5e-12, rel=1e-12)
    # the particles touch the walls and each other exactly: nothing is flagged. The deck's
    # 5e-7 s resolves the fastest impact in ~9.6 steps (>= MIN_STEPS_PER_CONTACT = 8), which
    # the summary reports as an expected peak-force error rather than a warning.
    assert [w.code for w in report.warnings] == []
    assert report.time_step.deck_steps_per_contact == pytest.approx(9.6, rel=0.02)
