"""Every cross-reference error of build_model: position, card and the phrase that explains it."""

from __future__ import annotations

import pytest
from deckfactory import (
    LINE_ELEMENT,
    LINE_MASS,
    LINE_MATERIAL,
    LINE_NODE,
    LINE_PARAMETERS,
    LINE_PDMP,
    LINE_RBEL,
    LINE_SLAVES,
    LINE_TRIANGLE,
    Boundary,
    Contact,
    Element,
    Initial,
    Mass,
    Rbel,
    Trace,
    Triangle,
    cube_deck,
    node,
    pos,
    replace,
    slave_set,
    triangles,
    with_nodes,
)

from x3dpd.deck.cards import Usrfrc
from x3dpd.errors import DeckError, UsrfrcError
from x3dpd.model.build import build_model


def _raises(deck, line, column, card, *phrases, **kw):
    with pytest.raises(DeckError) as info:
        build_model(deck, **kw)
    err = info.value
    assert (err.path, err.line, err.column, err.card) == ("cube.inp", line, column, card), str(err)
    for phrase in phrases:
        assert phrase in err.message, err.message
    assert str(err).startswith(f"cube.inp:{line}:{column}: {card}: ")
    return err


def test_no_parameters_card():
    _raises(cube_deck(parameters=None), 0, 0, "PARAMETERS", "no PARAMETERS card")


@pytest.mark.parametrize("dt", [0.0, -1e-6])
def test_time_step_must_be_positive(dt):
    deck = cube_deck()
    deck = replace(deck, parameters=replace(deck.parameters, dtmax=dt, dtmin=-1.0))
    _raises(deck, LINE_PARAMETERS, 1, "PARAMETERS", "DTMAX must be > 0")


def test_dtmin_above_dtmax():
    deck = cube_deck()
    deck = replace(deck, parameters=replace(deck.parameters, dtmin=2e-7, dtmax=1e-7))
    _raises(deck, LINE_PARAMETERS, 1, "PARAMETERS", "DTMIN 2e-07 is larger than DTMAX 1e-07")


def test_end_time_before_start_time():
    deck = cube_deck()
    deck = replace(deck, parameters=replace(deck.parameters, time=2.0, tmax=1.0))
    _raises(deck, LINE_PARAMETERS, 1, "PARAMETERS", "TMAX 1 is before the start time TIME 2")


def test_duplicate_node_points_at_the_second_and_names_the_first():
    deck = with_nodes(cube_deck(), replace(node(4, 9, 9, 9), pos=pos(300, 3)))
    _raises(
        deck,
        300,
        3,
        "NODE COORDINATES",
        "node 4 is defined twice",
        f"first at line {LINE_NODE + 4}",
    )


def test_undefined_node_in_elements():
    deck = cube_deck(elements=(Element(1, 2, (77,), pos(LINE_ELEMENT, 7)),))
    _raises(deck, LINE_ELEMENT, 7, "ELEMENTS", "node 77 is not defined")


def test_undefined_node_in_mass():
    deck = cube_deck(
        masses=(
            Mass(9, 1.0, 0, 0, 0, pos(LINE_MASS)),
            Mass(78, 1.0, 0, 0, 0, pos(LINE_MASS + 1, 2)),
        )
    )
    _raises(deck, LINE_MASS + 1, 2, "MASS", "node 78 is not defined")


def test_undefined_rbel_slave_points_at_the_slave():
    deck = cube_deck()
    rb = deck.rbels[0]
    deck = replace(deck, rbels=(replace(rb, slaves=(1, 2, 79, 4, 5, 6, 7, 8)),))
    _raises(deck, LINE_RBEL, 10 + 3 * 2, "RBEL", "slave node 79 is not defined")


def test_undefined_rbel_master():
    deck = cube_deck()
    deck = replace(deck, rbels=(replace(deck.rbels[0], master=80),))
    _raises(deck, LINE_RBEL, 1, "RBEL", "master node 80 is not defined")


def test_undefined_boundary_node():
    deck = cube_deck(boundaries=(Boundary(81, 81, 1, (1,), pos(60, 4)),))
    _raises(deck, 60, 4, "BOUNDARY CONDITIONS", "first node 81 is not defined")


def test_empty_boundary_range():
    deck = cube_deck(boundaries=(Boundary(5, 2, 1, (1,), pos(60)),))
    _raises(deck, 60, 1, "BOUNDARY CONDITIONS", "is empty")


