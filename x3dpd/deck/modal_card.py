"""The MODAL card (our extension): a linear structure given by its modes.

A text card whose records start with a keyword (docs/deck-reference.md, "MODAL")::

    MODAL
      MODE  1  37.74  0.0032          $ MODE  K  FREQ  ZETA  [MASS]
      MODE  2  236.5  0.0050
      SHAPE 9  1   70.48  -70.48      $ SHAPE NODE DOF  PHI_1 ... PHI_M  (one per MODE, in order)
      FILE  beam.uff  modes=1:3  zeta=0.005  map=101:9      $ or the modes from a file
      HOUSING added                   $ added (default) | included
    END

This module turns the card's lines into typed records (:class:`Modal`) with the position of
every value, and checks what one record can say on its own (numbers, DOF codes, option names).
The modes themselves -- mode files read, node ids mapped, the deck's mass coupled in -- are
the model builder's (x3dpd.model.build_modal); the files are read by
:func:`x3dpd.deck.parser.read_deck` (x3dpd.deck.mode_files), so that a deck that reads is a
deck whose files read.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from math import isfinite
from typing import Any

from x3dpd.deck.text_card import TextCard
from x3dpd.errors import NOWHERE, DeckError, Pos
from x3dpd.units import parse_units

CARD = "MODAL"
#: Options of a FILE record, with what each takes (for messages and the docs).
FILE_OPTIONS = {
    "format": "op2 | uff | csv | npz (default: from the file's suffix)",
    "modes": "mode numbers to keep: 1:3, 1,2,5 or 1:3,7",
    "band": "frequency band to keep, LO:HI (cycles per time unit)",
    "zeta": "damping ratio of every kept mode, or one per kept mode (comma-separated)",
    "map": "file node id to deck node id pairs, FILE:DECK[,FILE:DECK ...]",
    "units": "the file's units LENGTH,FORCE,TIME (e.g. m,N,s) when the file does not say",
    "normalize": "mass: rescale shapes by 1/sqrt(modal mass) when the file gives modal masses",
}
HOUSINGS = ("added", "included")
_NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eEdD][+-]?\d+)?$")


@dataclass(frozen=True)
class ModalMode:
    """MODE K FREQ ZETA [MASS]: mode ``number``, natural frequency ``freq`` [cycles per time
    unit], damping ratio ``zeta`` and generalized mass ``mass`` (1 when mass-normalised;
    None: not given, taken as 1)."""

    number: int
    freq: float
    zeta: float
    mass: float | None
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class ModalShape:
    """SHAPE NODE DOF PHI...: the shape values of deck node ``node``, DOF ``dof`` (1-6), one
    per MODE record in their order [1/sqrt(mass), rotations 1/(sqrt(mass) length)]."""

    node: int
    dof: int
    values: tuple[float, ...]
    pos: Pos = NOWHERE
    value_pos: tuple[Pos, ...] = ()
    node_pos: Pos = NOWHERE


@dataclass(frozen=True)
class ModalFile:
    """FILE PATH [OPTION=VALUE ...]: the modes of a mode file (x3dpd.deck.modes).
    ``options`` holds (name, value, position of the value), the value parsed (modes: a tuple
    of mode numbers; band: (lo, hi); zeta: a tuple; map: {file node: deck node}; units:
    (length, force, time); format, normalize: lower-case words); ``mode_set`` is the ModeSet
    read from the file (set by read_deck; None before)."""

    path: str
    options: tuple[tuple[str, Any, Pos], ...] = ()
    pos: Pos = NOWHERE
    mode_set: Any = field(default=None, compare=False, repr=False)

    def option(self, name: str) -> tuple[Any, Pos] | None:
        for key, value, pos in self.options:
            if key == name:
                return value, pos
        return None


@dataclass(frozen=True)
class Modal:
    """The MODAL card: inline modes and shapes, or mode files, and the housing option."""

    modes: tuple[ModalMode, ...] = ()
    shapes: tuple[ModalShape, ...] = ()
    files: tuple[ModalFile, ...] = ()
    housing: str = "added"
    housing_pos: Pos = NOWHERE
    pos: Pos = NOWHERE
    lines: tuple[str, ...] = ()  # the records as written (the writer prints them back)


def _err(message: str, pos: Pos) -> DeckError:
    return DeckError(message, "<deck>", pos.line, pos.column, CARD)


def _words(text: str, line: int, column: int, commas: bool) -> list[tuple[str, Pos]]:
    """Words of a line with their positions: separated by blanks and commas, or (``commas``
    False: a FILE record, whose option values hold commas) by blanks only."""
    return [
        (m.group(0), Pos(line, column + m.start()))
        for m in re.finditer(r"[^ \t,]+" if commas else r"[^ \t]+", text)
    ]


def _number(word: str, pos: Pos, what: str) -> float:
    if not _NUMBER.match(word):
        raise _err(f"{what}: expected a number, got {word!r}", pos)
    value = float(word.replace("d", "e").replace("D", "e"))
    if not isfinite(value):
        raise _err(f"{what}: expected a finite number, got {word!r}", pos)
    return value


def _integer(word: str, pos: Pos, what: str, low: int = 1) -> int:
    value = _number(word, pos, what)
    if value != int(value) or value < low:
        raise _err(f"{what}: expected an integer >= {low}, got {word!r}", pos)
    return int(value)


# Over 80 lines: the MODAL card's records read in one pass, each with its own error message.
def parse_modal(keyword_pos: Pos, lines: list[tuple[str, int, int]]) -> Modal:
    """The MODAL card from its text lines ``(text, line, column)``."""
    modes: list[ModalMode] = []
    shapes: list[ModalShape] = []
    files: list[ModalFile] = []
    housing, housing_pos = "added", NOWHERE
    kept: list[str] = []
    for text, line, column in lines:
        words = _words(text, line, column, True)
        if not words:
            continue
        if words[0][0].upper() == "FILE":
            words = _words(text, line, column, False)
        kept.append(text.strip())
        key, kpos = words[0][0].upper(), words[0][1]
        rest = words[1:]
        if key == "MODE":
            if len(rest) not in (3, 4):
                raise _err(f"MODE takes 3 or 4 values, K FREQ ZETA [MASS]; got {len(rest)}", kpos)
            number = _integer(*rest[0], "MODE K (mode number)")
            freq = _number(*rest[1], "MODE FREQ (natural frequency)")
            zeta = _number(*rest[2], "MODE ZETA (damping ratio)")
            if freq < 0.0:
                raise _err(f"MODE FREQ must be >= 0; got {rest[1][0]}", rest[1][1])
            if zeta < 0.0:
                raise _err(f"MODE ZETA must be >= 0; got {rest[2][0]}", rest[2][1])
            mass = None
            if len(rest) == 4:
                mass = _number(*rest[3], "MODE MASS (generalized mass)")
                if not mass > 0.0:
                    raise _err(f"MODE MASS must be > 0; got {rest[3][0]}", rest[3][1])
            if any(m.number == number for m in modes):
                raise _err(f"mode {number} is given twice", rest[0][1])
            modes.append(ModalMode(number, freq, zeta, mass, kpos))
        elif key == "SHAPE":
            if len(rest) < 3:
                raise _err("SHAPE takes NODE DOF and one value per MODE record", kpos)
            node = _integer(*rest[0], "SHAPE NODE")
            dof = _integer(*rest[1], "SHAPE DOF")
            if dof > 6:
                raise _err(f"SHAPE DOF {dof} is not one of 1..6 (x, y, z, rx, ry, rz)", rest[1][1])
            values = tuple(_number(w, p, "SHAPE value") for w, p in rest[2:])
            shapes.append(
                ModalShape(node, dof, values, kpos, tuple(p for _, p in rest[2:]), rest[0][1])
            )
        elif key == "FILE":
            if not rest:
                raise _err("FILE takes the path of a mode file, then OPTION=VALUE words", kpos)
            path, options = rest[0][0], []
            for word, pos in rest[1:]:
                name, eq, value = word.partition("=")
                name = name.lower()
                if not eq or not value:
                    raise _err(f"FILE option {word!r}: expected OPTION=VALUE", pos)
                if name not in FILE_OPTIONS:
                    raise _err(
                        f"unknown FILE option {name!r}; expected one of {', '.join(FILE_OPTIONS)}",
                        pos,
                    )
                if any(o[0] == name for o in options):
                    raise _err(f"FILE option {name!r} is given twice", pos)
                vpos = Pos(pos.line, pos.column + len(name) + 1)
                options.append((name, _option_value(name, value, vpos), vpos))
            files.append(ModalFile(path, tuple(options), kpos))
        elif key == "HOUSING":
            if len(rest) != 1 or rest[0][0].lower() not in HOUSINGS:
                raise _err(
                    "HOUSING takes one word: added (the deck's mass on modal nodes is "
                    "added to the modes) or included (the modes already contain it)",
                    rest[0][1] if rest else kpos,
                )
            housing, housing_pos = rest[0][0].lower(), kpos
        else:
            raise _err(
                f"unknown MODAL record {words[0][0]!r}; expected MODE, SHAPE, FILE or HOUSING", kpos
            )
    if files and (modes or shapes):
        raise _err(
            "give the modes either as MODE and SHAPE records or from a FILE, not both", files[0].pos
        )
    if len(files) > 1:
        raise _err("one FILE record per MODAL card (one structure)", files[1].pos)
    if not files and not modes:
        raise _err("no modes: give MODE and SHAPE records or a FILE record", keyword_pos)
    for s in shapes:
        if len(s.values) != len(modes):
            raise _err(
                f"SHAPE of node {s.node} DOF {s.dof} has {len(s.values)} values; expected "
                f"one per MODE record ({len(modes)})",
                s.value_pos[0] if s.value_pos else s.pos,
            )
    seen: dict[tuple[int, int], Pos] = {}
    for s in shapes:
        if (s.node, s.dof) in seen:
            raise _err(
                f"node {s.node} DOF {s.dof} has shape values twice (first at line "
                f"{seen[(s.node, s.dof)].line})",
                s.pos,
            )
        seen[(s.node, s.dof)] = s.pos
    if modes and not shapes:
        raise _err("MODE records without SHAPE records: no node moves", modes[0].pos)
    return Modal(
        tuple(modes), tuple(shapes), tuple(files), housing, housing_pos, keyword_pos, tuple(kept)
    )


def _option_value(name: str, value: str, vpos: Pos) -> Any:
    """A FILE option's value, parsed and checked (its meaning is applied by the model)."""
    if name == "format":
        if value.lower() not in ("op2", "uff", "unv", "csv", "npz"):
            raise _err(f"FILE format {value!r}: expected op2, uff, csv or npz", vpos)
        return value.lower()
    if name == "modes":
        return mode_numbers(value, vpos)
    if name == "band":
        return band(value, vpos)
    if name == "zeta":
        out = []
        for part in value.split(","):
            z = _number(part, vpos, "FILE zeta")
            if z < 0.0:
                raise _err(f"FILE zeta must be >= 0; got {part}", vpos)
            out.append(z)
        return tuple(out)
    if name == "map":
        return node_map(value, vpos)
    if name == "units":
        try:
            return parse_units(value.replace(",", " ").split())
        except ValueError as exc:
            raise _err(f"FILE units: {exc}", vpos) from None
    if value.lower() != "mass":  # normalize
        raise _err(f"FILE normalize {value!r}: the only choice is 'mass'", vpos)
    return "mass"


