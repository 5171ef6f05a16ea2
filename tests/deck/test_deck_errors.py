"""Every bad deck gives one DeckError with the exact place, card and what was expected.

One fixture per error in tests/fixtures/decks/bad/; each row gives the file, the line and
column the message must point at, the card named, and a phrase the message must contain.
"""

from __future__ import annotations

import pytest
from deck_helpers import FIXTURES

from x3dpd.deck import parse_deck, read_deck
from x3dpd.errors import DeckError

BAD = FIXTURES / "bad"

CASES = [
    # file, line, column, card, key phrase
    ("unknown_keyword.inp", 4, 1, "DECK", "unknown card keyword 'REEL'; did you mean RBEL?"),
    (
        "missing_end_next_card.inp",
        3,
        1,
        "PDMP",
        "PDMP (opened at line 1) has no END before the next card BODY",
    ),
    (
        "missing_end_eof.inp",
        7,
        1,
        "NODE COORDINATES",
        "NODE COORDINATES (opened at line 4) has no END: the file ends inside it",
    ),
    ("missing_end_title.inp", 3, 1, "TITLE", "TITLE (opened at line 1) has no END"),
    ("contact_one_block.inp", 4, 1, "CONTACT", "has no second END (a CONTACT card is: master"),
    ("contact_second_block_eof.inp", 6, 1, "CONTACT", "has no second END"),
    ("non_number.inp", 3, 14, "NODE COORDINATES", "Y (field 3) must be a number; got 'abc'"),
    ("non_number_continued.inp", 3, 8, "TRACE", "NODE (field 5) must be a number; got 'x29'"),
    ("bad_number_two_dots.inp", 2, 8, "BODY", "AY (field 2) must be a number; got '-386.1.0'"),
    (
        "parameters_too_few.inp",
        3,
        7,
        "PARAMETERS",
        (
            "PARAMETERS needs 11 values: TIME TMAX TREST DTMIN DTMAX INCR INCMAX IREST NINTPL ISTAT "
            "ITRAC; got 9"
        ),
    ),
    ("parameters_two_records.inp", 3, 5, "PARAMETERS", "a second record starts here"),
    ("body_too_many.inp", 2, 22, "BODY", "BODY needs 3 values: AX AY AZ; got 4"),
    ("node_too_few.inp", 2, 5, "NODE COORDINATES", "needs 4 values: ID X Y Z; got 3"),
    (
        "matid_too_few.inp",
        2,
        4,
        "MATID",
        "needs at least 8 values: MID TYPE MASS SCALE KX KY KZ C [EXTRA...]; got 7",
    ),
    ("initial_fields.inp", 2, 4, "INITIAL", "needs 4 or 7 values: NODE VX VY VZ [WX WY WZ]"),
    ("contact_triangle_fields.inp", 2, 4, "CONTACT", "4 values per master triangle"),
    ("integer_expected.inp", 3, 6, "ELEMENTS", "MID (field 2) must be an integer; got 2.5"),
    ("id_not_positive.inp", 2, 5, "NODE COORDINATES", "ID (field 1) must be a positive integer"),
    ("rbel_count_mismatch.inp", 1, 17, "RBEL", "RBEL declares COUNT=24 slave nodes but lists 23"),
    ("rbel_dof_code.inp", 1, 10, "RBEL", "DOFS (field 2) must be a code of distinct DOF digits"),
    ("boundary_last_before_first.inp", 2, 8, "BOUNDARY CONDITIONS", "LAST must be >= FIRST"),
    ("boundary_dof_range.inp", 2, 20, "BOUNDARY CONDITIONS", "must be a DOF number 1..6"),
    ("boundary_dof_twice.inp", 2, 20, "BOUNDARY CONDITIONS", "DOF 2 is listed twice"),
    ("dtmin_gt_dtmax.inp", 2, 28, "PARAMETERS", "DTMIN must be between 0 and DTMAX"),
    ("dtmax_not_positive.inp", 2, 36, "PARAMETERS", "DTMAX must be > 0"),
    ("tmax_before_time.inp", 2, 11, "PARAMETERS", "TMAX must be >= TIME"),
    ("itrac_zero.inp", 2, 83, "PARAMETERS", "must be >= 1; got 0"),
    ("rzero_not_positive.inp", 1, 10, "PDMP", "RZERO (particle radius) must be > 0"),
    ("prho_not_positive.inp", 2, 17, "PDMP", "PRHO (particle density) must be > 0"),
    ("pdmp_odd_maxwell.inp", 3, 19, "PDMP", "extra Maxwell terms come in pairs"),
    ("mass_negative.inp", 2, 8, "MASS", "MASS (field 2) must be >= 0"),
    (
        "duplicate_parameters.inp",
        7,
        1,
        "PARAMETERS",
        "PARAMETERS may appear only once; it was already given at line 1",
    ),
    ("amp_mid_line.inp", 2, 7, "TRACE", "'&' continues a record only at the end of a line"),
    ("text_after_end.inp", 3, 5, "BODY", "END must end its line; got 'BODY'"),
    ("values_outside_card.inp", 4, 4, "DECK", "expected a card keyword at the start of a line"),
    ("stray_end.inp", 2, 1, "DECK", "END with no card open"),
    ("empty.inp", 1, 1, "DECK", "the deck is empty"),
    ("comments_only.inp", 1, 1, "DECK", "the deck is empty"),
    ("nul_byte.inp", 2, 7, "DECK", "NUL byte"),
    ("not_utf8.inp", 2, 9, "DECK", "byte 0xb0 is not UTF-8 text"),
    ("control_char.inp", 2, 6, "DECK", "control character U+0007"),
]


