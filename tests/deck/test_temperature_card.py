"""The TEMPERATURE card as the deck reader sees it (x3dpd.deck.temperature_card): its records,
their errors (one line ``FILE:LINE:COL: TEMPERATURE: message``), the writer, and a temperature
set from outside (``--temperature``, a design's ``temperature``)."""

from __future__ import annotations

import pytest
from deck_helpers import DECKS, strip_positions

from x3dpd.deck import format_deck, parse_deck, read_deck
from x3dpd.deck.temperature_card import with_temperature
from x3dpd.errors import DeckError, InputError

HEAD = "PARAMETERS\n 0 0.01 0 1e-6 1e-6 0 1e9 0 5 0 100\nEND\n"


def card(records: str, units: str = "") -> str:
    return HEAD + units + "TEMPERATURE\n" + records + "\nEND\n"


def test_records_temperatures_and_materials():
    deck = parse_deck(
        card("  OPERATING 455C\n  ASSEMBLY 70 degF\n  PARTICLES 8 tungsten carbide\n  WALLS ti")
    )
    t = deck.temperature
    assert t.operating.kelvin == pytest.approx(728.15) and t.operating.unit == "degC"
    assert t.assembly.kelvin == pytest.approx((70 - 32) * 5 / 9 + 273.15)
    assert [(r.ident, r.material) for r in t.particles] == [(8, "tungsten carbide")]
    assert [(r.ident, r.material) for r in t.walls] == [(None, "ti")]
    assert t.material_of("walls", 3).material == "ti"  # a record without an id: every set
    default = parse_deck(card("OPERATING 850F")).temperature.assembly
    assert default.text == "70F" and default.kelvin == pytest.approx(294.2611111111111)


@pytest.mark.parametrize(
    ("records", "units", "where", "message"),
    [
        (
            "OPERATING 850",
            "",
            (5, 11),
            "OPERATING 850: a temperature without a unit needs the deck's UNITS card",
        ),
        ("OPERATING 850X", "", (5, 11), "expected a number with a unit F, C or K"),
        ("OPERATING -500F", "", (5, 11), "below absolute zero"),
        ("PARTICLES wc", "", (4, 1), "no OPERATING record"),
        ("OPERATING 1F\nOPERATING 2F", "", (6, 1), "OPERATING is given twice (first at line 5)"),
        ("OPERATING 1F\nWALLS unobtainium", "", (6, 7), "unknown material 'unobtainium'"),
        ("OPERATING 1F\nWALLS 3", "", (6, 1), "WALLS takes [SET] MATERIAL"),
        ("OPERATING 1F\nWALLS ti\nWALLS wc", "", (7, 1), "a second WALLS record without an id"),
        ("HOT 850F", "", (5, 1), "unknown record 'HOT': expected one of OPERATING T"),
        ("OPERATING 850", "UNITS\n m N s\nEND\n", None, None),  # fine: degC in a metric deck
    ],
)
def test_bad_records_are_one_line_errors_at_the_value(records, units, where, message):
    text = card(records, units)
    if message is None:
        assert parse_deck(text).temperature.operating.unit == "degC"
        return
    with pytest.raises(DeckError) as info:
        parse_deck(text, "t.inp")
    line = where[0] + text[: text.index("TEMPERATURE")].count("\n") - 3
    assert str(info.value).startswith(f"t.inp:{line}:{where[1]}: TEMPERATURE: ")
    assert message in str(info.value) and "\n" not in str(info.value)


def test_the_writer_prints_the_card_back_as_read():
    deck = parse_deck(
        card("OPERATING 850 degF\nASSEMBLY 21C\nPARTICLES 3 tungsten carbide\nWALLS ti")
    )
    again = parse_deck(format_deck(deck))
    assert strip_positions(again) == strip_positions(deck)
    shipped = read_deck(DECKS / "capsule_wc7.inp")
    assert strip_positions(parse_deck(format_deck(shipped))) == strip_positions(shipped)


def test_a_temperature_from_outside_replaces_operating():
    deck = read_deck(DECKS / "capsule_wc7.inp")  # UNITS in lbf s: bare numbers are degF
    hot = with_temperature(deck, 850)
    assert hot.temperature.operating.text == "850F"
    assert hot.temperature.operating.kelvin == pytest.approx((850 - 32) * 5 / 9 + 273.15)
    assert hot.temperature.assembly == deck.temperature.assembly
    assert with_temperature(deck, "455C").temperature.operating.unit == "degC"
    assert parse_deck(format_deck(hot)).temperature.operating.text == "850F"
    with pytest.raises(DeckError, match=r"capsule_wc7.inp:\d+:1: TEMPERATURE: --temperature: "):
        with_temperature(deck, "hot")
    with pytest.raises(InputError, match="has no TEMPERATURE card"):
        with_temperature(read_deck(DECKS / "beam_1.inp"), "850F")
    bare = parse_deck(card("OPERATING 70F"), "t.inp")  # no UNITS card: a bare number is refused
    with pytest.raises(DeckError, match="t.inp:4:1: TEMPERATURE: --temperature 850: a "):
        with_temperature(bare, 850)
