"""What every step of the model builder shares: deck errors and node lookups.

:class:`BuilderBase` holds the deck and turns a problem into a :class:`DeckError` at the
offending record; the step mixins (``build_particles``, ``build_structure``, ``build_walls``,
``build_loads``) and :func:`x3dpd.model.build.build_model` build on it. Also the small array
helpers they use.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from x3dpd.errors import DeckError, Pos

if TYPE_CHECKING:  # the builder reads cards by attribute; it needs no runtime import of them
    from x3dpd.deck.cards import Deck

_AXES = "xyz"
_ALL_DOFS = (1, 2, 3, 4, 5, 6)


class BuilderBase:
    """One build: holds the deck and the lookup tables the checks share."""

    def __init__(self, deck: Deck, usrfrc: tuple[str, ...], motion: tuple[str, ...]):
        self.deck = deck
        self.usrfrc = usrfrc
        self.motion = motion

    # -- errors -------------------------------------------------------------------------------

    def error(self, message: str, pos: Pos, card: str) -> DeckError:
        return DeckError(message, self.deck.path, pos.line, pos.column, card)

    def node(self, nid: int, pos: Pos, card: str, what: str = "node") -> int:
        """Index of node ``nid``; DeckError when it is not defined."""
        i = self.index.get(nid)
        if i is None:
            raise self.error(f"{what} {nid} is not defined in NODE COORDINATES", pos, card)
        return i

    def structural(self, nid: int, pos: Pos, card: str, what: str) -> int:
        """Index of a node that must not be a particle (report Appendix B, PDMP note 1)."""
        i = self.node(nid, pos, card, what)
        if i >= self.pstart:
            raise self.error(
                f"{what} {nid} is a particle node (PDMP NODLIM {self.nodlim}: nodes above it are "
                f"particles, which must not be connected to elements, masses or rigid links)",
                pos,
                card,
            )
        return i


def _pos_at(positions: Sequence[Pos], k: int, fallback: Pos) -> Pos:
    return positions[k] if k < len(positions) else fallback


def _ro(a, dtype=np.float64) -> np.ndarray:
    """C-contiguous read-only copy (the model's arrays must not be modified)."""
    out = np.array(a, dtype=dtype, order="C", copy=True)
    out.flags.writeable = False
    return out
