"""The TEMPERATURE card (our extension): the temperature a deck runs at, and what it is made of.

A text card whose records start with a keyword (docs/deck-reference.md, "TEMPERATURE")::

    TEMPERATURE
      OPERATING 850F                 $ the temperature the run is at (required)
      ASSEMBLY  70F                  $ where the deck's numbers hold (default 70 °F)
      PARTICLES 8 tungsten-carbide   $ PARTICLES [NODLIM] MATERIAL: a PDMP group's material
      WALLS     titanium             $ WALLS [SET] MATERIAL: a CONTACT set's walls' material
    END

A temperature is a number with its unit (``850F``, ``455C``, ``728K``; also ``degF``, ``°C``)
or a bare number, read in the convention of the deck's UNITS card: degF in an inch or foot deck,
degC in a metric one (x3dpd.materials.temperature_units). A bare number in a deck without a
UNITS card is refused: nothing says which scale it is on. A PARTICLES or WALLS record without
an id is the material of every group (set) that has no record of its own. Materials are names
of the material library (x3dpd.materials, ``x3dpd materials``).

This module holds the card's records, reads them from the card's lines (the numbers' units
once the whole deck, and so its UNITS card, is known: :func:`resolved`) and writes them back;
:func:`with_temperature` sets the operating temperature from outside the deck
(``--temperature``, a design's ``temperature``). What the temperature does to the model -- the
properties at T and the expansion from the assembly temperature -- is x3dpd.model.temperature's.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace

from x3dpd.deck.text_card import TextCard
from x3dpd.errors import NOWHERE, DeckError, InputError, Pos
from x3dpd.materials import MaterialError, material, parse_temperature, temperature_unit_for

CARD = "TEMPERATURE"
#: The card's records and what each takes (for messages and the writer's header comment).
RECORDS = {
    "OPERATING": "T",
    "ASSEMBLY": "T0",
    "PARTICLES": "[NODLIM] MATERIAL",
    "WALLS": "[SET] MATERIAL",
}
#: The assembly temperature when the card gives none (the issue's and the report's room).
DEFAULT_ASSEMBLY = "70F"
#: How a unit is written after a number.
SUFFIX = {"degF": "F", "degC": "C", "K": "K"}
_BARE = re.compile(r"^\s*[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\s*$")
_ID = re.compile(r"^\d+$")


@dataclass(frozen=True)
class Reading:
    """A temperature as the deck gives it: ``text`` as written (the writer prints it back),
    ``kelvin`` [K] (None until :func:`resolved` has the deck's units), ``unit`` the unit it is
    on (degF, degC, K) and ``origin``: "" for the card's record, else what set it
    (``--temperature``)."""

    text: str
    kelvin: float | None = None
    unit: str = ""
    origin: str = field(default="", compare=False)
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class MaterialRecord:
    """PARTICLES [NODLIM] MATERIAL or WALLS [SET] MATERIAL: ``material`` (a library name, as
    written) of the PDMP group after node ``ident`` or of CONTACT set ``ident``'s walls; ``ident``
    None: of every group (set) without a record of its own."""

    ident: int | None
    material: str
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Temperature:
    """The TEMPERATURE card: the ``operating`` and ``assembly`` temperatures and the materials
    of the particle groups (``particles``) and of the walls (``walls``)."""

    operating: Reading
    assembly: Reading
    particles: tuple[MaterialRecord, ...] = ()
    walls: tuple[MaterialRecord, ...] = ()
    pos: Pos = NOWHERE

    def material_of(self, kind: str, ident: int) -> MaterialRecord | None:
        """The record naming the material of group (``kind`` "particles") or set ("walls")
        ``ident``: its own, else the card's record without an id, else None."""
        records = self.particles if kind == "particles" else self.walls
        own = [r for r in records if r.ident == ident]
        anyone = [r for r in records if r.ident is None]
        return (own or anyone or [None])[0]


def _err(message: str, pos: Pos) -> DeckError:
    return DeckError(message, "<deck>", pos.line, pos.column, CARD)


def _words(text: str, line: int, column: int) -> list[tuple[str, Pos]]:
    return [(m.group(0), Pos(line, column + m.start())) for m in re.finditer(r"[^ \t,]+", text)]


def _material_record(key: str, rest, kpos: Pos) -> MaterialRecord:
    what = "NODLIM (the PDMP group's)" if key == "PARTICLES" else "SET (the CONTACT set's)"
    ident = None
    if rest and _ID.match(rest[0][0]):
        ident = int(rest[0][0])
        rest = rest[1:]
    if not rest:
        raise _err(f"{key} takes [{what.split()[0]}] MATERIAL, a library name; got none", kpos)
    name = " ".join(w for w, _ in rest)
    try:
        material(name)
    except MaterialError as exc:
        raise _err(f"{key}: {exc}", rest[0][1]) from None
    return MaterialRecord(ident, name, kpos)


def parse_temperature_card(keyword_pos: Pos, lines: list[tuple[str, int, int]]) -> Temperature:
    """The card from its text lines ``(text, line, column)``; the temperatures are read later,
    with the deck's units (:func:`resolved`)."""
    found: dict[str, Reading] = {}
    records: dict[str, list[MaterialRecord]] = {"PARTICLES": [], "WALLS": []}
    for text, line, column in lines:
        words = _words(text, line, column)
        if not words:
            continue
        key, kpos = words[0][0].upper(), words[0][1]
        if key not in RECORDS:
            raise _err(
                f"unknown record {words[0][0]!r}: expected one of "
                + ", ".join(f"{k} {v}" for k, v in RECORDS.items()),
                kpos,
            )
        rest = words[1:]
        if key in ("OPERATING", "ASSEMBLY"):
            if key in found:
                raise _err(f"{key} is given twice (first at line {found[key].pos.line})", kpos)
            if not rest:
                raise _err(f"{key} takes a temperature, e.g. 850F, 455C or 728K", kpos)
            found[key] = Reading(" ".join(w for w, _ in rest), pos=rest[0][1])
            continue
        record = _material_record(key, rest, kpos)
        if any(r.ident == record.ident for r in records[key]):
            whom = "without an id" if record.ident is None else f"for {record.ident}"
            raise _err(f"a second {key} record {whom}", kpos)
        records[key].append(record)
    if "OPERATING" not in found:
        raise _err("no OPERATING record: give the temperature the deck runs at", keyword_pos)
    assembly = found.get("ASSEMBLY", Reading(DEFAULT_ASSEMBLY, pos=keyword_pos))
    return Temperature(
        found["OPERATING"],
        assembly,
        tuple(records["PARTICLES"]),
        tuple(records["WALLS"]),
        keyword_pos,
    )


def read_reading(reading: Reading, units, what: str) -> Reading:
    """``reading`` with its kelvin and unit: a bare number on the scale of the deck's ``units``
    (a UNITS card, or None: refused). Raises :class:`DeckError` at the reading."""
    if _BARE.match(reading.text) and units is None:
        raise _err(
            f"{what} {reading.text}: a temperature without a unit needs the deck's UNITS card "
            "(a bare number is then °F in an inch or foot deck, °C in a metric one); or write "
            f"its unit: {reading.text.strip()}F, {reading.text.strip()}C or "
            f"{reading.text.strip()}K",
            reading.pos,
        )
    system = units.system if units is not None else None
    try:
        kelvin, unit = parse_temperature(reading.text, temperature_unit_for(system))
    except MaterialError as exc:
        raise _err(f"{what}: {exc}", reading.pos) from None
    return replace(reading, kelvin=kelvin, unit=unit)


def resolved(card: Temperature, units) -> Temperature:
    """The card with its temperatures read (kelvin) in the deck's ``units`` (its UNITS card or
    None)."""
    return replace(
        card,
        operating=read_reading(card.operating, units, "OPERATING"),
        assembly=read_reading(card.assembly, units, "ASSEMBLY"),
    )


def with_temperature(deck, temperature, origin: str = "--temperature"):
    """``deck`` at the operating temperature ``temperature`` (a number on the scale of the
    deck's UNITS card, or a text with its unit: ``850F``) instead of its card's. Raises
    :class:`InputError` for a deck without a TEMPERATURE card, :class:`DeckError` (at the
    card, naming ``origin``) for a temperature that cannot be read."""
    card = deck.temperature
    if card is None:
        raise InputError(
            f"{origin} {temperature}: {deck.path} has no TEMPERATURE card to say what its "
            "particles and walls are made of (docs/deck-reference.md, TEMPERATURE)"
        )
    text = temperature if isinstance(temperature, str) else f"{float(temperature):g}"
    try:
        reading = read_reading(Reading(text, origin=origin, pos=card.pos), deck.units, origin)
    except DeckError as exc:
        raise DeckError(exc.message, deck.path, exc.line, exc.column, CARD) from None
    if _BARE.match(text):  # written with the unit it was read on, so the deck stands alone
        reading = replace(reading, text=f"{text.strip()}{SUFFIX[reading.unit]}")
    return replace(deck, temperature=replace(card, operating=reading))


def card_lines(card: Temperature) -> list[str]:
    """The card's records as the writer prints them (the temperatures as written)."""
    out = [f"OPERATING {card.operating.text}", f"ASSEMBLY {card.assembly.text}"]
    for key, records in (("PARTICLES", card.particles), ("WALLS", card.walls)):
        for r in records:
            out.append(
                " ".join([key, *([str(r.ident)] if r.ident is not None else []), r.material])
            )
    return out


#: The card's registration with the deck reader and writer (x3dpd.deck.text_cards).
TEXT_CARD = TextCard(
    CARD,
    "temperature",
    parse=parse_temperature_card,
    lines=card_lines,
    header=" | ".join(f"{k} {v}" for k, v in RECORDS.items()),
    resolve=resolved,
)

__all__ = [
    "CARD",
    "TEXT_CARD",
    "DEFAULT_ASSEMBLY",
    "RECORDS",
    "MaterialRecord",
    "Reading",
    "Temperature",
    "card_lines",
    "parse_temperature_card",
    "read_reading",
    "resolved",
    "with_temperature",
]
