"""Decks for the tools above the API (the CLI, design, study): read, fill, write, build.

Re-exports, so that a tool imports ``x3dpd.api`` and never the layers below it
(tests/meta/test_layering.py; docs/architecture.md):

* :func:`read_deck` -- a deck file into typed cards (:class:`Deck`); a bad token raises
  :class:`~x3dpd.errors.DeckError` ``FILE:LINE:COL: CARD: message`` (docs/deck-reference.md);
* :func:`format_deck` / :func:`write_deck` -- the cards back to X3D deck text / a file;
* :class:`Deck` and the cards a tool edits: :class:`Node`, :class:`Mass`, :class:`Title`,
  :class:`Contact`, :class:`Triangle`, :class:`Element`;
  :class:`WallMat` -- a WALLMAT record (a cavity's wall material, x3dpd.study's ``--walls``);
* :func:`fill_positions`, :func:`filled_deck`, :func:`with_material`, :data:`PACKINGS` --
  particles packed into a deck's cavity (``x3dpd fill``, docs/fill.md);
  :func:`cavity_triangles`, :func:`cavity_box` -- a cavity's triangles and, for a box, its
  corners; :data:`BY_SHAPE_NAME` -- the analytic wall shapes (CYLINDER, CAPSULE) and their
  inscribed meshes;
* :func:`plated_deck`, :func:`plates_from_specs`, :func:`expand_plates`, :func:`sphere_ids` --
  a multiple individual particle damper's drilled plates, one sphere per hole (PLATES card,
  x3dpd.deck.plates; ``x3dpd fill --plates``, a design's [mip]);
* :func:`with_cavities`, :func:`default_spacing`, :func:`cavity_set`,
  :func:`check_masters` -- several identical cavities on a structure (x3dpd.deck.cavities,
  docs/design.md);
* :func:`is_user_file` -- whether a USRFRC spec names a Python file (code the deck runs);
* :func:`build_model` -- the arrays the solver runs (:func:`x3dpd.api.build` also takes a path);
* :func:`with_temperature` -- a deck at another operating temperature (its TEMPERATURE card's
  OPERATING replaced: ``--temperature``, a design's ``temperature``).
"""

from __future__ import annotations

from x3dpd.deck import format_deck, read_deck
from x3dpd.deck.cards import Contact, Deck, Element, Mass, Node, Title, Triangle, WallMat
from x3dpd.deck.cavities import cavity_set, check_masters, default_spacing, with_cavities
from x3dpd.deck.fill import (
    cavity_box,
    cavity_triangles,
    fill_positions,
    filled_deck,
    with_material,
)
from x3dpd.deck.plates import expand_plates, plated_deck, plates_from_specs, sphere_ids
from x3dpd.deck.plates_card import STARTS, Plate
from x3dpd.deck.temperature_card import with_temperature
from x3dpd.deck.writer import write_deck
from x3dpd.geometry.packing import PACKINGS
from x3dpd.geometry.shapes import BY_SHAPE_NAME
from x3dpd.model.build import build_model
from x3dpd.physics.usrfrc import is_user_file

__all__ = [
    "BY_SHAPE_NAME",
    "PACKINGS",
    "STARTS",
    "Plate",
    "Contact",
    "Deck",
    "Element",
    "Mass",
    "Node",
    "Title",
    "Triangle",
    "WallMat",
    "build_model",
    "cavity_box",
    "cavity_set",
    "cavity_triangles",
    "check_masters",
    "default_spacing",
    "expand_plates",
    "fill_positions",
    "filled_deck",
    "format_deck",
    "is_user_file",
    "plated_deck",
    "plates_from_specs",
    "read_deck",
    "sphere_ids",
    "with_cavities",
    "with_material",
    "with_temperature",
    "write_deck",
]
