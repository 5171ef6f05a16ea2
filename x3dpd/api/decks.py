"""Decks for the tools above the API (the CLI, design, study): read, fill, write, build.

Re-exports, so that a tool imports ``x3dpd.api`` and never the layers below it
(tests/meta/test_layering.py; docs/architecture.md):

* :func:`read_deck` -- a deck file into typed cards (:class:`Deck`); a bad token raises
  :class:`~x3dpd.errors.DeckError` ``FILE:LINE:COL: CARD: message`` (docs/deck-reference.md);
* :func:`format_deck` / :func:`write_deck` -- the cards back to X3D deck text / a file;
* :class:`Deck`, :class:`Node` -- the deck and its NODE COORDINATES card's rows;
  :class:`WallMat` -- a WALLMAT record (a cavity's wall material, x3dpd.study's ``--walls``);
* :func:`fill_positions`, :func:`filled_deck`, :data:`PACKINGS` -- particles packed into a
  deck's cavity (``x3dpd fill``, docs/fill.md);
* :func:`build_model` -- the arrays the solver runs (:func:`x3dpd.api.build` also takes a path).
"""

from __future__ import annotations

from x3dpd.deck import format_deck, read_deck
from x3dpd.deck.cards import Deck, Node, WallMat
from x3dpd.deck.fill import fill_positions, filled_deck
from x3dpd.deck.writer import write_deck
from x3dpd.geometry.packing import PACKINGS
from x3dpd.model.build import build_model

__all__ = ["PACKINGS", "Deck", "Node", "WallMat", "build_model", "fill_positions",
           "filled_deck", "format_deck", "read_deck", "write_deck"]
