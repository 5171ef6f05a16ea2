"""Every syntax form of the X3D free format that the grammar accepts, checked value by value."""

from __future__ import annotations

import re

import pytest
from deck_helpers import ROOT, strip_positions

from x3dpd.deck import Pos, parse_deck, read_deck
from x3dpd.deck import parser as deck_parser
from x3dpd.deck.fields import CARDS

PDMP_RECORD = "25, 0.03125, 7.32971e-4, 0.33, 25.0e6, 10.0e6, 2.0e-6, 0.30"


def test_values_on_the_keyword_line_and_end_on_the_last_line():
    deck = parse_deck(f"PDMP {PDMP_RECORD}, 0.0, 0.0, 0.0 END\n")
    (g,) = deck.pdmp
    assert (g.nodlim, g.rzero, g.e1, g.pcof) == (25, 0.03125, 10.0e6, 0.30)
    assert g.pos == Pos(1, 6)


def test_keyword_line_continued():
    deck = parse_deck("RBEL 25,123456, 4, &\n   1, 2, &\n   3, 4\nEND\n")
    (r,) = deck.rbels
    assert (r.master, r.dofs, r.slaves) == (25, (1, 2, 3, 4, 5, 6), (1, 2, 3, 4))
    assert r.pos == Pos(1, 6)
    assert r.slave_positions == (Pos(2, 4), Pos(2, 7), Pos(3, 4), Pos(3, 7))


@pytest.mark.parametrize("amp", [" &", ", &", ",&", "&", " & $ more on the next line", " ,  &  "])
def test_continuation_with_or_without_comma(amp):
    deck = parse_deck(f"TRACE\n 25, 26{amp}\n 27 28\nEND\n")
    assert deck.trace.nodes == (25, 26, 27, 28)


def test_blank_and_comment_lines_inside_a_continued_record():
    deck = parse_deck("TRACE\n 25 26 &\n\n$ a comment\n   \n 27\nEND\n")
    assert deck.trace.nodes == (25, 26, 27)
    assert deck.trace.positions[-1] == Pos(6, 2)


def test_comments_everywhere():
    text = (
        "$ leading comment\n\nBODY $ gravity\n$\n$ AX AY AZ\n 0.0, -386.1, 0.0 $ in/s^2\n"
        "END $ done\n$ trailing\n"
    )
    deck = parse_deck(text)
    assert (deck.body.ax, deck.body.ay, deck.body.az) == (0.0, -386.1, 0.0)
    assert deck.body.pos == Pos(6, 2)


@pytest.mark.parametrize(
    ("keyword", "field"),
    [
        ("TITL", "title"),
        ("TITLE", "title"),
        ("title", "title"),
        ("Titles", "title"),
        ("PARA", "parameters"),
        ("PARAMETERS", "parameters"),
        ("parameter", "parameters"),
        ("MATI", "materials"),
        ("MATID", "materials"),
        ("matid", "materials"),
        ("PDMP", "pdmp"),
        ("pdmp", "pdmp"),
        ("BODY", "body"),
        ("Body Force", "body"),
        ("TRAC", "trace"),
        ("TRACE", "trace"),
        ("tracer nodes", "trace"),
        ("NODE", "nodes"),
        ("NODE COORDINATES", "nodes"),
        ("nodes", "nodes"),
        ("ELEM", "elements"),
        ("ELEMENTS", "elements"),
        ("elem", "elements"),
        ("MASS", "masses"),
        ("masses", "masses"),
        ("RBEL", "rbels"),
        ("rbel", "rbels"),
        ("BOUN", "boundaries"),
        ("BOUNDARY CONDITIONS", "boundaries"),
        ("boundary", "boundaries"),
        ("CONT", "contacts"),
        ("CONTACT", "contacts"),
        ("contact surfaces", "contacts"),
        ("INIT", "initials"),
        ("INITIAL", "initials"),
        ("INITIAL VELOCITIES", "initials"),
        ("USRF", "usrfrc"),
        ("USRFRC", "usrfrc"),
        ("usrfrc", "usrfrc"),
    ],
)
def test_keywords_by_four_letters_any_case(keyword, field):
    bodies = {
        "title": "a title\nEND",
        "parameters": "0 1 0 1e-7 1e-7 0 1e9 0 5 0 1\nEND",
        "materials": "2 1 0 1 1 1 1 0\nEND",
        "pdmp": f"{PDMP_RECORD}\nEND",
        "body": "0 -386.1 0\nEND",
        "trace": "25\nEND",
        "nodes": "1 0 0 0\nEND",
        "elements": "1 2 25\nEND",
        "masses": "25 1.0\nEND",
        "rbels": "25 123 1 3\nEND",
        "boundaries": "1 25 1 2\nEND",
        "contacts": "1 1 2 3\nEND\n1 26\nEND",
        "initials": "26 1 0 0\nEND",
        "usrfrc": "sine:node=25,dof=1,amp=1,hz=2\nEND",
    }
    deck = parse_deck(f"{keyword}\n{bodies[field]}\n")
    assert getattr(deck, field)