@pytest.mark.parametrize(
    ("name", "line", "column", "card", "phrase"), CASES, ids=[c[0] for c in CASES]
)
def test_bad_deck(name, line, column, card, phrase):
    path = BAD / name
    with pytest.raises(DeckError) as info:
        read_deck(path)
    e = info.value
    assert (e.path, e.line, e.column, e.card) == (str(path), line, column, card)
    assert phrase in e.message
    assert str(e) == f"{path}:{line}:{column}: {card}: {e.message}"


def test_every_fixture_has_a_case():
    assert sorted(p.name for p in BAD.glob("*.inp")) == sorted(c[0] for c in CASES)


@pytest.mark.parametrize(
    ("name", "line", "column", "card", "phrase"),
    [c for c in CASES if c[0] not in ("not_utf8.inp",)],
    ids=[c[0] for c in CASES if c[0] not in ("not_utf8.inp",)],
)
def test_parse_deck_reports_the_same(name, line, column, card, phrase):
    """parse_deck(text) and read_deck(path) share one pipeline and give the same error."""
    text = (BAD / name).read_bytes().decode("utf-8")
    with pytest.raises(DeckError) as info:
        parse_deck(text, "x.inp")
    assert (info.value.line, info.value.column, info.value.card) == (line, column, card)
    assert phrase in info.value.message


def test_missing_file_is_a_deck_error(tmp_path):
    with pytest.raises(DeckError, match="cannot read the deck"):
        read_deck(tmp_path / "nope.inp")


@pytest.mark.parametrize(
    ("text", "phrase"),
    [
        ("TITLE\nx\nEND\nPARM\n", "did you mean PARAMETERS?"),
        ("TITEL\nx\nEND\n", "did you mean TITLE?"),
        ("MATERIAL\n 1 1 0 1 1 1 1 0\nEND\n", "did you mean MATID?"),
        ("GRAVITY\n 0 -386.1 0\nEND\n", "expected one of TITLE, PARAMETERS"),
    ],
)
def test_unknown_keyword_suggestions(text, phrase):
    with pytest.raises(DeckError, match=phrase.replace("?", r"\?")):
        parse_deck(text)


@pytest.mark.parametrize(
    "text",
    [
        "TRACE\n 1 2\n 3 2.5\nEND\n",  # integer expected in a list
        "NODE\n 1 0 0 0 0\nEND\n",  # too many (slow path of the node fast path)
        "NODE\n 1, 0, 0\nEND\n",  # too few with commas
        "NODE\n 1 0 0 0 $ c\n 2 0 0\nEND\n",
        "NODE\n -1 0 0 0\nEND\n",
        "CONTACT\n1 1 2 3\nEND\n 1\nEND\n",  # a slave record without nodes
        "RBEL\n 25 123456 0\nEND\n",
        "TRACE\nEND\n",
        "BODY\nEND\n",
        "ELEMENTS\n 1 2 3 4 5\nEND\n",
        "INITIAL\n 28 1 2 3 4\nEND\n",  # rotational velocities come all three or none
        "INITIAL\n 28 1 2 3 4 5 6 7\nEND\n",
        "MASS\n 25 1 2 3 4 5\nEND\n",
        "PDMP\n 25 .1 1 .3 1 1 1\nEND\n",
        "PDMP\n -1 .1 1 .3 1 1 1 .3\nEND\n",
        "BOUNDARY CONDITIONS\n 1 25 0 2\nEND\n",
        "TITLE\nx\nEND\nTITLE\ny\nEND\n",
        "BODY\n 0 0 0\nEND\nTRACE\n 1\nEND\nBODY\n 1 1 1\nEND\n",
        "BODY\n 1e400 0 0\n",
        "NODE\n 1 0 0 0 &\nEND\n",
        "BODY\n 0 0 0 END END\n",
        "\x0c",
        "TITLE\r\nx\rEND\n",
    ],
)
def test_more_bad_decks_give_deck_errors(text):
    with pytest.raises(DeckError) as info:
        parse_deck(text, "t.inp")
    assert info.value.line >= 1 and info.value.column >= 1
