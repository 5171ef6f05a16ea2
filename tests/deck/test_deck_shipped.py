"""The shipped decks (report Appendix A, transcribed in decks/) parse to the printed values.

Each check runs on ``decks/appendix_a.inp`` and on a frozen copy of the transcription
(tests/fixtures/decks/good/); positions are located in the file's own text, so a comment header
added to the shipped deck does not break them, and the frozen copy pins them to exact numbers.
"""

from __future__ import annotations

import pytest
from deck_helpers import DECKS, FIXTURES, strip_positions, where

from x3dpd.deck import Pos, format_deck, parse_deck, read_deck

PRINTED = FIXTURES / "good" / "appendix_a_printed.inp"


@pytest.fixture(scope="module", params=[DECKS / "appendix_a.inp", PRINTED], ids=["decks", "frozen"])
def appendix_a(request):
    deck = read_deck(request.param)
    assert deck.path == str(request.param)
    return deck


def _at(deck, needle, occurrence=0):
    return where(deck.path, needle, occurrence)


def test_exact_positions_in_the_frozen_copy():
    deck = read_deck(PRINTED)
    assert deck.parameters.pos == Pos(8, 7)  # first value, after the '$' header line
    assert deck.nodes[25].pos == Pos(66, 4)  # '   26   3.12500e-002 ...'
    assert deck.rbels[0].pos == Pos(123, 6)  # 'RBEL 25,123456, 24, &'
    assert deck.contacts[0].slaves[0].positions[-1] == Pos(151, 12)


def test_title_is_kept_verbatim(appendix_a):
    assert appendix_a.title.text == (
        '(50) 0.0625" diameter steel particles with viscoelastic properties\n'
        'cavity interior dimensions: 0.25 x 0.25 x 0.25"\n'
        "coefficient of friction =0.30"
    )


def test_parameters(appendix_a):
    p = appendix_a.parameters
    assert (p.time, p.tmax, p.trest, p.dtmin, p.dtmax) == (0.0, 15.0, 0.1, 5e-7, 5e-7)
    assert (p.incr, p.incmax, p.irest, p.nintpl, p.istat, p.itrac) == (0, 1e9, 0, 5, 0, 2000)
    assert p.pos == _at(appendix_a, "0.  15.000")


def test_matid_record_spans_two_lines(appendix_a):
    (m,) = appendix_a.materials
    assert (m.mid, m.mtype, m.mass, m.scale) == (2, 1, 1.0e-12, 1.0)
    assert (m.kx, m.ky, m.kz, m.c) == (11.4882, 1e12, 1e12, 3.08293e-4)
    assert m.extra == (11.4882, 0, 0, 1, 0, 0, 1)
    assert m.pos == _at(appendix_a, "2, 1, 1.0e-12")


def test_pdmp(appendix_a):
    (g,) = appendix_a.pdmp
    assert (g.nodlim, g.rzero, g.prho, g.ppoi) == (25, 0.03125, 7.32971e-4, 0.33)
    assert (g.e0, g.e1, g.t1, g.pcof) == (25.0e6, 10.0e6, 2.0e-6, 0.30)
    assert (g.vx0, g.vy0, g.vz0, g.extra_terms) == (0.0, 0.0, 0.0, ())


def test_body_and_trace(appendix_a):
    assert (appendix_a.body.ax, appendix_a.body.ay, appendix_a.body.az) == (0.0, -386.1, 0.0)
    trace = appendix_a.trace
    assert trace.nodes == tuple(range(25, 76))  # 51 nodes; printed without commas before '&'
    assert len(trace.positions) == 51
    assert trace.positions[0] == _at(appendix_a, "25, 26, 27")
    assert trace.positions[10] == _at(appendix_a, "35, 36")


def test_nodes(appendix_a):
    nodes = appendix_a.nodes
    assert len(nodes) == 75
    assert [n.nid for n in nodes] == list(range(1, 76))
    n26 = nodes[25]
    assert (n26.nid, n26.x, n26.y, n26.z) == (26, 0.03125, 0.03125, -0.09375)
    assert n26.pos == _at(appendix_a, "26   3.12500e-002")
    assert (nodes[0].x, nodes[0].y, nodes[0].z) == (0.0, 0.1875, -0.125)


def test_structure_cards(appendix_a):
    (e,) = appendix_a.elements
    assert (e.eid, e.mid, e.nodes) == (1, 2, (25,))
    (m,) = appendix_a.masses
    assert (m.nid, m.mass, m.ixx, m.iyy, m.izz) == (25, 3.002e-3, 1e20, 1e20, 1e20)
    (r,) = appendix_a.rbels
    assert (r.master, r.dofs, r.slaves) == (25, (1, 2, 3, 4, 5, 6), tuple(range(1, 25)))
    assert r.pos == _at(appendix_a, "25,123456")
    assert r.slave_positions[0] == _at(appendix_a, "1, 2, 3, 4, 5, 6, 7")
    (b,) = appendix_a.boundaries
    assert (b.first, b.last, b.inc, b.dofs) == (1, 25, 1, (2, 3, 4, 5, 6))


def test_contact(appendix_a):
    (c,) = appendix_a.contacts
    assert len(c.triangles) == 12
    assert all(t.set_id == 1 for t in c.triangles)
    assert c.triangles[0].nodes == (1, 2, 4) and c.triangles[-1].nodes == (22, 24, 23)
    (s,) = c.slaves
    assert s.set_id == 1 and s.nodes == tuple(range(26, 76)) and len(s.nodes) == 50
    last = _at(appendix_a, "73 74 75")
    assert s.positions[-1] == Pos(last.line, last.column + 6)


def test_cube_variant_differs_only_in_cavity_nodes(appendix_a):
    """decks/appendix_a_cube.inp: the same deck with nodes 1-24 moved onto the cube's faces."""
    cube, printed = (
        strip_positions(read_deck(DECKS / "appendix_a_cube.inp")),
        strip_positions(appendix_a),
    )
    assert cube.nodes[24:] == printed.nodes[24:]
    assert all(a != b for a, b in zip(cube.nodes[:24], printed.nodes[:24], strict=True))
    assert cube.contacts == printed.contacts and cube.pdmp == printed.pdmp


@pytest.mark.parametrize("name", ["appendix_a.inp", "appendix_a_cube.inp"])
def test_shipped_decks_round_trip(name):
    deck = read_deck(DECKS / name)
    assert deck.path == str(DECKS / name)
    again = parse_deck(format_deck(deck))
    assert strip_positions(again) == strip_positions(deck)