def test_end_is_case_insensitive_and_may_be_indented():
    deck = parse_deck("body\n 0 0 -1\n   end\ntrace\n 1 2 End\n")
    assert deck.body.az == -1.0 and deck.trace.nodes == (1, 2)


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("0.", 0.0),
        ("5.e-7", 5e-7),
        ("1.e9", 1e9),
        ("1.0E20", 1e20),
        ("1.87500e-001", 0.1875),
        ("10.0e6", 1e7),
        ("-386.100", -386.1),
        ("+1", 1.0),
        ("1.0D0", 1.0),
        ("2.5d-3", 2.5e-3),
        (".5", 0.5),
        ("-.5E+2", -50.0),
        ("7", 7.0),
        ("0.00000e+000", 0.0),
        ("3.08293e-4", 3.08293e-4),
    ],
)
def test_fortran_numbers(text, value):
    deck = parse_deck(f"BODY\n {text} {text},{text}\nEND\nNODE\n 1 {text} 0 0\nEND\n")
    assert (deck.body.ax, deck.body.ay, deck.body.az) == (value, value, value)
    assert deck.nodes[0].x == value


@pytest.mark.parametrize(("text", "value"), [("25", 25), ("25.", 25), ("2.5e1", 25), ("+25", 25)])
def test_integer_fields_accept_integral_numbers(text, value):
    deck = parse_deck(f"ELEMENTS\n 1 2 {text}\nEND\n")
    assert deck.elements[0].nodes == (value,)


def test_separators_blanks_tabs_and_commas():
    deck = parse_deck(
        "NODE COORDINATES\n1,0.5,0.25,0.125\n\t2\t1.0 ,2.0,  3.0\n3 , 4 ,5 ,6 ,\nEND\n"
    )
    assert [(n.nid, n.x, n.y, n.z) for n in deck.nodes] == [
        (1, 0.5, 0.25, 0.125),
        (2, 1.0, 2.0, 3.0),
        (3, 4.0, 5.0, 6.0),
    ]
    assert [n.pos for n in deck.nodes] == [Pos(2, 1), Pos(3, 2), Pos(4, 1)]


def test_contact_with_two_slave_sets_and_two_triangle_sets():
    text = "CONTACT\n 1 1 2 4\n 1 2 3 4\n 2 5 6 7\nEND\n 1 26 27 28 &\n   29 30\n 2 31, 32\nEND\n"
    (c,) = parse_deck(text).contacts
    assert [(t.set_id, t.nodes) for t in c.triangles] == [
        (1, (1, 2, 4)),
        (1, (2, 3, 4)),
        (2, (5, 6, 7)),
    ]
    assert [(s.set_id, s.nodes) for s in c.slaves] == [(1, (26, 27, 28, 29, 30)), (2, (31, 32))]
    assert c.slaves[0].positions[-1] == Pos(7, 7) and c.slaves[1].pos == Pos(8, 2)
    assert c.pos == Pos(1, 1)


def test_contact_without_slaves():
    (c,) = parse_deck("CONTACT\n 1 1 2 3\nEND\nEND\n").contacts
    assert len(c.triangles) == 1 and c.slaves == ()


def test_several_pdmp_cards_are_particle_groups_in_file_order():
    text = (
        f"PDMP\n {PDMP_RECORD}\nEND\n"
        "PDMP\n 75, 0.05, 7.3e-4, 0.33, 25.0e6, 0.0, 1.0, 0.2, 1.0, 2.0, 3.0, 5.e6, 1.e-5 &\n"
        "   2.e6, 1.e-4\n 90 0.01 1e-3 0.3 1e7 0 1 0\nEND\n"
    )
    g1, g2, g3 = parse_deck(text).pdmp
    assert (g1.nodlim, g1.vx0, g1.extra_terms) == (25, 0.0, ())
    assert (g2.nodlim, g2.rzero, g2.e1, (g2.vx0, g2.vy0, g2.vz0)) == (75, 0.05, 0.0, (1, 2, 3))
    assert g2.extra_terms == ((5e6, 1e-5), (2e6, 1e-4))
    assert (g3.nodlim, g3.pcof) == (90, 0.0)


def test_repeated_cards_accumulate_in_file_order():
    text = (
        "MATID\n 2 1 0 1 1 1 1 0\nEND\nNODE\n 1 0 0 0\nEND\nMATID\n 3 1 0 1 2 2 2 0 9 9\nEND\n"
        "NODE\n 2 1 0 0\nEND\nUSRFRC\n sine:node=1,dof=1,amp=1,hz=1\nEND\n"
        "USRFRC\n sine:node=2,dof=2,amp=1,hz=1\n  ramp:node=2  \nEND\n"
    )
    deck = parse_deck(text)
    assert [m.mid for m in deck.materials] == [2, 3] and deck.materials[1].extra == (9.0, 9.0)
    assert [n.nid for n in deck.nodes] == [1, 2]
    assert [u.specs for u in deck.usrfrc] == [
        ("sine:node=1,dof=1,amp=1,hz=1",),
        ("sine:node=2,dof=2,amp=1,hz=1", "ramp:node=2"),
    ]


