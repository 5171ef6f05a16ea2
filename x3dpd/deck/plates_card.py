"""The PLATES card (our extension): drilled plates of a multiple individual particle (MIP)
damper, one sphere per hole (report Section 11.2, Figures 66-68).

A text card, one record per plate, each a list of ``key=value`` words (docs/deck-reference.md,
"PLATES")::

    PLATES
      set=1 master=1 holes=221 pitch=0.6 hole=0.504 thickness=0.501 shim=0.009 size=10 end=0.05
      set=2 master=1 holes=221 pitch=0.6 hole=0.504 thickness=0.5015 shim=0.009 size=10 end=0.05
    END

This module turns the card's lines into :class:`Plate` records with the position of every
key, and checks what one record can say on its own (a known key, a number where one belongs,
a word from its list). The plates are built into the deck's cards -- the holes' HOLES walls,
their nodes, the spheres -- by :func:`x3dpd.deck.plates.expand_plates`, which checks the rest
(a hole larger than the plate, a free length that is not positive) against the deck.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from x3dpd.deck.text_card import TextCard
from x3dpd.errors import NOWHERE, DeckError, Pos

CARD = "PLATES"
#: Every key, what it takes, and whether a record needs it (docs/deck-reference.md).
KEYS = {
    "set": ("the CONTACT set id of the plate's holes (its HOLES wall, its WALLMAT record)", True),
    "master": ("the structural node the plate rides on (its nodes become RBEL slaves of it)", True),
    "holes": ("how many holes, one sphere in each", True),
    "pitch": ("the holes' spacing on the square grid [length]", True),
    "hole": ("the holes' diameter [length]", True),
    "thickness": ("the plate's (measured) thickness [length]", True),
    "size": ("the plate's width, or WIDTH1,WIDTH2 along the grid's two axes [length]", True),
    "shim": ("the shim between the plate and its end plate [length]; default 0", False),
    "end": ("the end plates' thickness [length], between stacked plates; default 0", False),
    "axis": ("x, y or z (or 1, 2, 3): the holes' axis; default the USRFRC drive's", False),
    "cols": ("holes per row of the grid; default ceil(sqrt(holes))", False),
    "at": ("X,Y,Z of the plate's centre at its holes' bottom; default stacked", False),
    "start": ("bottom, middle, top or random: where each sphere starts; default bottom", False),
    "seed": ("the seed of start=random; default 0", False),
    "lumped": ("yes: one hole stands for the plate's alike holes; default no", False),
}
STARTS = ("bottom", "middle", "top", "random")
AXES = {"x": 1, "y": 2, "z": 3, "1": 1, "2": 2, "3": 3}
_NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eEdD][+-]?\d+)?$")


@dataclass(frozen=True)
class Plate:
    """One PLATES record: a drilled plate (module docstring; lengths in the deck's units).

    ``keys`` holds where each key given stands (for messages), ``pos`` the record's start."""

    set_id: int
    master: int
    holes: int
    pitch: float
    hole: float
    thickness: float
    size: tuple[float, float]
    shim: float = 0.0
    end: float = 0.0
    axis: int | None = None
    cols: int | None = None
    at: tuple[float, float, float] | None = None
    start: str = "bottom"
    seed: int = 0
    lumped: bool = False
    pos: Pos = NOWHERE
    keys: tuple[tuple[str, Pos], ...] = ()

    def where(self, key: str) -> Pos:
        """The position of ``key`` in the record (the record's start when not given)."""
        return dict(self.keys).get(key, self.pos)

    @property
    def length(self) -> float:
        """The holes' length: the plate's thickness plus its shim [length]."""
        return self.thickness + self.shim

    def record(self) -> str:
        """The record as a PLATES line (the writer's)."""
        words = [
            f"set={self.set_id}",
            f"master={self.master}",
            f"holes={self.holes}",
            f"pitch={self.pitch!r}",
            f"hole={self.hole!r}",
            f"thickness={self.thickness!r}",
            f"shim={self.shim!r}",
            "size="
            + ",".join(map(repr, self.size[:1] if self.size[0] == self.size[1] else self.size)),
        ]
        if self.end:
            words.append(f"end={self.end!r}")
        if self.axis is not None:
            words.append(f"axis={'xyz'[self.axis - 1]}")
        if self.cols is not None:
            words.append(f"cols={self.cols}")
        if self.at is not None:
            words.append("at=" + ",".join(map(repr, self.at)))
        if self.start != "bottom":
            words.append(f"start={self.start}")
        if self.seed:
            words.append(f"seed={self.seed}")
        if self.lumped:
            words.append("lumped=yes")
        return " ".join(words)


def parse_plates(lines: list[tuple[str, int, int]]) -> tuple[Plate, ...]:
    """The card's records from its lines ``(text, line, column)``; a DeckError at the word."""
    return tuple(_record(text, line, col) for text, line, col in lines)


def _record(text: str, line: int, col: int) -> Plate:
    values: dict = {}
    keys: list[tuple[str, Pos]] = []
    for m in re.finditer(r"[^\s]+", text):
        word, at = m.group(), Pos(line, col + m.start())
        key, eq, value = word.partition("=")
        key = key.lower()
        if not eq or key not in KEYS:
            raise _error(at, f"expected key=value with a key of {', '.join(KEYS)}; got {word!r}")
        if key in values:
            raise _error(at, f"{key} is given twice")
        values[key] = _value(key, value, at)
        keys.append((key, at))
    start = Pos(line, col + len(text) - len(text.lstrip()))
    missing = [k for k, (_, needed) in KEYS.items() if needed and k not in values]
    if missing:
        raise _error(
            start,
            f"missing {', '.join(missing)} (needs: "
            + ", ".join(k for k, (_, n) in KEYS.items() if n)
            + ")",
        )
    size = values.pop("size")
    values["size"] = (size[0], size[-1])
    values["set_id"] = values.pop("set")
    return Plate(**values, pos=start, keys=tuple(keys))


def _value(key: str, text: str, at: Pos):
    if key in ("start", "lumped", "axis"):
        word = text.lower()
        allowed = {"start": STARTS, "lumped": ("yes", "no"), "axis": tuple(AXES)}[key]
        if word not in allowed:
            raise _error(at, f"{key} must be one of {', '.join(allowed)}; got {text!r}")
        return AXES[word] if key == "axis" else (word == "yes" if key == "lumped" else word)
    parts = text.split(",")
    counts = {"at": (3,), "size": (1, 2)}.get(key, (1,))
    if len(parts) not in counts:
        raise _error(at, f"{key} takes {' or '.join(map(str, counts))} number(s); got {text!r}")
    numbers = []
    for part in parts:
        if not _NUMBER.match(part):
            raise _error(at, f"{key} must be a number; got {part!r}")
        v = float(part.replace("d", "e").replace("D", "e"))
        if not math.isfinite(v):
            raise _error(at, f"{key} must be finite; got {part!r}")
        numbers.append(v)
    if key in ("set", "master", "holes", "cols", "seed"):
        v = numbers[0]
        if v != int(v) or (key != "seed" and v < 1) or v < 0:
            raise _error(
                at, f"{key} must be a{' positive' if key != 'seed' else ''} integer; got {text!r}"
            )
        return int(v)
    if key in ("pitch", "hole", "thickness", "size") and min(numbers) <= 0.0:
        raise _error(at, f"{key} must be > 0; got {text!r}")
    if key == "end" and numbers[0] < 0.0:
        raise _error(at, f"end must be >= 0; got {text!r}")
    return tuple(numbers) if key in ("at", "size") else numbers[0]


def _error(at: Pos, message: str) -> DeckError:
    return DeckError(message, "<deck>", at.line, at.column, CARD)


def _parse_card(keyword_pos: Pos, lines: list[tuple[str, int, int]]) -> tuple[Plate, ...]:
    """The card's plates from its lines (each record names its own position)."""
    return parse_plates(lines)


def _card_lines(plates: tuple[Plate, ...]) -> list[str]:
    """The card's records as the writer prints them."""
    return [p.record() for p in plates]


#: The card's registration with the deck reader and writer (x3dpd.deck.text_cards); a deck
#: read from a file has its plates built into its cards (x3dpd.deck.plates) and none left.
TEXT_CARD = TextCard(CARD, "plates", parse=_parse_card, lines=_card_lines, written=bool)
