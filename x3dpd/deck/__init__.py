"""The X3D deck language: grammar, typed cards, reader and writer.

``read_deck(path)`` / ``parse_deck(text)`` turn a deck into a :class:`Deck` of typed cards (or
raise one :class:`~x3dpd.errors.DeckError` ``FILE:LINE:COL: CARD: message``);
``format_deck(deck)`` / ``write_deck(deck, path)`` write one back as normalized text that parses
to equal cards. ``docs/deck-reference.md`` documents every card and field.
"""

from x3dpd.deck.cards import (
    Body,
    Boundary,
    Contact,
    AnalyticWall,
    Deck,
    Hooke,
    Element,
    Initial,
    Mass,
    Material,
    Node,
    Parameters,
    Pdmp,
    Pos,
    Rbel,
    SlaveSet,
    Title,
    Trace,
    Triangle,
    Usrfrc,
    WallMat,
)
from x3dpd.deck.parser import parse_deck, read_deck
from x3dpd.deck.writer import format_deck, write_deck

__all__ = [
    "AnalyticWall",
    "Body",
    "Boundary",
    "Contact",
    "Deck",
    "Element",
    "Hooke",
    "Initial",
    "Mass",
    "Material",
    "Node",
    "Parameters",
    "Pdmp",
    "Pos",
    "Rbel",
    "SlaveSet",
    "Title",
    "Trace",
    "Triangle",
    "Usrfrc",
    "WallMat",
    "format_deck",
    "parse_deck",
    "read_deck",
    "write_deck",
]