def mode_numbers(value: str, pos: Pos) -> tuple[int, ...]:
    """``1:3,7`` -> (1, 2, 3, 7)."""
    out: list[int] = []
    for part in value.split(","):
        lo, colon, hi = part.partition(":")
        a = _integer(lo, pos, "FILE modes")
        b = _integer(hi, pos, "FILE modes") if colon else a
        if b < a:
            raise _err(f"FILE modes {part}: the range is empty", pos)
        out.extend(range(a, b + 1))
    return tuple(out)


def band(value: str, pos: Pos) -> tuple[float, float]:
    """``LO:HI`` -> (lo, hi) with 0 <= lo < hi."""
    lo, colon, hi = value.partition(":")
    if not colon:
        raise _err(f"FILE band {value!r}: expected LO:HI", pos)
    a, b = _number(lo, pos, "FILE band"), _number(hi, pos, "FILE band")
    if not 0.0 <= a < b:
        raise _err(f"FILE band {value}: expected 0 <= LO < HI", pos)
    return a, b


def node_map(value: str, pos: Pos) -> dict[int, int]:
    """``101:9,205:12`` -> {101: 9, 205: 12} (file node id -> deck node id)."""
    out: dict[int, int] = {}
    for part in value.split(","):
        a, colon, b = part.partition(":")
        if not colon:
            raise _err(f"FILE map {part!r}: expected FILE_NODE:DECK_NODE", pos)
        fa, fb = _integer(a, pos, "FILE map"), _integer(b, pos, "FILE map")
        if fa in out:
            raise _err(f"FILE map: file node {fa} is mapped twice", pos)
        out[fa] = fb
    return out


