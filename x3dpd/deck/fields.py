"""The card table of the X3D deck language: canonical names, four-letter keys and field names.

X3D identifies a card by the first four letters of its keyword, so ``BOUN``, ``BOUNDARY`` and
``BOUNDARY CONDITIONS`` are the same card. The parser uses this table for messages (field names,
"did you mean ...") and the writer for canonical names and the ``$`` header comments.
``docs/deck-reference.md`` gives each field's unit role and default.
"""

from __future__ import annotations

from dataclasses import dataclass

from x3dpd.geometry.shapes import SHAPES
from x3dpd.deck.text_cards import TEXT_CARDS
from x3dpd.physics.effect_units import UNITS


@dataclass(frozen=True)
class CardSpec:
    """One card of the deck language.

    Parameters
    ----------
    name : str
        Canonical keyword, as the writer prints it (``"NODE COORDINATES"``).
    key : str
        The four letters X3D reads (``"NODE"``); any word starting with them names the card.
    fields : tuple of str
        Names of a record's fields, in order (for messages and the writer's header comments).
    repeat : str
        Name of the field that repeats after ``fields`` ("" when a record has no list).
    """

    name: str
    key: str
    fields: tuple[str, ...]
    repeat: str = ""

    def field_name(self, index: int) -> str:
        """Name of the 0-based field ``index`` of a record (a list field gets its item's name)."""
        if index < len(self.fields):
            return self.fields[index]
        return self.repeat or f"field {index + 1}"

    def label(self, index: int) -> str:
        """``"Y (field 3)"`` for messages; ``"field 9"`` when the field has no name."""
        name = self.field_name(index)
        return name if name == f"field {index + 1}" else f"{name} (field {index + 1})"


PARAMETER_FIELDS = (
    "TIME",
    "TMAX",
    "TREST",
    "DTMIN",
    "DTMAX",
    "INCR",
    "INCMAX",
    "IREST",
    "NINTPL",
    "ISTAT",
    "ITRAC",
)
MATID_FIELDS = ("MID", "TYPE", "MASS", "SCALE", "KX", "KY", "KZ", "C")
PDMP_FIELDS = ("NODLIM", "RZERO", "PRHO", "PPOI", "E0", "E1", "T1", "PCOF", "VX0", "VY0", "VZ0")

CARDS: tuple[CardSpec, ...] = (
    CardSpec("TITLE", "TITL", ("TEXT",)),
    CardSpec("PARAMETERS", "PARA", PARAMETER_FIELDS),
    CardSpec("MATID", "MATI", MATID_FIELDS, "EXTRA"),
    CardSpec("PDMP", "PDMP", PDMP_FIELDS, "E2 T2 ..."),
    CardSpec("BODY", "BODY", ("AX", "AY", "AZ")),
    CardSpec("TRACE", "TRAC", (), "NODE"),
    CardSpec("NODE COORDINATES", "NODE", ("ID", "X", "Y", "Z")),
    CardSpec("ELEMENTS", "ELEM", ("ID", "MID", "NODE1", "NODE2")),
    CardSpec("MASS", "MASS", ("NODE", "MASS", "IXX", "IYY", "IZZ")),
    CardSpec("RBEL", "RBEL", ("MASTER", "DOFS", "COUNT"), "SLAVE"),
    CardSpec("BOUNDARY CONDITIONS", "BOUN", ("FIRST", "LAST", "INC"), "DOF"),
    CardSpec("CONTACT", "CONT", ("SET", "N1", "N2", "N3")),
    CardSpec("INITIAL", "INIT", ("NODE", "VX", "VY", "VZ", "WX", "WY", "WZ")),
    CardSpec("USRFRC", "USRF", ("SPEC",)),
    CardSpec("HOOKE", "HOOK", ("NODLIM", "KN", "E")),
    CardSpec("WALLMAT", "WALL", ("SET", "E", "NU", "MU")),
    CardSpec("FRICTION", "FRIC", ("NODLIM", "LAW", "MUS", "MUK", "ROLL", "MUR")),
    CardSpec("UNITS", "UNIT", ("LENGTH", "FORCE", "TIME")),
) + tuple(CardSpec(s.card, s.key, s.fields) for s in SHAPES)  # CYLINDER, CAPSULE ...
# our text cards (x3dpd.deck.text_cards: MODAL, PLATES, TEMPERATURE ...)
CARDS += tuple(CardSpec(c.name, c.key, ("RECORD",)) for c in TEXT_CARDS)
# the effect units' own cards (x3dpd.physics.effect_units)
CARDS += tuple(CardSpec(u.card.name, u.card.key, u.card.fields) for u in UNITS if u.card)
if len({c.key for c in CARDS}) != len(CARDS):
    raise ValueError(f"two cards share their four letters: {sorted(c.key for c in CARDS)}")

#: Card spec by canonical name.
BY_NAME: dict[str, CardSpec] = {c.name: c for c in CARDS}
#: Card spec by four-letter key (upper case).
BY_KEY: dict[str, CardSpec] = {c.key: c for c in CARDS}
#: Fields of a CONTACT slave record (its second block).
CONTACT_SLAVES = CardSpec("CONTACT", "CONT", ("SET",), "SLAVE")
#: Cards that may appear at most once.
SINGLE_CARDS = ("TITLE", "PARAMETERS", "BODY", "TRACE", "UNITS") + tuple(c.name for c in TEXT_CARDS)
#: The four letters of the cards whose records are text lines, read to the card's END.
TEXT_KEYS = ("TITL", "USRF", "UNIT", "FRIC") + tuple(c.key for c in TEXT_CARDS)


def card_for_word(word: str) -> CardSpec | None:
    """The card a keyword names (X3D reads its first four letters), or None."""
    return BY_KEY.get(word[:4].upper()) if len(word) >= 4 else None
