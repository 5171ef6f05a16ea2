"""Lark transformer: records of the deck grammar -> typed cards (``cards.py``).

The grammar (``x3d.lark``) hands each card over as ``[KEYWORD, item, ..., END]``; an item is a
ROWS token (a run of one-line records) or a continued record (its lines). This module splits the
lines into records and values, converts fields (with the helpers of ``records.py``), checks field
counts and card-local values, and raises :class:`~x3dpd.errors.DeckError` naming the field.
Cross-card checks (an undefined node, a
duplicate id) belong to ``x3dpd.model.build``. No physics here.

The transformer is passed to the ``Lark`` constructor, so no parse tree is built. Errors are
raised with the path ``"<deck>"``; ``parser.py`` puts in the real path.
"""

from __future__ import annotations

from math import isfinite
from typing import Any

from lark import Token, Transformer

from x3dpd.deck.cards import (
    Body,
    Boundary,
    Deck,
    Element,
    Initial,
    Mass,
    Material,
    Node,
    Parameters,
    Pdmp,
    Pos,
    Rbel,
    Title,
    Trace,
    UnitRecord,
    Units,
    Usrfrc,
)
from x3dpd.deck.text_cards import BY_TEXT_TERMINAL, TEXT_CARDS
from x3dpd.deck.transform_contact import ContactCards
from x3dpd.deck.fields import BY_NAME, SINGLE_CARDS
from x3dpd.deck.records import (  # noqa: F401  (Piece, to_float re-exported)
    _EXACT_INT,
    Piece,
    Record,
    _count,
    _counted,
    _dof,
    _dof_code,
    _fail,
    _first,
    _floats,
    _int,
    _one_record,
    _pos,
    _positions,
    _records,
    _split,
    to_float,
)
from x3dpd.errors import DeckError
from x3dpd.physics.effect_units import UNITS
from x3dpd.units import parse_units

#: The effect unit of each unit card's keyword terminal (its name's first word).
_UNIT_OF_KEYWORD = {u.card.name.split()[0].upper(): u for u in UNITS if u.card is not None}

#: What a card callback returns: canonical card name, keyword token, card or list of records.
_Card = tuple[str, Token, Any]


