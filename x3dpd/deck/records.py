"""Records of a card body and their fields: the low-level helpers of the deck transformer.

A card's lines are split into records (one line, or several joined by '&') and values; a value
is converted to a number, an id or a DOF, and a bad one raises :class:`~x3dpd.errors.DeckError`
at the field, naming it (field names from ``fields.py``). ``transform.py`` builds the cards with
these.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from math import isfinite
from typing import Any

from lark import Token

from x3dpd.deck.cards import Pos
from x3dpd.deck.fields import CardSpec
from x3dpd.errors import DeckError

_WORD = re.compile(r"[^\s,&]+")
#: A number with a Fortran double-precision exponent (``1.0D0``, ``-2.5d-3``).
_FORTRAN = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)[dD][+-]?\d+")
#: Largest integer a float field may spell as an integer id (2**53: exact in float64).
_EXACT_INT = 2**53

#: One line of a record: its line number, the column of ``text[0]``, and the line's text (values,
#: blanks, maybe '&' and a comment; for a continued record's tokens also trailing blank lines).
Piece = tuple[int, int, str]
#: A record: its lines (one, or several joined by '&').
Record = list[Piece]


def _body(text: str) -> str:
    """The values part of a line (its text before any comment)."""
    cut = text.find("$")
    return text if cut < 0 else text[:cut]


def _records(items: list[Any]) -> Iterator[Record]:
    """The records of a card body: ROWS tokens hold one record per line, ``record`` a list."""
    for item in items:
        if isinstance(item, Token):  # ROWS; blank and comment-only lines are not records
            line, col = item.line, item.column
            for text in item.split("\n"):
                if _body(text).strip(" \t,"):
                    yield [(line, col, text)]
                line, col = line + 1, 1
        else:
            yield item


def _split(record: Record) -> list[str]:
    """The values of a record, as strings."""
    out: list[str] = []
    for _, _, text in record:
        out += _WORD.findall(_body(text))
    return out


def _where(record: Record, index: int) -> tuple[int, int]:
    """Line and column of value ``index`` of a record (just after its last value if fewer)."""
    k = 0
    line = col = 0
    for ln, c, text in record:
        for m in _WORD.finditer(_body(text)):
            if k == index:
                return ln, c + m.start()
            line, col, k = ln, c + m.end(), k + 1
    return line, col


def _positions(record: Record, start: int) -> tuple[Pos, ...]:
    """One Pos per value of a record, from value ``start`` on."""
    out = []
    for line, col, text in record:
        out.extend(Pos(line, col + m.start()) for m in _WORD.finditer(_body(text)))
    return tuple(out[start:])


def _first(record: Record) -> Pos:
    """Position of a record's first value."""
    line, col, text = record[0]
    return Pos(line, col + len(text) - len(text.lstrip(" \t,")))


def _pos(tok: Token) -> Pos:
    return Pos(tok.line, tok.column)


def _fail(spec: CardSpec, record: Record, index: int, message: str) -> DeckError:
    line, col = _where(record, index)
    return DeckError(message, "<deck>", line, col, spec.name)


def to_float(text: str) -> float:
    """A Fortran-style number (``1.0D0`` has a double-precision exponent) as a float. Raises
    ValueError naming ``text`` as written when it is not a number (a word such as ``mindlin``
    is not rewritten: only a number's exponent letter D is read as E)."""
    try:
        return float(text)
    except ValueError:
        if not _FORTRAN.fullmatch(text.strip()):
            raise ValueError(f"not a number: {text!r}") from None
        return float(text.replace("d", "e").replace("D", "e"))


def _number(spec: CardSpec, record: Record, values: list[str], i: int, what: str) -> float:
    """Field ``i`` as a float; a word that is no number is a DeckError naming the field."""
    try:
        return to_float(values[i])
    except ValueError:
        raise _fail(spec, record, i, f"{spec.label(i)} must be {what}; got {values[i]!r}") from None


