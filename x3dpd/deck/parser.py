# Over 400 lines: the generated grammar, the block reader and its error messages are one reader.
"""Read an X3D deck: text -> :class:`~x3dpd.deck.cards.Deck`, or one clear :class:`DeckError`.

Three stages:

1. **Lines.** The file is read in blocks of whole lines (bounded memory): a NUL byte, bytes that
   are not UTF-8, a control character or an over-long line stop the read at once (``DECK``
   errors). A cheap line check (:class:`_Gate`) follows the cards; at the first line that cannot
   be part of a deck (garbage outside a card, a non-number inside one) reading stops and the text
   so far is parsed, so 100 MB of garbage is rejected after its first block. The gate only
   decides when to stop reading; every message about the deck's content comes from the grammar.
2. **Grammar.** ``x3d.lark`` (LALR, contextual lexer) with :class:`DeckTransformer` passed to
   the constructor, so cards are built while parsing and no tree is kept.
3. **Errors.** Lark's errors are turned into ``FILE:LINE:COL: CARD: message`` with the open
   card, the field expected and the closest card name (:func:`_syntax_error`).
"""

from __future__ import annotations

import difflib
import io
import os
import re
from collections.abc import Iterator
from dataclasses import replace
from functools import cache
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedEOF, UnexpectedInput

from x3dpd.deck.cards import Deck
from x3dpd.deck.modal_card import load_mode_files
from x3dpd.deck.plates import expand_plates
from x3dpd.deck.fields import (
    BY_KEY,
    BY_NAME,
    CARDS,
    CONTACT_SLAVES,
    TEXT_KEYS,
    CardSpec,
    card_for_word,
)
from x3dpd.deck.records import _split
from x3dpd.deck.text_cards import TEXT_CARDS
from x3dpd.deck.transform import DeckTransformer
from x3dpd.errors import DeckError
from x3dpd.geometry.shapes import SHAPES
from x3dpd.physics.effect_units import UNITS

#: Longest line accepted [bytes]; a longer one is not a deck (a list continues with '&').
MAX_LINE = 1 << 20
#: Bytes read at a time (whole lines are handed on, so a block holds up to this plus one line).
BLOCK = 1 << 20
#: Grammar terminal of each card keyword (the first word of the canonical name) -> card name.
KEYWORD_TERMINALS = {c.name.split()[0]: c.name for c in CARDS}
#: Tokens of a record still being read (a complete record ends with ROW or ROWS).
_PARTIAL_RECORD = ("CROW", "VALUES")
_CARD_LIST = ", ".join(c.name for c in CARDS)

_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f]")
# Possessive quantifiers (Python 3.11): the gate's scans run in linear time on any input.
_NUM = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eEdD][+-]?\d+)?(?![A-Za-z0-9_.])"
_VALUE_LINE = rf"[ \t,]*+(?:{_NUM}[ \t,]*+)*+(?:&[ \t]*+)?"
_VALUE_LINES = re.compile(rf"(?:{_VALUE_LINE}(?:\$[^\n]*+)?\n)*+")
_LAST_VALUE_LINE = re.compile(
    rf"{_VALUE_LINE}(?:(END)(?![A-Za-z0-9_])[ \t]*+)?(?:\$.*+)?\n?", re.IGNORECASE
)
_KEYWORD_LINE = re.compile(
    r"[ \t]*+([A-Za-z]{4})[A-Za-z]*+"
    r"(?:[ \t]++(?!END(?![A-Za-z0-9_]))[A-Za-z]++)*+",
    re.IGNORECASE,
)
_WORD_AT = re.compile(r"[^\s,$&]*")