class DeckTransformer(ContactCards, Transformer):
    """Callbacks of the deck grammar; a card callback returns ``(card name, keyword, value)``."""

    def record(self, children: list[Token]) -> Record:
        return [(t.line, t.column, str(t)) for t in children]

    # -- text cards -------------------------------------------------------------------------
    def title(self, c: list[Token]) -> _Card:
        lines = [t.rstrip() for t in c[1:-1]]
        if lines and c[1].line == c[0].line:
            lines[0] = lines[0].lstrip()
        return "TITLE", c[0], Title("\n".join(lines), _pos(c[0]))

    def usrfrc(self, c: list[Token]) -> _Card:
        return "USRFRC", c[0], Usrfrc(tuple(t.strip() for t in c[1:-1]), _pos(c[0]))

    def units(self, c: list[Token]) -> _Card:
        words = " ".join(str(t) for t in c[1:-1]).replace(",", " ").split()
        at = c[1] if len(c) > 2 else c[0]
        try:
            system = parse_units(words)
        except ValueError as exc:
            raise DeckError(str(exc), "<deck>", at.line, at.column, "UNITS") from None
        return "UNITS", c[0], Units(*system, _pos(c[0]))

    def text_card(self, c: list[Token]) -> _Card:
        """One of our text cards (x3dpd.deck.text_cards), read by its module's ``parse``."""
        card = BY_TEXT_TERMINAL[c[0].type]
        lines = [(str(t), t.line, t.column) for t in c[1:-1]]
        return card.name, c[0], card.parse(_pos(c[0]), lines)

    # -- value cards ------------------------------------------------------------------------
    def parameters(self, c: list[Any]) -> _Card:
        spec = BY_NAME["PARAMETERS"]
        expected = "11 values: " + " ".join(spec.fields)
        rec = _one_record(spec, c[0], list(_records(c[1:-1])), expected)
        v = _split(rec)
        _count(spec, rec, v, 11, 11, expected)
        f = _floats(spec, rec, v)
        incr, irest, nintpl, istat, itrac = (_int(spec, rec, v, i, None) for i in (5, 7, 8, 9, 10))
        if f[4] <= 0:
            raise _fail(spec, rec, 4, f"DTMAX must be > 0; got {v[4]}")
        if f[3] < 0 or f[3] > f[4]:
            raise _fail(spec, rec, 3, f"DTMIN must be between 0 and DTMAX ({v[4]}); got {v[3]}")
        if f[1] < f[0]:
            raise _fail(spec, rec, 1, f"TMAX must be >= TIME ({v[0]}); got {v[1]}")
        if itrac < 1:
            raise _fail(spec, rec, 10, f"ITRAC (trace every ITRAC steps) must be >= 1; got {v[10]}")
        card = Parameters(
            f[0], f[1], f[2], f[3], f[4], incr, f[6], irest, nintpl, istat, itrac, _first(rec)
        )
        return "PARAMETERS", c[0], card

    def matid(self, c: list[Any]) -> _Card:
        spec = BY_NAME["MATID"]
        out = []
        expected = "at least 8 values: " + " ".join(spec.fields) + " [EXTRA...]"
        for rec, v in _counted(spec, c[1:-1], 8, None, expected):
            mid, mtype = _int(spec, rec, v, 0), _int(spec, rec, v, 1, None)
            f = _floats(spec, rec, v, 2)
            if f[0] < 0:
                raise _fail(spec, rec, 2, f"MASS (element mass) must be >= 0; got {v[2]}")
            out.append(Material(mid, mtype, *f[:6], tuple(f[6:]), _first(rec)))
        return "MATID", c[0], out

    def pdmp(self, c: list[Any]) -> _Card:
        spec = BY_NAME["PDMP"]
        expected = "8 to 11 values: " + " ".join(spec.fields) + " (then pairs E2 T2 ...)"
        out = []
        for rec, v in _counted(spec, c[1:-1], 8, None, expected):
            if len(v) > 11 and (len(v) - 11) % 2:
                message = (
                    f"PDMP extra Maxwell terms come in pairs E2 T2 E3 T3 ... after VZ0; "
                    f"got {len(v)} values"
                )
                raise _fail(spec, rec, len(v) - 1, message)
            nodlim = _int(spec, rec, v, 0, 0)
            f = _floats(spec, rec, v, 1) + [0.0] * max(0, 11 - len(v))
            if f[0] <= 0:
                raise _fail(spec, rec, 1, f"RZERO (particle radius) must be > 0; got {v[1]}")
            if f[1] <= 0:
                raise _fail(spec, rec, 2, f"PRHO (particle density) must be > 0; got {v[2]}")
            extra = tuple(zip(f[10::2], f[11::2]))
            out.append(Pdmp(nodlim, *f[:10], extra, _first(rec)))
        return "PDMP", c[0], out

    def body(self, c: list[Any]) -> _Card:
        spec = BY_NAME["BODY"]
        rec = _one_record(spec, c[0], list(_records(c[1:-1])), "3 values: AX AY AZ")
        v = _split(rec)
        _count(spec, rec, v, 3, 3, "3 values: AX AY AZ")
        return "BODY", c[0], Body(*_floats(spec, rec, v), _first(rec))

    def trace(self, c: list[Any]) -> _Card:
        spec = BY_NAME["TRACE"]
        nodes: list[int] = []
        where: list[Pos] = []
        for rec in _records(c[1:-1]):
            v = _split(rec)
            nodes.extend(_int(spec, rec, v, i) for i in range(len(v)))
            where.extend(_positions(rec, 0))
        if not nodes:
            raise DeckError(
                "TRACE needs at least one node id; got none",
                "<deck>",
                c[0].line,
                c[0].column,
                spec.name,
            )
        return "TRACE", c[0], Trace(tuple(nodes), tuple(where), _pos(c[0]))

    def node(self, c: list[Any]) -> _Card:
        out = []
        append = out.append
        for item in c[1:-1]:
            if not isinstance(item, Token) or "," in item or "$" in item:
                out.extend(map(self._node, _records([item])))
                continue
            line, col = item.line, item.column
            for text in item.split("\n"):  # fast path: lines "id x y z"
                v = text.split()
                node = None
                if len(v) == 4:
                    try:
                        nid, x, y, z = int(v[0]), float(v[1]), float(v[2]), float(v[3])
                        if 0 < nid < _EXACT_INT and isfinite(abs(x) + abs(y) + abs(z)):
                            indent = len(text) - len(text.lstrip())
                            node = Node(nid, x, y, z, Pos(line, col + indent))
                    except ValueError:  # 1.0D0, 25., a bad field: the slow path decides
                        pass
                if node is None and v:
                    node = self._node([(line, col, text)])
                if node is not None:
                    append(node)
                line, col = line + 1, 1
        return "NODE COORDINATES", c[0], out

    @staticmethod
    def _node(rec: Record) -> Node:
        spec = BY_NAME["NODE COORDINATES"]
        v = _split(rec)
        _count(spec, rec, v, 4, 4, "4 values: ID X Y Z")
        return Node(_int(spec, rec, v, 0), *_floats(spec, rec, v, 1), _first(rec))

    def elements(self, c: list[Any]) -> _Card:
        spec = BY_NAME["ELEMENTS"]
        out = []
        for rec, v in _counted(spec, c[1:-1], 3, 4, "3 or 4 values: ID MID NODE1 [NODE2]"):
            ids = [_int(spec, rec, v, i) for i in range(len(v))]
            out.append(Element(ids[0], ids[1], tuple(ids[2:]), _first(rec)))
        return "ELEMENTS", c[0], out

    def mass(self, c: list[Any]) -> _Card:
        spec = BY_NAME["MASS"]
        out = []
        for rec, v in _counted(spec, c[1:-1], 2, 5, "2 to 5 values: NODE MASS [IXX IYY IZZ]"):
            f = _floats(spec, rec, v, 1) + [0.0] * (5 - len(v))
            for i, x in enumerate(f[: len(v) - 1], start=1):
                if x < 0:
                    raise _fail(spec, rec, i, f"{spec.label(i)} must be >= 0; got {v[i]}")
            out.append(Mass(_int(spec, rec, v, 0), *f, _first(rec)))
        return "MASS", c[0], out

    def rbel(self, c: list[Any]) -> _Card:
        spec = BY_NAME["RBEL"]
        out = []
        for rec, v in _counted(
            spec, c[1:-1], 4, None, "MASTER DOFS COUNT and COUNT slave node ids"
        ):
            master = _int(spec, rec, v, 0)
            dofs = _dof_code(spec, rec, v, 1)
            count = _int(spec, rec, v, 2)
            if count != len(v) - 3:
                raise _fail(
                    spec, rec, 2, f"RBEL declares COUNT={count} slave nodes but lists {len(v) - 3}"
                )
            slaves = tuple(_int(spec, rec, v, i) for i in range(3, len(v)))
            out.append(Rbel(master, dofs, slaves, _positions(rec, 3), _first(rec)))
        return "RBEL", c[0], out

    def boundary(self, c: list[Any]) -> _Card:
        spec = BY_NAME["BOUNDARY CONDITIONS"]
        out = []
        for rec, v in _counted(
            spec, c[1:-1], 4, None, "FIRST LAST INC and at least one DOF (1..6)"
        ):
            first, last, inc = (_int(spec, rec, v, i) for i in range(3))
            if last < first:
                raise _fail(spec, rec, 1, f"LAST must be >= FIRST ({first}); got {last}")
            seen: list[int] = []
            dofs = tuple(_dof(spec, rec, v, i, seen) for i in range(3, len(v)))
            out.append(Boundary(first, last, inc, dofs, _first(rec)))
        return "BOUNDARY CONDITIONS", c[0], out

    def initial(self, c: list[Any]) -> _Card:
        spec = BY_NAME["INITIAL"]
        out = []
        for rec in _records(c[1:-1]):
            v = _split(rec)
            if len(v) not in (4, 7):  # point at the record, or at the first value too many
                message = f"INITIAL needs 4 or 7 values: NODE VX VY VZ [WX WY WZ]; got {len(v)}"
                raise _fail(spec, rec, 0 if len(v) < 7 else 7, message)
            vel = _floats(spec, rec, v, 1)
            out.append(Initial(_int(spec, rec, v, 0), tuple(vel), _first(rec)))
        return "INITIAL", c[0], out

    # -- the whole deck ---------------------------------------------------------------------
    def unit_card(self, c: list[Any]) -> _Card:
        """A card of an effect unit's own (x3dpd.physics.effect_units): the card's values per
        record, its node fields integers."""
        unit = _UNIT_OF_KEYWORD[c[0].type]  # the grammar's terminal is the keyword's first word
        card, spec = unit.card, BY_NAME[unit.card.name]
        n = len(card.fields)
        out = []
        for rec, v in _counted(spec, c[1:-1], n, n, f"{n} values: {' '.join(card.fields)}"):
            floats = _floats(spec, rec, v)
            values = tuple(
                _int(spec, rec, v, i) if name in card.node_fields else floats[i]
                for i, name in enumerate(card.fields)
            )
            out.append(UnitRecord(unit.name, values, _first(rec), _positions(rec, 0)))
        return "UNIT", c[0], out

    def start(self, cards: list[_Card]) -> Deck:
        single: dict[str, Any] = {}
        seen: dict[str, Token] = {}
        lists: dict[str, list[Any]] = {}
        for name, kw, value in cards:
            if name in SINGLE_CARDS:
                if name in single:
                    raise DeckError(
                        f"{name} may appear only once; it was already given at line "
                        f"{seen[name].line}",
                        "<deck>",
                        kw.line,
                        kw.column,
                        name,
                    )
                single[name], seen[name] = value, kw
            elif isinstance(value, list):
                lists.setdefault(name, []).extend(value)
            else:
                lists.setdefault(name, []).append(value)

        def many(name: str) -> tuple[Any, ...]:
            return tuple(lists.get(name, ()))

        return Deck(
            title=single.get("TITLE"),
            parameters=single.get("PARAMETERS"),
            materials=many("MATID"),
            pdmp=many("PDMP"),
            body=single.get("BODY"),
            trace=single.get("TRACE"),
            nodes=many("NODE COORDINATES"),
            elements=many("ELEMENTS"),
            masses=many("MASS"),
            rbels=many("RBEL"),
            boundaries=many("BOUNDARY CONDITIONS"),
            contacts=many("CONTACT"),
            initials=many("INITIAL"),
            usrfrc=many("USRFRC"),
            units=single.get("UNITS"),
            hooke=many("HOOKE") or None,
            wallmat=many("WALLMAT") or None,
            friction=many("FRICTION") or None,
            analytic_walls=many("ANALYTIC") or None,
            unit_records=many("UNIT") or None,
            # our text cards, each resolved once the UNITS card is known (TEMPERATURE's bare
            # numbers are on its scale)
            **{card.field: _resolved(card, single) for card in TEXT_CARDS},
        )


def _resolved(card, single: dict):
    """Text card ``card``'s value in the deck (None without), resolved with its UNITS card."""
    value = single.get(card.name)
    if value is None or card.resolve is None:
        return value
    return card.resolve(value, single.get("UNITS"))
