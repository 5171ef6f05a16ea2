"""Write a :class:`~x3dpd.deck.cards.Deck` back as normalized deck text.

The text uses canonical card names, one record per line (long lists continue with ``&``), a ``$``
comment naming the fields of each card, and numbers in Python's shortest round-trip form
(``repr``), so ``parse_deck(format_deck(d))`` gives back the same cards bit for bit (positions
aside). Cards are written in the order of the report's Appendix A.
"""

from __future__ import annotations

import math
import operator
import os
from collections.abc import Iterable

from x3dpd._files import write_atomically
from x3dpd.deck.cards import Deck
from x3dpd.deck.fields import BY_NAME, CONTACT_SLAVES, MATID_FIELDS, PARAMETER_FIELDS, PDMP_FIELDS
from x3dpd.deck.text_cards import TEXT_CARDS
from x3dpd.geometry.shapes import SHAPES
from x3dpd.physics.effect_units import UNITS

#: Values per line before a list record (TRACE, RBEL, slave set) is continued with ``&``.
PER_LINE = 10
#: Values per line of a record with named fields (PARAMETERS, PDMP, MATID ...).
PER_FIELD_LINE = 16
_INDENT = "   "


def _f(x: float) -> str:
    """A float in shortest round-trip form (``repr``), which the deck grammar reads back exactly."""
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"a deck cannot hold the non-finite number {x!r}")
    return repr(x)


def _i(x: int) -> str:
    """An integer (bool and float are refused, so a typo cannot turn 2.5 into 2)."""
    try:
        if isinstance(x, bool):
            raise TypeError
        return str(operator.index(x))
    except TypeError:
        raise ValueError(f"expected an integer, got {x!r}") from None


def _record(values: list[str], out: list[str], per_line: int = PER_FIELD_LINE) -> None:
    """Append one record, ``per_line`` values a line, continued with ``&``."""
    for start in range(0, len(values), per_line):
        chunk = " ".join(values[start : start + per_line])
        more = start + per_line < len(values)
        out.append(f"{_INDENT}{chunk} &" if more else f"{_INDENT}{chunk}")


def _text_line(line: str, what: str) -> str:
    """Check that a TITLE line or USRFRC spec reads back unchanged; return it."""
    if "$" in line or any(ord(ch) < 32 and ch != "\t" for ch in line):
        raise ValueError(f"{what} {line!r} cannot hold '$' or control characters")
    # a line of blanks and commas alone reads back as a blank line (the free format's separators)
    if not line.strip(" \t,") or line != line.rstrip() or line.strip().upper() == "END":
        raise ValueError(
            f"{what} {line!r} must be non-blank (not only commas), not END, without trailing blanks"
        )
    return line


def _card(out: list[str], name: str, header: Iterable[str] | None = None) -> None:
    out.append(name)
    if header:
        out.append("$ " + " ".join(header))


def _dofs(dofs: tuple[int, ...]) -> str:
    if not dofs or any(not 1 <= operator.index(d) <= 6 for d in dofs):
        raise ValueError(f"a DOF code needs digits 1..6, got {dofs!r}")
    return "".join(str(d) for d in dofs)


