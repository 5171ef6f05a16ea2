"""The registry of our text cards: what a text card provides (x3dpd.deck.text_card), and the cards.

The deck reader and writer read this registry for every text card of our own: the grammar
(x3dpd.deck.parser.grammar: one keyword and one alternative of the rule ``text_card``), the
field table and the cards that may appear once (x3dpd.deck.fields), the reader's early gate
(its lines are text to the card's END), the transformer (its ``parse``, then its ``resolve``
once the UNITS card is known) and the writer (the keyword, its ``header``, its ``lines``, END;
in registry order, after UNITS).

Adding a text card
------------------
Write its records' parser and printer in ``x3dpd/deck/<name>_card.py`` with ``TEXT_CARD =
TextCard(...)``, add the module to :data:`TEXT_CARDS` below and the field to
x3dpd.deck.cards.Deck: three files of ``deck/``. What the card does to the model is the
model builder's (MODAL: x3dpd.model.build_modal; TEMPERATURE: x3dpd.model.temperature).
"""

from __future__ import annotations

import dataclasses

from x3dpd.deck import modal_card, plates_card, temperature_card
from x3dpd.deck.text_card import TextCard

__all__ = ["TEXT_CARDS", "BY_TEXT_TERMINAL", "TextCard"]


def _register(*modules) -> tuple[TextCard, ...]:
    """The text cards of ``modules`` (each defines ``TEXT_CARD``), checked, in the given order."""
    out = []
    for m in modules:
        card = dataclasses.replace(m.TEXT_CARD, module=m.__name__)
        if not card.name.replace(" ", "").isalpha() or len(card.name) < 4:
            raise ValueError(f"{m.__name__}: a text card's keyword is a word of 4 letters or more")
        out.append(card)
    for key in ("key", "field"):
        values = [getattr(c, key) for c in out]
        if len(set(values)) != len(values):
            raise ValueError(f"two text cards share a {key}: {values}")
    return tuple(out)


#: The text cards, in the order the writer prints them.
TEXT_CARDS: tuple[TextCard, ...] = _register(temperature_card, modal_card, plates_card)
#: Text card by the grammar's terminal of its keyword.
BY_TEXT_TERMINAL = {c.terminal: c for c in TEXT_CARDS}