def test_undefined_triangle_node():
    tris = list(triangles())
    tris[3] = replace(tris[3], nodes=(5, 82, 7))
    deck = cube_deck(contacts=(Contact(tuple(tris), (slave_set([10]),)),))
    _raises(deck, LINE_TRIANGLE + 3, 1, "CONTACT", "triangle node 82 is not defined")


def test_undefined_slave_node_points_at_the_id():
    deck = cube_deck(contacts=(Contact(triangles(), (slave_set([10, 83]),)),))
    _raises(deck, LINE_SLAVES, 5 + 4, "CONTACT", "slave node 83 is not defined")


def test_undefined_initial_node():
    deck = cube_deck(initials=(Initial(84, (1.0, 0.0, 0.0), pos(85, 2)),))
    _raises(deck, 85, 2, "INITIAL", "node 84 is not defined")


def test_undefined_trace_node_points_at_the_id():
    deck = cube_deck(trace=Trace((9, 85), (pos(5, 4), pos(5, 8)), pos(5)))
    _raises(deck, 5, 8, "TRACE", "node 85 is not defined")


def test_undefined_material():
    deck = cube_deck(elements=(Element(1, 5, (9,), pos(LINE_ELEMENT)),))
    _raises(deck, LINE_ELEMENT, 1, "ELEMENTS", "uses material 5", "no MATID record defines")


def test_material_type_other_than_1_2_3():
    deck = cube_deck()
    deck = replace(deck, materials=(replace(deck.materials[0], mtype=4),))
    _raises(deck, LINE_MATERIAL, 1, "MATID", "type 4", "the types are 1 = ", "2 = ", "3 = ")


def test_element_touching_a_particle():
    deck = cube_deck(elements=(Element(1, 2, (9, 10), pos(LINE_ELEMENT)),))
    _raises(deck, LINE_ELEMENT, 1, "ELEMENTS", "element 1 node 10 is a particle node", "NODLIM 9")


def test_rbel_touching_a_particle():
    deck = cube_deck()
    deck = replace(
        deck, rbels=(replace(deck.rbels[0], slaves=tuple(range(1, 9)) + (10,), slave_positions=()),)
    )
    _raises(deck, LINE_RBEL, 1, "RBEL", "slave node 10 is a particle node")


def test_mass_on_a_particle():
    deck = cube_deck(masses=(Mass(10, 1.0, 0, 0, 0, pos(LINE_MASS)),))
    _raises(deck, LINE_MASS, 1, "MASS", "node 10 is a particle node")


def test_node_in_two_rigid_bodies():
    deck = cube_deck()
    deck = replace(
        deck, rbels=deck.rbels + (Rbel(4, (1, 2, 3, 4, 5, 6), (3,), (pos(52, 9),), pos(52)),)
    )
    _raises(
        deck,
        52,
        1,
        "RBEL",
        "master node 4 already belongs to the rigid body of master 9",
        f"line {LINE_RBEL}",
    )


def test_slave_in_two_rigid_bodies():
    deck = cube_deck(masses=(Mass(9, 1.0, 1, 1, 1, pos(40)), Mass(1, 1.0, 1, 1, 1, pos(41))))
    deck = replace(
        deck,
        rbels=(
            replace(deck.rbels[0], slaves=(2, 3, 4, 5, 6, 7, 8), slave_positions=()),
            Rbel(1, (1, 2, 3, 4, 5, 6), (3,), (pos(52, 9),), pos(52)),
        ),
    )
    _raises(deck, 52, 9, "RBEL", "slave node 3 already belongs to the rigid body of master 9")


def test_rbel_dof_code_other_than_123456():
    deck = cube_deck()
    deck = replace(deck, rbels=(replace(deck.rbels[0], dofs=(1, 2, 3)),))
    _raises(deck, LINE_RBEL, 1, "RBEL", "DOF code 123", "only 123456")


def test_degenerate_triangle_gives_its_area():
    tris = list(triangles())
    tris[5] = replace(tris[5], nodes=(1, 2, 2))
    deck = cube_deck(contacts=(Contact(tuple(tris), (slave_set([10]),)),))
    _raises(
        deck, LINE_TRIANGLE + 5, 1, "CONTACT", "triangle 6 (nodes 1 2 2) is degenerate", "area 0"
    )