# Over 80 lines: the deck's cards written in the reader's order, a short block per card.
def format_deck(deck: Deck) -> str:
    """Normalized deck text for ``deck``; parsing it gives back equal cards (positions aside).

    Parameters
    ----------
    deck : Deck
        The cards to write. Empty card tuples and ``None`` cards are left out.

    Returns
    -------
    str
        The deck text, ending with a newline.

    Raises
    ------
    ValueError
        A value the deck language cannot hold: a non-finite number, a non-integer id, a TITLE
        line or USRFRC spec containing ``$``, blank or reading ``END``.
    """
    out: list[str] = []
    if deck.title is not None:
        out.append("TITLE")
        if deck.title.text:
            out.extend(_text_line(line, "TITLE line") for line in deck.title.text.split("\n"))
        out.append("END")
    if deck.parameters is not None:
        p = deck.parameters
        _card(out, "PARAMETERS", PARAMETER_FIELDS)
        _record(
            [
                _f(p.time),
                _f(p.tmax),
                _f(p.trest),
                _f(p.dtmin),
                _f(p.dtmax),
                _i(p.incr),
                _f(p.incmax),
                _i(p.irest),
                _i(p.nintpl),
                _i(p.istat),
                _i(p.itrac),
            ],
            out,
        )
        out.append("END")
    if deck.materials:
        _card(out, "MATID", (*MATID_FIELDS, "EXTRA..."))
        for m in deck.materials:
            _record(
                [
                    _i(m.mid),
                    _i(m.mtype),
                    _f(m.mass),
                    _f(m.scale),
                    _f(m.kx),
                    _f(m.ky),
                    _f(m.kz),
                    _f(m.c),
                    *map(_f, m.extra),
                ],
                out,
            )
        out.append("END")
    for g in deck.pdmp:
        _card(out, "PDMP", (*PDMP_FIELDS, "[E2 T2 ...]"))
        values = [
            _i(g.nodlim),
            *map(_f, (g.rzero, g.prho, g.ppoi, g.e0, g.e1, g.t1, g.pcof, g.vx0, g.vy0, g.vz0)),
        ]
        for e, t in g.extra_terms:
            values += [_f(e), _f(t)]
        _record(values, out)
        out.append("END")
    if deck.body is not None:
        b = deck.body
        _card(out, "BODY", BY_NAME["BODY"].fields)
        _record([_f(b.ax), _f(b.ay), _f(b.az)], out)
        out.append("END")
    if deck.trace is not None:
        out.append("TRACE")
        _record([_i(n) for n in deck.trace.nodes], out, PER_LINE)
        out.append("END")
    if deck.nodes:
        _card(out, "NODE COORDINATES", BY_NAME["NODE COORDINATES"].fields)
        out.extend(f"{_INDENT}{_i(n.nid)} {_f(n.x)} {_f(n.y)} {_f(n.z)}" for n in deck.nodes)
        out.append("END")
    if deck.elements:
        _card(out, "ELEMENTS", ("ID", "MID", "NODE1", "[NODE2]"))
        for e in deck.elements:
            if len(e.nodes) not in (1, 2):
                raise ValueError(f"element {e.eid} needs 1 or 2 nodes, got {e.nodes!r}")
            _record([_i(e.eid), _i(e.mid), *map(_i, e.nodes)], out)
        out.append("END")
    if deck.masses:
        _card(out, "MASS", BY_NAME["MASS"].fields)
        for m in deck.masses:
            _record([_i(m.nid), _f(m.mass), _f(m.ixx), _f(m.iyy), _f(m.izz)], out)
        out.append("END")
    if deck.rbels:
        _card(out, "RBEL", ("MASTER", "DOFS", "COUNT", "SLAVE..."))
        for r in deck.rbels:
            _record(
                [_i(r.master), _dofs(r.dofs), str(len(r.slaves)), *map(_i, r.slaves)], out, PER_LINE
            )
        out.append("END")
    if deck.boundaries:
        _card(out, "BOUNDARY CONDITIONS", ("FIRST", "LAST", "INC", "DOF..."))
        for bc in deck.boundaries:
            _dofs(bc.dofs)
            _record([_i(bc.first), _i(bc.last), _i(bc.inc), *map(_i, bc.dofs)], out)
        out.append("END")
    for c in deck.contacts:
        _card(out, "CONTACT", BY_NAME["CONTACT"].fields)
        for t in c.triangles:
            if len(t.nodes) != 3:
                raise ValueError(f"a contact triangle needs 3 nodes, got {t.nodes!r}")
            _record([_i(t.set_id), *map(_i, t.nodes)], out)
        out.append("END")
        out.append("$ " + " ".join((*CONTACT_SLAVES.fields, "SLAVE...")))
        for s in c.slaves:
            if not s.nodes:
                raise ValueError(f"slave set {s.set_id} lists no nodes")
            _record([_i(s.set_id), *map(_i, s.nodes)], out, PER_LINE)
        out.append("END")
    if deck.initials:
        _card(out, "INITIAL", ("NODE", "VX", "VY", "VZ", "[WX WY WZ]"))
        for ini in deck.initials:
            if len(ini.velocity) not in (3, 6):
                raise ValueError(f"INITIAL node {ini.nid} needs 3 or 6 velocities")
            _record([_i(ini.nid), *map(_f, ini.velocity)], out)
        out.append("END")
    if deck.hooke:
        _card(out, "HOOKE", ("NODLIM", "KN", "E"))
        for h in deck.hooke:
            _record([_i(h.nodlim), _f(h.kn), _f(h.e)], out)
        out.append("END")
    if deck.wallmat:
        _card(out, "WALLMAT", BY_NAME["WALLMAT"].fields)
        for m in deck.wallmat:
            _record([_i(m.set_id), _f(m.e), _f(m.nu), _f(m.mu)], out)
        out.append("END")
    if deck.friction:
        _card(out, "FRICTION", ("NODLIM", "LAW", "MUS", "MUK", "[ROLL MUR]"))
        for r in deck.friction:
            rolling = [r.roll, _f(r.mu_r)] if r.roll != "none" or r.mu_r != 0.0 else []
            _record([_i(r.nodlim), r.law, _f(r.mu_s), _f(r.mu_k), *rolling], out)
        out.append("END")
    for shape in SHAPES:  # analytic wall cards (CYLINDER, CAPSULE ...), one per shape used
        mine = [w for w in deck.analytic_walls or () if w.shape == shape.name]
        if mine:
            _card(out, shape.card, shape.fields)
            for w in mine:
                _record([_i(w.set_id)] + [_i(n) for n in w.nodes] + [_f(v) for v in w.params], out)
            out.append("END")
    for unit in UNITS:  # the effect units' own cards, one per unit used
        mine = [r for r in deck.unit_records or () if r.unit == unit.name]
        if mine and unit.card is not None:
            _card(out, unit.card.name, unit.card.fields)
            nodes = [f in unit.card.node_fields for f in unit.card.fields]
            for r in mine:
                _record([_i(v) if is_node else _f(v) for v, is_node in zip(r.values, nodes)], out)
            out.append("END")
    if deck.units is not None:
        out += ["UNITS", _INDENT + " ".join(deck.units.system), "END"]
    for card in TEXT_CARDS:  # our text cards (x3dpd.deck.text_cards), in registry order
        value = getattr(deck, card.field)
        if card.written(value):
            out += [card.name] + (["$ " + card.header] if card.header else [])
            out += [_INDENT + _text_line(t, f"{card.name} record") for t in card.lines(value)]
            out.append("END")
    for u in deck.usrfrc:
        out.append("USRFRC")
        out.extend(_INDENT + _text_line(spec.strip(), "USRFRC spec") for spec in u.specs)
        out.append("END")
    return "\n".join(out) + "\n"


def write_deck(deck: Deck, path: str | os.PathLike[str]) -> None:
    """Write ``format_deck(deck)`` to ``path`` atomically (a temporary file, then ``os.replace``).

    A reader never sees a half-written deck, and an existing file is replaced only once the new
    text is complete on disk.
    """
    text = format_deck(deck).encode("utf-8")
    write_atomically(path, lambda f: f.write(text))