def grammar() -> str:
    """The deck grammar: ``x3d.lark`` with a keyword for every text card of ours
    (x3dpd.deck.text_cards), every registered analytic wall shape (x3dpd.geometry.shapes) and
    every effect unit's own card (x3dpd.physics.effect_units)."""
    text = (Path(__file__).with_name("x3d.lark")).read_text()
    text = text.replace(
        "%TEXT_CARD_TERMINALS%", " | ".join(c.terminal for c in TEXT_CARDS)
    ).replace(
        "%TEXT_CARD_KEYWORDS%",
        "\n".join(f"{c.terminal}: /{c.key}[A-Za-z]*/i" for c in TEXT_CARDS),
    )
    terminals = [s.card for s in SHAPES]
    keywords = "\n".join(f"{s.card}: /{s.key}/i _MORE" for s in SHAPES)
    cards = [u.card for u in UNITS if u.card is not None]
    unit_terminals = [_terminal(c.name) for c in cards]
    return (
        text.replace("%SHAPE_TERMINALS%", " | ".join(terminals))
        .replace("%SHAPE_KEYWORDS%", keywords)
        .replace("%UNIT_CARD_ALTERNATIVE%", "| unit_card" if cards else "")
        .replace(
            "%UNIT_CARD_RULE%",
            f"unit_card: ({' | '.join(unit_terminals)}) _records" if cards else "",
        )
        .replace(
            "%UNIT_KEYWORDS%",
            "\n".join(f"{t}: /{c.key}/i _MORE" for t, c in zip(unit_terminals, cards)),
        )
    )


def _terminal(card: str) -> str:
    """The grammar's terminal of a unit's card keyword (its first word)."""
    return card.split()[0].upper()


@cache
def _parser() -> Lark:
    return Lark(
        grammar(),
        parser="lalr",
        lexer="contextual",
        transformer=DeckTransformer(),
        maybe_placeholders=False,
    )


# -- stage 1: lines -----------------------------------------------------------------------------


def _checked(text: str, first_line: int, path: str) -> str:
    """Whole lines of deck text with '\n' line ends; control characters are refused."""
    bad = _CONTROL.search(text)
    if bad and bad.group() == "\r":
        text = text.replace("\r\n", "\n")
        bad = _CONTROL.search(text)
    if bad:
        line = first_line + text.count("\n", 0, bad.start())
        col = bad.start() - text.rfind("\n", 0, bad.start())
        what = {"\0": "NUL byte", "\r": "carriage return without newline"}.get(
            bad.group(), f"control character U+{ord(bad.group()):04X}"
        )
        raise DeckError(f"{what}: a deck is plain text (is this a binary file?)", path, line, col)
    return text


def _decode(block: bytes, line: int, path: str) -> str:
    """Whole lines of bytes as checked text (``line``: number of the block's first line)."""
    try:
        text = block.decode("utf-8")
    except UnicodeDecodeError as e:
        _checked(block[: e.start].decode("utf-8"), line, path)  # an earlier fault comes first
        col = e.start - block.rfind(b"\n", 0, e.start)
        raise DeckError(
            f"byte 0x{block[e.start]:02x} is not UTF-8 text: this looks like a binary "
            "file, not a deck",
            path,
            line + block.count(b"\n", 0, e.start),
            col,
        ) from None
    if line == 1:
        text = text.removeprefix("\ufeff")
    return _checked(text, line, path)


def _file_blocks(f: io.BufferedReader, path: str) -> Iterator[str]:
    """The file as checked text blocks of whole lines, read ``BLOCK`` bytes at a time."""
    line, carry = 1, b""
    while data := f.read(BLOCK):
        data = carry + data
        cut = data.rfind(b"\n") + 1
        if cut == 0 and len(data) > MAX_LINE:
            raise DeckError(
                f"line longer than {MAX_LINE} bytes: this is not a deck (long lists "
                "continue on the next line after '&')",
                path,
                line,
                1,
            )
        block, carry = data[:cut], data[cut:]
        if block:
            yield _decode(block, line, path)
            line += block.count(b"\n")
    if carry:
        yield _decode(carry, line, path)