def test_title_lines_are_kept_verbatim():
    text = (
        "TITLE first line on the keyword line\n  indented second line  \n\n$ a comment\n"
        "PARAMETERS study, cost $5\nEND\n"
    )
    deck = parse_deck(text)
    assert deck.title.text == (
        "first line on the keyword line\n  indented second line\nPARAMETERS study, cost"
    )
    assert parse_deck("TITLE\nEND\n").title.text == ""
    assert parse_deck("TITLE\nENDING is not END\nend\n").title.text == "ENDING is not END"


def test_optional_fields_default_to_zero():
    deck = parse_deck(
        "MASS\n 25 3.0e-3\n 26 1 2\nEND\nINITIAL\n 26 1 2 3\n 27 1 2 3 4 5 6\n"
        "END\nPDMP\n 25 .1 1 .3 1 0 1 .3 5\nEND\n"
    )
    assert [(m.mass, m.ixx, m.iyy, m.izz) for m in deck.masses] == [(3e-3, 0, 0, 0), (1, 2, 0, 0)]
    assert [i.velocity for i in deck.initials] == [(1, 2, 3), (1, 2, 3, 4, 5, 6)]
    assert (deck.pdmp[0].vx0, deck.pdmp[0].vy0, deck.pdmp[0].vz0) == (5.0, 0.0, 0.0)


def test_elements_with_one_or_two_nodes():
    deck = parse_deck("ELEMENTS\n 1 2 25\n 2 2 25 26\nEND\n")
    assert [e.nodes for e in deck.elements] == [(25,), (25, 26)]


def test_boundary_and_dof_codes():
    deck = parse_deck(
        "BOUNDARY CONDITIONS\n 1, 25, 1, 2, 3, 4, 5 6\n 30 40 2 1\nEND\n"
        "RBEL\n 25 135 1 3\n 26 6 2 4 5\nEND\n"
    )
    assert [(b.first, b.last, b.inc, b.dofs) for b in deck.boundaries] == [
        (1, 25, 1, (2, 3, 4, 5, 6)),
        (30, 40, 2, (1,)),
    ]
    assert [(r.dofs, r.slaves) for r in deck.rbels] == [((1, 3, 5), (3,)), ((6,), (4, 5))]


def test_line_ends_bom_and_missing_final_newline():
    unix = parse_deck("BODY\n 0 -1 0\nEND\nTRACE\n 1 2\nEND")
    dos = parse_deck("\ufeffBODY\r\n 0 -1 0\r\nEND\r\nTRACE\r\n 1 2\r\nEND\r\n")
    assert strip_positions(unix) == strip_positions(dos)
    assert unix.trace.positions == dos.trace.positions


def test_indented_keywords_and_blank_lines_between_cards():
    deck = parse_deck("\n\n   BODY\n 0 0 0\n END\n\n\n  TRACE 5 6 END\n\n")
    assert deck.body.pos == Pos(4, 2) and deck.trace.nodes == (5, 6)


def test_read_deck_and_parse_deck_agree(tmp_path):
    text = (ROOT / "decks" / "appendix_a.inp").read_text()
    path = tmp_path / "a.inp"
    path.write_text(text)
    assert read_deck(path) == parse_deck(text, str(path))


def test_read_deck_accepts_str_and_pathlike(tmp_path):
    path = tmp_path / "b.inp"
    path.write_text("BODY\n 0 0 0\nEND\n")
    assert read_deck(str(path)).path == str(path) and read_deck(path).path == str(path)


def test_grammar_has_a_terminal_per_card():
    # x3d.lark plus one keyword per registered analytic wall shape (CYLINDER, CAPSULE ...)
    grammar = deck_parser.grammar()
    for card in CARDS:
        terminal = card.name.split()[0]
        pattern = rf"^{terminal}: /{card.key}"
        assert re.search(pattern, grammar, re.MULTILINE | re.IGNORECASE), card.name
    assert set(deck_parser.KEYWORD_TERMINALS.values()) == {c.name for c in CARDS}


def test_big_cards_take_the_same_path_as_small_ones():
    """A 20,000-line NODE card with a few odd lines in it (the fast path falls back)."""
    lines = [f"{i} {i * 0.5} {-i * 0.25:.6e} 0." for i in range(1, 20001)]
    lines[9] = "10, 5.0, -2.5, 0."
    lines[99] = "100 5.0D1 -25. 0. $ comment"
    lines[999] = "1000 500. -250.\t0."
    deck = parse_deck("NODE\n" + "\n".join(lines) + "\n$ last\nEND\n")
    assert len(deck.nodes) == 20000
    assert [n.nid for n in deck.nodes] == list(range(1, 20001))
    assert (deck.nodes[99].x, deck.nodes[99].y) == (50.0, -25.0)
    assert deck.nodes[19999].pos == Pos(20001, 1)


def test_the_gate_never_changes_a_result(monkeypatch):
    """With the early-stop gate flagging every line, decks still parse (it only saves time)."""
    text = (ROOT / "decks" / "appendix_a.inp").read_text()
    expected = parse_deck(text)
    monkeypatch.setattr(deck_parser._Gate, "_line", lambda self, line: False)
    assert parse_deck(text) == expected