def _floats(spec: CardSpec, record: Record, values: list[str], start: int = 0) -> list[float]:
    """Fields ``start``... as floats; a word that is no number, or a number beyond float64's
    range (1e400), is refused."""
    out = [_number(spec, record, values, i, "a number") for i in range(start, len(values))]
    if not all(map(isfinite, out)):
        i = start + next(k for k, x in enumerate(out) if not isfinite(x))
        raise _fail(
            spec,
            record,
            i,
            f"{spec.label(i)} is beyond the range of a double (|x| < 1.8e308); got {values[i]}",
        )
    return out


def _int(spec: CardSpec, record: Record, values: list[str], i: int, least: int | None = 1) -> int:
    """Field ``i`` as an integer (``25.`` and ``1.e3`` are accepted; 2.5 is not)."""
    text = values[i]
    try:
        value = int(text)
    except ValueError:
        x = _number(spec, record, values, i, "an integer")
        if not (x.is_integer() and abs(x) < _EXACT_INT):
            message = f"{spec.label(i)} must be an integer; got {text}"
            raise _fail(spec, record, i, message) from None
        value = int(x)
    if abs(value) >= _EXACT_INT:  # ids and counts index int64 arrays; floats count steps
        raise _fail(spec, record, i, f"{spec.label(i)} must be an integer below 2^53; got {text}")
    if least is not None and value < least:
        what = "a positive integer" if least == 1 else f"an integer >= {least}"
        raise _fail(spec, record, i, f"{spec.label(i)} must be {what}; got {text}")
    return value


def _count(
    spec: CardSpec, record: Record, values: list[str], low: int, high: int | None, expected: str
) -> None:
    """Check the number of values of a record; the message names the fields expected."""
    n = len(values)
    if n < low or (high is not None and n > high):  # point at the record, or the first extra
        raise _fail(spec, record, 0 if n < low else high, f"{spec.name} needs {expected}; got {n}")


def _counted(
    spec: CardSpec, items: list[Any], low: int, high: int | None, expected: str
) -> Iterator[tuple[Record, list[str]]]:
    """Each record of a card's ``items`` with its values, checked by :func:`_count`."""
    for rec in _records(items):
        values = _split(rec)
        _count(spec, rec, values, low, high, expected)
        yield rec, values


def _dof(spec: CardSpec, record: Record, values: list[str], i: int, seen: list[int]) -> int:
    """Field ``i`` as a DOF number 1..6 (x y z rx ry rz), not already in ``seen``."""
    dof = _int(spec, record, values, i, None)
    if not 1 <= dof <= 6:
        raise _fail(
            spec,
            record,
            i,
            f"{spec.label(i)} must be a DOF number 1..6 (x y z rx ry rz); got {values[i]}",
        )
    if dof in seen:
        raise _fail(spec, record, i, f"{spec.label(i)}: DOF {dof} is listed twice")
    seen.append(dof)
    return dof


def _dof_code(spec: CardSpec, record: Record, values: list[str], i: int) -> tuple[int, ...]:
    """Field ``i`` as a DOF code: distinct digits 1..6, e.g. 123456 -> (1, 2, 3, 4, 5, 6)."""
    digits = [int(d) for d in str(_int(spec, record, values, i))]
    if any(d < 1 or d > 6 for d in digits) or len(set(digits)) != len(digits):
        raise _fail(
            spec,
            record,
            i,
            f"{spec.label(i)} must be a code of distinct DOF digits "
            f"1..6 (x y z rx ry rz, e.g. 123456); got {values[i]}",
        )
    return tuple(digits)


def _one_record(spec: CardSpec, kw: Token, records: list[Record], expected: str) -> Record:
    if not records:
        raise DeckError(
            f"{spec.name} needs {expected}; got none", "<deck>", kw.line, kw.column, spec.name
        )
    if len(records) > 1:
        raise _fail(
            spec,
            records[1],
            0,
            f"{spec.name} takes one record ({expected}); a second "
            f"record starts here (end a line with '&' to continue)",
        )
    return records[0]