class _Gate:
    """Follows the cards over whole lines; stops at the first line no deck can hold there.

    Only decides when to stop reading early; it may let a bad line through (the grammar then
    finds it) but must not stop at a good one (if it does, the whole file is parsed anyway).
    Runs of value lines are skipped by one regex match, so the gate costs little on big decks.
    """

    def __init__(self) -> None:
        self.text = False  # inside a text card (TITLE, USRFRC, UNITS, FRICTION, MODAL ...)
        self.ends = 0  # ENDs still needed by the open value card (0: between cards)

    def scan(self, text: str) -> int:
        """End offset of the first bad line of ``text`` (whole lines), or -1 if none."""
        pos, n = 0, len(text)
        while pos < n:
            if self.ends:
                pos = _VALUE_LINES.match(text, pos).end()
                if pos >= n:
                    break
            eol = text.find("\n", pos) + 1 or n
            if not self._line(text[pos:eol]):
                return eol
            pos = eol
        return -1

    def _line(self, line: str) -> bool:
        if self.text:
            if line.split("$", 1)[0].strip().upper() == "END":
                self.text = False
            return True
        if self.ends:
            return self._values(line)
        if not line.split("$", 1)[0].strip(" \t\n,"):
            return True
        m = _KEYWORD_LINE.match(line)
        key = m.group(1).upper() if m else ""
        if key not in BY_KEY:
            return False
        if key in TEXT_KEYS:
            self.text = True
            return True
        self.ends = 2 if key == "CONT" else 1
        return self._values(line[m.end() :])

    def _values(self, line: str) -> bool:
        m = _LAST_VALUE_LINE.fullmatch(line)
        if m is None:
            return False
        if m.group(1):
            self.ends -= 1
        return True


def _load(blocks: Iterator[str], path: str) -> Deck:
    """Pass checked text blocks through the gate, then parse (see the module docstring)."""
    gate = _Gate()
    kept: list[str] = []
    for block in blocks:
        end = gate.scan(block)
        if end < 0:
            kept.append(block)
            continue
        kept.append(block[:end])
        head = "".join(kept)
        try:
            _parse(head, path)
        except DeckError as e:
            if e.line <= head.count("\n"):  # a real error, not the end of the truncated text
                raise
        kept.append(block[end:])
        kept.extend(blocks)
        break
    deck = _parse("".join(kept), path)
    if deck == Deck(path):
        raise DeckError(
            f"the deck is empty: expected cards ({_CARD_LIST}), each ending with END", path, 1, 1
        )
    return deck


# -- stage 2: grammar ---------------------------------------------------------------------------


def _parse(text: str, path: str) -> Deck:
    if text and not text.endswith("\n"):
        text += "\n"
    try:
        deck = _parser().parse(text)
    except UnexpectedInput as e:
        raise _syntax_error(e, text, path) from None
    except DeckError as e:  # raised by the transformer without the path
        raise DeckError(e.message, path, e.line, e.column, e.card) from None
    return replace(deck, path=path)


# -- stage 3: errors ----------------------------------------------------------------------------


def _open_card(e: UnexpectedInput) -> tuple[Token | None, list]:
    """The keyword token of the card being parsed at the error, and the stack above it."""
    ip = getattr(e, "interactive_parser", None)
    stack = list(ip.parser_state.value_stack) if ip is not None else []
    for i in range(len(stack) - 1, -1, -1):
        item = stack[i]
        if isinstance(item, Token) and item.type in KEYWORD_TERMINALS:
            return item, stack[i + 1 :]
    return None, []


def _flat(items: list) -> Iterator[Token]:
    """The tokens of parser-stack items (subtrees of inlined rules opened up)."""
    for item in items:
        if isinstance(item, Tree):
            yield from _flat(item.children)
        elif isinstance(item, Token):
            yield item


def _values_so_far(above: list) -> int:
    """How many values of the current record were read before the error."""
    toks: list[Token] = []
    for item in reversed(above):
        part = item.children if isinstance(item, Tree) else [item]  # a Tree: CROW+ so far
        if not all(isinstance(t, Token) and t.type in _PARTIAL_RECORD for t in part):
            break
        toks[:0] = part
    return len(_split([(t.line, t.column, str(t)) for t in toks]))


def _suggest(word: str) -> str:
    """'; did you mean RBEL?' when the word's first four letters are one letter off a card's."""
    close = difflib.get_close_matches(word[:4].upper(), list(BY_KEY), n=1, cutoff=0.75)
    if close:
        return f"; did you mean {BY_KEY[close[0]].name}?"
    return f"; expected one of {_CARD_LIST}"