def test_collinear_triangle_is_degenerate():
    deck = with_nodes(cube_deck(particles=[], pdmp=()), node(50, 0.5, 0.0, 0.0))
    tris = list(triangles())
    tris[0] = replace(tris[0], nodes=(1, 50, 2))
    deck = replace(deck, contacts=(Contact(tuple(tris), ()),))
    _raises(deck, LINE_TRIANGLE, 1, "CONTACT", "triangle 1 (nodes 1 50 2) is degenerate")


def test_triangle_node_that_is_a_particle():
    tris = list(triangles())
    tris[2] = replace(tris[2], nodes=(5, 10, 6))
    deck = cube_deck(contacts=(Contact(tuple(tris), (slave_set([10]),)),))
    _raises(deck, LINE_TRIANGLE + 2, 1, "CONTACT", "triangle node 10 is a particle node")


@pytest.mark.parametrize(
    "field, value, phrase",
    [
        ("rzero", 0.0, "radius RZERO must be > 0"),
        ("rzero", -0.1, "radius RZERO must be > 0"),
        ("prho", 0.0, "density PRHO must be > 0"),
        ("e0", 0.0, "E0 must be > 0"),
        ("ppoi", 0.5, "PPOI must lie in (-1, 0.5)"),
        ("pcof", -0.1, "PCOF must be >= 0"),
    ],
)
def test_bad_particle_properties(field, value, phrase):
    deck = cube_deck()
    deck = replace(deck, pdmp=(replace(deck.pdmp[0], **{field: value}),))
    _raises(deck, LINE_PDMP, 1, "PDMP", phrase)


def test_relaxation_time_needed_for_a_maxwell_term():
    deck = cube_deck()
    deck = replace(deck, pdmp=(replace(deck.pdmp[0], e1=1e6, t1=0.0),))
    _raises(deck, LINE_PDMP, 1, "PDMP", "T1 must be > 0 when E1 is not zero")


def test_pdmp_groups_must_increase():
    deck = cube_deck()
    deck = replace(deck, pdmp=(deck.pdmp[0], replace(deck.pdmp[0], nodlim=5, pos=pos(22))))
    _raises(deck, 22, 1, "PDMP", "NODLIM 5 must be larger than the previous PDMP card's NODLIM 9")


@pytest.mark.parametrize("field", ["mass", "ixx", "izz"])
def test_negative_mass_or_inertia(field):
    deck = cube_deck()
    deck = replace(deck, masses=(replace(deck.masses[0], **{field: -1.0}),))
    _raises(deck, LINE_MASS, 1, "MASS", "negative")


def test_negative_element_mass():
    deck = cube_deck()
    deck = replace(deck, materials=(replace(deck.materials[0], mass=-2.0),))
    _raises(deck, LINE_MATERIAL, 1, "MATID", "negative element mass -2")


def test_particle_in_two_slave_sets():
    deck = cube_deck(particles=[(0.5, 0.5, 0.5), (0.2, 0.2, 0.2)])
    tris2 = tuple(replace(t, set_id=2) for t in triangles(first_line=150))
    deck = replace(
        deck,
        contacts=(
            Contact(triangles() + tris2, (slave_set([10, 11]), slave_set([11], 2, line=92))),
        ),
    )
    _raises(
        deck,
        92,
        5,
        "CONTACT",
        "particle 11 is already a slave of another set",
        f"line {LINE_SLAVES}",
    )


def test_slave_that_is_not_a_particle():
    deck = cube_deck(contacts=(Contact(triangles(), (slave_set([10, 3]),)),))
    _raises(deck, LINE_SLAVES, 9, "CONTACT", "slave node 3 is not a particle")


def test_slave_set_without_triangles():
    deck = cube_deck(contacts=(Contact(triangles(), (slave_set([10], 4),)),))
    _raises(deck, LINE_SLAVES, 1, "CONTACT", "slave set 4 has no master triangles")


def test_free_massless_node_loaded_by_a_spring():
    deck = with_nodes(cube_deck(particles=[], pdmp=()), node(50, 3, 0, 0))
    deck = replace(deck, elements=deck.elements + (Element(2, 2, (50,), pos(31)),))
    _raises(
        deck,
        LINE_NODE + 50,
        1,
        "NODE COORDINATES",
        "node 50 has no mass but its free x DOF is loaded by element 2 (line 31)",
        "add a MASS record for node 50",
        "fix DOF 1",
    )