def load_mode_files(deck, base_dir: str):
    """``deck`` with the ModeSet of every MODAL FILE record read (a relative path is taken from
    ``base_dir``, the deck's folder). A file that cannot be read is a DeckError at its record:
    ``FILE:LINE:COL: MODAL: mode file NAME: what is wrong``."""
    import os
    from dataclasses import replace

    modal = deck.modal
    if modal is None or not modal.files:
        return deck
    from x3dpd.deck.modes import read_modes
    from x3dpd.errors import InputError, ModeFileError

    files = []
    for rec in modal.files:
        path = rec.path if os.path.isabs(rec.path) else os.path.join(base_dir, rec.path)
        fmt = rec.option("format")
        try:
            modes = read_modes(path, fmt[0] if fmt else None)
        except ModeFileError as exc:  # the file named once, as the record gives it
            where = f"{rec.path}:{exc.line}" if exc.line else rec.path
            raise DeckError(
                f"mode file {where}: {exc.message}", deck.path, rec.pos.line, rec.pos.column, CARD
            ) from None
        except InputError as exc:
            raise DeckError(
                f"mode file {rec.path}: {exc}", deck.path, rec.pos.line, rec.pos.column, CARD
            ) from None
        files.append(replace(rec, mode_set=modes))
    return replace(deck, modal=replace(modal, files=tuple(files)))


def _card_lines(modal: Modal) -> list[str]:
    """The card's records as written (the writer prints them back)."""
    return list(modal.lines)


#: The card's registration with the deck reader and writer (x3dpd.deck.text_cards).
TEXT_CARD = TextCard(CARD, "modal", parse=parse_modal, lines=_card_lines)