def _syntax_error(e: UnexpectedInput, text: str, path: str) -> DeckError:
    """One DeckError for a lark error: where, in which card, what was there, what was expected."""
    token = getattr(e, "token", None)
    at_eof = isinstance(e, UnexpectedEOF) or (token is not None and token.type == "$END")
    if at_eof:
        line, col = text.count("\n") + 1, 1
        word = ""
    else:
        line, col = e.line, e.column
        start = e.pos_in_stream if token is None else token.start_pos
        word = _WORD_AT.match(text, start).group() or text[start : start + 1]
    kw, above = _open_card(e)
    shown = repr(word[:40] + ("..." if len(word) > 40 else ""))
    if kw is None:
        if card_for_word(word) is None and word.isalpha() and word.upper() != "END":
            return DeckError(f"unknown card keyword {shown}{_suggest(word)}", path, line, col)
        if word.upper() == "END":
            return DeckError(
                "END with no card open (a card keyword must come first)", path, line, col
            )
        return DeckError(
            f"expected a card keyword at the start of a line ({_CARD_LIST}); got {shown}",
            path,
            line,
            col,
        )
    name = KEYWORD_TERMINALS[kw.type]
    spec: CardSpec = BY_NAME[name]
    ends = [t for t in _flat(above) if t.type == "END"]  # CONTACT: is the first block done?
    if above and isinstance(above[-1], Token) and above[-1].type == "END":
        return DeckError(
            f"END must end its line; got {shown} after it (a card keyword starts a new line)",
            path,
            line,
            col,
            name,
        )
    opened, no_end = f"{name} (opened at line {kw.line})", "has no END"
    if name == "CONTACT":
        no_end = (
            "has no second END (a CONTACT card is: master triangles, END, slave sets, END)"
            if ends
            else "has no END after its master triangles"
        )
        spec = CONTACT_SLAVES if ends else spec
    if at_eof:
        return DeckError(
            f"{opened} {no_end}: the file ends inside it; expected END after its last line",
            path,
            line,
            col,
            name,
        )
    if word.isalpha() and card_for_word(word) is not None:
        return DeckError(
            f"{opened} {no_end} before the next card {word.upper()}; expected END "
            "on a line of its own before it",
            path,
            line,
            col,
            name,
        )
    if word == "&":
        return DeckError("'&' continues a record only at the end of a line", path, line, col, name)
    return DeckError(
        f"{spec.label(_values_so_far(above))} must be a number; got {shown} (or END "
        "to close the card)",
        path,
        line,
        col,
        name,
    )


# -- API ----------------------------------------------------------------------------------------


def parse_deck(text: str, path: str = "<deck>") -> Deck:
    """Parse deck text.

    Parameters
    ----------
    text : str
        The whole deck.
    path : str
        Name used in error messages and stored as ``Deck.path``.

    Returns
    -------
    Deck
        The cards, in file order; each record keeps the position of its first token. A PLATES
        card is built into the deck's cards (x3dpd.deck.plates.expand_plates).

    Raises
    ------
    DeckError
        ``FILE:LINE:COL: CARD: message`` for anything wrong with the text.
    """
    deck = _load(iter([_checked(text.removeprefix("\ufeff"), 1, path)]), path)
    return expand_plates(load_mode_files(deck, os.getcwd()))


def read_deck(path: str | os.PathLike[str]) -> Deck:
    """Read and parse the deck file ``path`` (see :func:`parse_deck`).

    The file is read in blocks of whole lines and rejected at its first line that cannot be part
    of a deck, so a large binary or garbage file fails at once with bounded memory.
    """
    name = os.fspath(path)
    try:
        f = open(name, "rb")  # noqa: SIM115 -- closed by the with below
    except OSError as e:
        raise DeckError(f"cannot read the deck: {e.strerror or e}", name) from None
    with f:
        deck = _load(_file_blocks(f, name), name)
    return expand_plates(load_mode_files(deck, os.path.dirname(os.path.abspath(name))))