def test_free_massless_node_loaded_by_a_wall():
    # the cavity's corners are not in a rigid body and nothing fixes them
    deck = cube_deck(rbels=(), boundaries=(Boundary(9, 9, 1, (2, 3, 4, 5, 6), pos(60)),))
    _raises(
        deck,
        LINE_NODE + 1,
        1,
        "NODE COORDINATES",
        "node 1 has no mass",
        "wall contact of the CONTACT triangle at line",
    )


def test_massless_rigid_body_loaded_by_its_spring():
    deck = cube_deck(masses=())
    _raises(
        deck,
        LINE_NODE + 9,
        1,
        "NODE COORDINATES",
        "the rigid body of master 9 has no mass but its free x DOF is loaded by",
        "add a MASS record for node 9",
    )


def test_free_massless_node_loaded_by_usrfrc():
    deck = with_nodes(cube_deck(particles=[], pdmp=()), node(50, 3, 0, 0))
    _raises(
        deck,
        LINE_NODE + 50,
        1,
        "NODE COORDINATES",
        "node 50 has no mass",
        "USRFRC force 'constant:node=50,dof=2,amp=1'",
        "fix DOF 2",
        usrfrc=("constant:node=50,dof=2,amp=1",),
    )


def test_massless_node_is_fine_when_fixed_slaved_or_prescribed():
    base = with_nodes(cube_deck(particles=[], pdmp=()), node(50, 3, 0, 0))
    loaded = replace(base, elements=base.elements + (Element(2, 2, (50,), pos(31)),))
    # fixed x (the spring acts along x only: ky = kz = 0 and c acts on fixed y, z too)
    fixed = replace(
        loaded, boundaries=loaded.boundaries + (Boundary(50, 50, 1, (1, 2, 3), pos(61)),)
    )
    build_model(fixed)
    # slave of the rigid body
    rb = loaded.rbels[0]
    slaved = replace(loaded, rbels=(replace(rb, slaves=rb.slaves + (50,), slave_positions=()),))
    build_model(slaved)
    # driven by prescribed motion on every loaded DOF
    build_model(loaded, motion=tuple(f"node=50,dof={d},amp=0.1,hz=1" for d in (1, 2, 3)))


def test_bad_usrfrc_spec_on_the_deck_points_at_the_card():
    deck = cube_deck(usrfrc=(Usrfrc(("sine:node=9,dof=1,amp=1,hz=-3",), pos(95, 2)),))
    _raises(deck, 95, 2, "USRFRC", "hz=")


def test_bad_usrfrc_spec_on_the_command_line_is_a_usrfrc_error():
    with pytest.raises(UsrfrcError, match="node=99"):
        build_model(cube_deck(), usrfrc=("constant:node=99,dof=1,amp=1",))


def test_ambiguous_inside_of_a_lone_floor():
    """A floor alone: its nodes' centroid lies in its plane; without particles nothing tells."""
    floor = (Triangle(1, (1, 2, 3), pos(LINE_TRIANGLE)), Triangle(1, (1, 3, 4), pos(71)))
    deck = cube_deck(contacts=(Contact(floor, ()),))
    _raises(deck, LINE_TRIANGLE, 1, "CONTACT", "cannot tell the inside of triangle 1")


def test_lone_floor_takes_its_inside_from_its_particles():
    floor = (Triangle(1, (1, 2, 3), pos(LINE_TRIANGLE)), Triangle(1, (1, 4, 3), pos(71)))
    m = build_model(
        cube_deck(particles=[(0.5, 0.5, -0.5)], contacts=(Contact(floor, (slave_set([10]),)),))
    )
    # (1,2,3) is wound +z and (1,4,3) -z; the particle is below, so both face -z
    assert m.tri_sign.tolist() == [-1.0, 1.0]


def test_error_positions_from_the_real_parser(tmp_path):
    """A duplicate node in a deck file: the parser's positions reach the message."""
    from pathlib import Path

    from x3dpd.deck import read_deck

    text = (Path(__file__).resolve().parents[2] / "decks" / "appendix_a_cube.inp").read_text()
    lines = text.splitlines()
    at = next(k for k, line in enumerate(lines) if line.split()[:1] == ["30"])
    lines.insert(at + 1, "   27   0.5   0.5   0.5")
    path = tmp_path / "dup.inp"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(DeckError) as info:
        build_model(read_deck(path))
    first = next(k for k, line in enumerate(lines) if line.split()[:1] == ["27"]) + 1
    assert info.value.line == at + 2 and info.value.card == "NODE COORDINATES"
    assert f"node 27 is defined twice (first at line {first})" in info.value.message
