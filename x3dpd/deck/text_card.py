"""What a text card of our own declares about itself: the interface of x3dpd.deck.text_cards.

A *text card* is one of our extension cards whose records are lines of words rather than of
numbers -- keyword records (MODAL, TEMPERATURE) or key=value records (PLATES) -- read and
written by its own module of ``x3dpd/deck/``. Its :class:`TextCard` says what the deck's shared
code needs: the keyword, the :class:`x3dpd.deck.cards.Deck` field it fills, how its lines are
parsed and printed back, and (optionally) how its values are resolved once the whole deck is
read (TEMPERATURE's bare numbers are on the UNITS card's scale). The grammar's rule and
keyword, the field table (x3dpd.deck.fields), the reader's early gate (a text card's lines are
text, read to its END), the transformer and the writer take every text card from its
registration (x3dpd.deck.text_cards); a card of this kind needs no code of theirs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable


def _given(value: Any) -> bool:
    return value is not None


@dataclass(frozen=True)
class TextCard:
    """One text card of our own (module docstring)."""

    name: str  # the keyword as the writer prints it ("TEMPERATURE")
    field: str  # the Deck field its value fills (at most one card per deck)
    #: (keyword position, [(text, line, column)] of its records) -> the card's value; raises
    #: DeckError at the word at fault
    parse: Callable
    #: the card's value -> its record lines as the writer prints them (each read back the same)
    lines: Callable
    #: the writer's comment line after the keyword ("" none)
    header: str = ""
    #: (value, the deck's UNITS card or None) -> the value once the whole deck is read
    resolve: Callable | None = None
    #: whether the writer prints the card for this value (None: not given)
    written: Callable = _given
    module: str = ""  # the defining module (set by the registry)

    @property
    def key(self) -> str:
        """The four letters X3D reads of a keyword."""
        return self.name[:4].upper()

    @property
    def terminal(self) -> str:
        """The grammar's terminal of the keyword."""
        return self.name.upper()
