"""build_model: arrays from hand-made decks, with expected values computed here by hand."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from deckfactory import (
    CORNERS,
    DENSITY,
    KX,
    MASTER,
    MASTER_MASS,
    RADIUS,
    SCALE,
    TRIANGLES,
    Boundary,
    C,
    Contact,
    Element,
    Initial,
    Mass,
    Material,
    Pdmp,
    Rbel,
    Trace,
    cube_deck,
    node,
    pos,
    replace,
    slave_set,
    triangles,
    with_nodes,
)

from x3dpd.deck import read_deck
from x3dpd.model.build import build_model
from x3dpd.model.model import EFFECTS

DECKS = Path(__file__).resolve().parents[2] / "decks"


def test_particle_mass_and_inertia():
    m = build_model(cube_deck(particles=[(0.5, 0.5, 0.5), (0.2, 0.2, 0.2)]))
    mass = DENSITY * 4.0 / 3.0 * math.pi * RADIUS**3  # report Appendix B note 2
    assert m.particle_start == 9 and m.n_particles == 2
    assert m.node_ids.tolist() == list(range(1, 12))
    np.testing.assert_allclose(m.mass[9:], [mass, mass], rtol=1e-15)
    np.testing.assert_allclose(m.inertia[9:], np.full((2, 3), 0.4 * mass * RADIUS**2), rtol=1e-15)
    np.testing.assert_array_equal(m.radius, [RADIUS, RADIUS])
    np.testing.assert_array_equal(m.density, [DENSITY, DENSITY])


def test_appendix_a_particle_mass_matches_the_decks_readme():
    m = build_model(read_deck(DECKS / "appendix_a.inp"))
    expected = 7.32971e-4 * 4.0 / 3.0 * math.pi * 0.03125**3
    assert expected == pytest.approx(9.3696e-8, rel=1e-4)  # decks/README.md
    np.testing.assert_allclose(m.mass[m.particle_start :], expected, rtol=1e-15)
    # node 25: MASS 3.002e-3 plus half the element mass 1e-12 (the ground half is dropped)
    assert m.mass[m.index_of(25)] == pytest.approx(3.002e-3 + 0.5e-12, rel=1e-15)
    assert m.rigid_mass[0] == pytest.approx(3.002e-3 + 0.5e-12, rel=1e-15)


def test_mass_records_add_and_element_mass_is_lumped_on_its_nodes():
    deck = cube_deck(particles=[])
    deck = with_nodes(deck, node(20, 3, 0, 0), node(21, 4, 0, 0))
    deck = replace(
        deck,
        materials=deck.materials + (Material(3, 1, 0.8, 1.0, 5.0, 5.0, 5.0, 0.0, pos=pos(11)),),
        elements=deck.elements + (Element(2, 3, (20, 21), pos(31)), Element(3, 3, (21,), pos(32))),
        masses=deck.masses
        + (
            Mass(20, 1.0, 0, 0, 0, pos(41)),
            Mass(20, 0.25, 1, 2, 3, pos(42)),
            Mass(21, 2.0, 0, 0, 0, pos(43)),
        ),
        pdmp=(),
    )
    m = build_model(deck)
    assert m.mass[m.index_of(20)] == pytest.approx(1.0 + 0.25 + 0.8 / 2)
    assert m.mass[m.index_of(21)] == pytest.approx(2.0 + 0.8 / 2 + 0.8 / 2)
    np.testing.assert_array_equal(m.inertia[m.index_of(20)], [1, 2, 3])
    assert m.n_particles == 0 and m.particle_start == m.n_nodes


def test_springs_apply_the_scale_and_damp_along_all_axes():
    m = build_model(cube_deck())
    np.testing.assert_array_equal(m.spring_nodes, [[m.index_of(MASTER), -1]])
    np.testing.assert_array_equal(m.spring_k, [[SCALE * KX, 0.0, 0.0]])
    np.testing.assert_array_equal(m.spring_c, [[SCALE * C] * 3])


def test_viscoelastic_terms_are_padded_across_groups():
    deck = cube_deck(particles=[(0.3, 0.5, 0.5), (0.7, 0.5, 0.5)])
    deck = replace(
        deck,
        pdmp=(
            Pdmp(9, 0.1, 7.0, 0.3, 2.0e7, 0.0, 0.0, 0.0, pos=pos(20)),
            Pdmp(
                10,
                0.05,
                3.0,
                0.25,
                1.0e7,
                5.0e6,
                2e-6,
                0.2,
                1.0,
                2.0,
                3.0,
                extra_terms=((3.0e6, 5e-7),),
                pos=pos(21),
            ),
        ),
    )
    m = build_model(deck)
    np.testing.assert_array_equal(m.particle_group, [0, 1])
    np.testing.assert_array_equal(m.moduli, [[2.0e7, 0.0, 0.0], [1.0e7, 5.0e6, 3.0e6]])
    np.testing.assert_array_equal(m.taus, [[np.inf, 1.0, 1.0], [np.inf, 2e-6, 5e-7]])
    np.testing.assert_array_equal(m.radius, [0.1, 0.05])
    np.testing.assert_array_equal(m.poisson, [0.3, 0.25])
    np.testing.assert_array_equal(m.mu, [0.0, 0.2])
    np.testing.assert_array_equal(m.v0[m.particle_start :, :3], [[0, 0, 0], [1, 2, 3]])


def test_elastic_particles_have_one_modulus_column():
    m = build_model(cube_deck())
    assert m.moduli.shape == (1, 1) and m.taus.shape == (1, 1)
    assert m.taus[0, 0] == np.inf


def test_initial_velocities_pdmp_then_initial_then_boundary():
    deck = cube_deck(particles=[(0.3, 0.5, 0.5), (0.7, 0.5, 0.5)])
    deck = replace(
        deck,
        pdmp=(replace(deck.pdmp[0], vx0=1.0, vy0=2.0, vz0=3.0),),
        initials=(
            Initial(11, (7.0, 8.0, 9.0, 0.1, 0.2, 0.3), pos(80)),
            Initial(MASTER, (4.0, 5.0, 6.0), pos(81)),
        ),
        boundaries=deck.boundaries + (Boundary(10, 10, 1, (3,), pos(61)),),
    )
    m = build_model(deck)
    np.testing.assert_array_equal(m.v0[m.index_of(10)], [1, 2, 0, 0, 0, 0])  # z fixed
    np.testing.assert_array_equal(m.v0[m.index_of(11)], [7, 8, 9, 0.1, 0.2, 0.3])
    np.testing.assert_array_equal(m.v0[m.index_of(MASTER)], [4, 0, 0, 0, 0, 0])  # 2..6 fixed


def test_boundary_ranges_use_the_increment_and_skip_missing_nodes():
    deck = cube_deck(
        particles=[],
        pdmp=(),
        boundaries=(Boundary(1, 9, 2, (1, 4), pos(60)), Boundary(9, 9, 1, (2, 3, 5, 6), pos(61))),
    )
    deck = with_nodes(deck, node(30, 5, 5, 5))
    deck = replace(deck, boundaries=deck.boundaries + (Boundary(2, 30, 7, (2,), pos(62)),))
    # 2..30 step 7 names nodes 2, 9, 16, 23, 30; 16 and 23 do not exist
    m = build_model(deck)
    fixed = {int(m.node_ids[i]): tuple(np.flatnonzero(m.fixed[i]) + 1) for i in range(m.n_nodes)}
    assert fixed[1] == fixed[3] == fixed[5] == fixed[7] == (1, 4)
    assert fixed[2] == (2,) and fixed[4] == ()
    assert fixed[9] == (1, 2, 3, 4, 5, 6)
    assert fixed[30] == (2,)


def test_rigid_inertia_by_the_parallel_axis_theorem():
    # master 9 at the origin with Ixx, Iyy, Izz = 0.1, 0.2, 0.3; slaves with masses at r:
    deck = cube_deck(particles=[])
    deck = replace(
        deck,
        masses=deck.masses
        + (
            Mass(2, 2.0, 0.01, 0.02, 0.03, pos(41)),  # r = (1, 0, 0)
            Mass(4, 3.0, 0.0, 0.0, 0.0, pos(42)),  # r = (0, 1, 0)
            Mass(3, 0.5, 0.0, 0.0, 0.0, pos(43)),
        ),  # r = (1, 1, 0)
        pdmp=(),
    )
    m = build_model(deck)
    # m (|r|^2 1 - r r^T) by hand:
    j2 = 2.0 * np.diag([0.0, 1.0, 1.0]) + np.diag([0.01, 0.02, 0.03])
    j4 = 3.0 * np.diag([1.0, 0.0, 1.0])
    j3 = 0.5 * np.array([[1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 0.0, 2.0]])
    expected = np.diag([0.1, 0.2, 0.3]) + j2 + j4 + j3
    np.testing.assert_allclose(m.rigid_inertia[0], expected, rtol=1e-15)
    assert m.rigid_mass[0] == pytest.approx(MASTER_MASS + 2.0 + 3.0 + 0.5)
    assert m.rigid_master.tolist() == [m.index_of(MASTER)]
    assert m.rigid_ptr.tolist() == [0, 8]
    assert sorted(m.node_ids[m.rigid_slaves].tolist()) == list(range(1, 9))


def _inward(m):
    p = [m.x0[m.tri_nodes[:, k]] for k in range(3)]
    n = np.cross(p[1] - p[0], p[2] - p[0])
    return m.tri_sign[:, None] * n / np.linalg.norm(n, axis=1, keepdims=True)


@pytest.mark.parametrize(
    "flip", [(), tuple(range(0, 12, 2)), (1, 2, 5, 6, 9, 10), tuple(range(12))]
)
def test_wall_normals_point_inward_whatever_the_winding(flip):
    m = build_model(cube_deck(flip=flip))
    expected = np.array([n for _, n in TRIANGLES], dtype=float)
    np.testing.assert_allclose(_inward(m), expected, atol=1e-15)
    signs = np.where(np.isin(np.arange(12), flip), -1.0, 1.0)
    np.testing.assert_array_equal(m.tri_sign, signs)
    # tri_nodes stay as written
    written = [tuple(int(m.node_ids[i]) for i in t) for t in m.tri_nodes]
    assert written == [t.nodes for t in triangles(flip)]


def test_coplanar_triangles_form_one_face_per_side():
    m = build_model(cube_deck(flip=(0, 3, 4, 7, 8, 11)))
    np.testing.assert_array_equal(m.tri_face, [0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5])
    np.testing.assert_array_equal(m.face_cavity, [0] * 6)
    np.testing.assert_array_equal(m.cavity_set_ids, [1])


def test_two_cavities_are_sorted_by_set_id_and_particles_follow_their_sets():
    shifted = {n + 30: (x + 5, y, z) for n, (x, y, z) in CORNERS.items()}
    deck = cube_deck(particles=[(0.5, 0.5, 0.5), (5.5, 0.5, 0.5), (9, 9, 9)])
    deck = with_nodes(deck, *[node(n, *xyz) for n, xyz in shifted.items()])
    # particles must have the highest ids: renumber the second box's nodes below NODLIM
    deck = replace(deck, pdmp=(replace(deck.pdmp[0], nodlim=38),))
    deck = replace(
        deck,
        nodes=tuple(
            nd
            if nd.nid < 10 or nd.nid > 12
            else replace(nd, nid=nd.nid + 30, pos=pos(200 + nd.nid))
            for nd in deck.nodes
        ),
    )
    tris2 = tuple(
        replace(t, set_id=7, nodes=tuple(n + 30 for n in t.nodes), pos=pos(150 + k))
        for k, t in enumerate(triangles())
    )
    deck = replace(
        deck,
        contacts=(Contact(tris2 + triangles(), (slave_set([40], 1), slave_set([41], 7, line=91))),),
        rbels=deck.rbels + (Rbel(31, (1, 2, 3, 4, 5, 6), tuple(range(32, 39)), pos=pos(51)),),
        masses=deck.masses + (Mass(31, 1.0, 1, 1, 1, pos(41)),),
    )
    m = build_model(deck)
    np.testing.assert_array_equal(m.cavity_set_ids, [1, 7])
    np.testing.assert_array_equal(m.node_ids[m.particle_start :], [40, 41, 42])
    np.testing.assert_array_equal(m.particle_cavity, [0, 1, -1])
    # faces of set 1 first (cavity 0), then set 7, though set 7's triangles come first
    np.testing.assert_array_equal(m.face_cavity, [0] * 6 + [1] * 6)
    np.testing.assert_array_equal(m.tri_face[:12], np.repeat(np.arange(6, 12), 2))
    np.testing.assert_allclose(_inward(m)[:12], [n for _, n in TRIANGLES], atol=1e-15)
    assert "pair_contact" in m.effects  # one particle is in no cavity


def test_trace_defaults_to_every_node_and_keeps_deck_order():
    m = build_model(cube_deck())
    np.testing.assert_array_equal(m.trace_nodes, np.arange(m.n_nodes))
    deck = cube_deck(trace=Trace((10, 9, 1), (pos(5, 4), pos(5, 8), pos(5, 12)), pos(5)))
    m = build_model(deck)
    np.testing.assert_array_equal(m.node_ids[m.trace_nodes], [10, 9, 1])


def test_scalars_and_arrays_are_read_only():
    m = build_model(cube_deck())
    assert (m.t0, m.tmax, m.dt, m.itrac) == (0.0, 1.0, 1e-7, 100)
    np.testing.assert_array_equal(m.body_accel, [0.0, -10.0, 0.0])
    for name in ("x0", "mass", "fixed", "tri_sign", "moduli", "rigid_inertia"):
        arr = getattr(m, name)
        assert arr.flags.c_contiguous and not arr.flags.writeable
    assert m.node_ids.dtype == np.int64 and m.fixed.dtype == bool


def test_appendix_a_windings_disagree_but_normals_face_the_master_centroid():
    """decks/README.md: the printed x and y faces are wound outward, the z faces inward."""
    m = build_model(read_deck(DECKS / "appendix_a.inp"))
    np.testing.assert_array_equal(m.tri_sign, [-1.0] * 8 + [1.0] * 4)
    centroid = m.x0[np.unique(m.tri_nodes)].mean(axis=0)
    np.testing.assert_allclose(centroid, [0.125, 0.125, 0.0], atol=1e-15)
    p0 = m.x0[m.tri_nodes[:, 0]]
    assert np.all(np.einsum("tk,tk->t", _inward(m), centroid - p0) > 0)
    assert m.tri_face.tolist() == [0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5]


# -- effects --------------------------------------------------------------------------------------


def test_effects_of_the_base_cube():
    m = build_model(cube_deck())
    assert m.effects == {"gravity", "springs", "dampers", "rigid_links", "wall_contact"}
    assert m.effects <= set(EFFECTS)


def test_effects_of_the_appendix_a_deck():
    m = build_model(read_deck(DECKS / "appendix_a_cube.inp"))
    assert m.effects == {
        "gravity",
        "springs",
        "dampers",
        "rigid_links",
        "wall_contact",
        "pair_contact",
        "viscoelastic",
        "friction",
    }


def test_effects_springs_only_on_fixed_dofs_do_not_count():
    deck = cube_deck(
        materials=(Material(2, 1, 0.0, 1.0, 0.0, 7.0, 7.0, 0.0, pos=pos(10)),), body=None
    )
    m = build_model(deck)  # ky, kz act on DOFs 2 and 3 of node 9, which BOUNDARY fixes
    assert "springs" not in m.effects and "dampers" not in m.effects
    assert "gravity" not in m.effects


def test_effects_rigid_rotation_pairs_viscoelastic_friction_external_motion():
    deck = cube_deck(
        particles=[(0.3, 0.5, 0.5), (0.7, 0.5, 0.5)],
        boundaries=(Boundary(1, 9, 1, (2, 3, 4, 5), pos(60)),),
    )
    deck = replace(deck, pdmp=(replace(deck.pdmp[0], e1=1.0e6, t1=1e-6, pcof=0.3),))
    m = build_model(
        deck, usrfrc=("sine:node=9,dof=1,amp=1,hz=10",), motion=("node=9,dof=6,amp=0.01,hz=5",)
    )
    assert {
        "rigid_rotation",
        "pair_contact",
        "viscoelastic",
        "friction",
        "external_force",
        "prescribed_motion",
    } <= m.effects
    assert build_model(cube_deck()).effects.isdisjoint(
        {
            "rigid_rotation",
            "pair_contact",
            "viscoelastic",
            "friction",
            "external_force",
            "prescribed_motion",
        }
    )


def test_effects_particles_in_separate_cavities_do_not_pair():
    deck = cube_deck(particles=[(0.5, 0.5, 0.5)])
    m = build_model(deck)
    assert "pair_contact" not in m.effects
    deck = cube_deck(particles=[(0.5, 0.5, 0.5), (0.2, 0.2, 0.2)])
    deck = replace(deck, contacts=(Contact(triangles(), (slave_set([10]),)),))
    m = build_model(deck)  # particle 11 is in no cavity: it may meet particle 10
    assert "pair_contact" in m.effects and "wall_contact" in m.effects
    deck = replace(deck, contacts=(Contact(triangles(), ()),))
    assert "wall_contact" not in build_model(deck).effects


def test_deck_usrfrc_card_is_kept_and_counts_as_external_force():
    from x3dpd.deck.cards import Usrfrc

    deck = cube_deck(usrfrc=(Usrfrc(("constant:node=9,dof=1,amp=2",), pos(95)),))
    m = build_model(deck)
    assert m.usrfrc == ("constant:node=9,dof=1,amp=2",)
    assert "external_force" in m.effects


def test_user_force_file_on_the_card_is_found_beside_the_deck(tmp_path, monkeypatch):
    from x3dpd.deck.cards import Usrfrc
    from x3dpd.errors import DeckError

    folder = tmp_path / "job"
    folder.mkdir()
    (folder / "force.py").write_text("def usrfrc(time, coords, vels, force):\n    pass\n")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)  # the working directory holds no force.py
    deck = replace(
        cube_deck(usrfrc=(Usrfrc(("force.py", "constant:node=9,dof=1,amp=2"), pos(95)),)),
        path=str(folder / "deck.inp"),
    )
    m = build_model(deck)
    assert m.usrfrc == (str(folder / "force.py"), "constant:node=9,dof=1,amp=2")

    (folder / "force.py").unlink()
    with pytest.raises(DeckError) as err:
        build_model(deck)
    text = str(err.value)
    assert text.startswith(f"{folder / 'deck.inp'}:95:") and "USRFRC" in text
    assert "'force.py' not found" in text and str(folder / "force.py") in text
