"""The contact cards' callbacks of the deck transformer (x3dpd.deck.transform): HOOKE, WALLMAT,
FRICTION, the analytic wall shapes and CONTACT -- records to typed cards (``cards.py``), each
field checked where it stands (docs/deck-reference.md). No physics here."""

from __future__ import annotations

from typing import Any

from lark import Token

from x3dpd.deck.cards import (
    AnalyticWall,
    Contact,
    Friction,
    Hooke,
    SlaveSet,
    Triangle,
    WallMat,
)
from x3dpd.deck.fields import BY_NAME, CONTACT_SLAVES
from x3dpd.deck.records import (
    _count,
    _counted,
    _fail,
    _first,
    _floats,
    _int,
    _pos,
    _positions,
    _split,
)
from x3dpd.geometry.shapes import BY_SHAPE_CARD

#: What a card callback returns: canonical card name, keyword token, card or list of records.
_Card = tuple[str, Token, Any]


class ContactCards:
    """Callbacks of the contact cards (mixed into :class:`x3dpd.deck.transform.DeckTransformer`;
    lark finds a callback by the rule's name)."""

    def hooke(self, c: list[Any]) -> _Card:
        spec = BY_NAME["HOOKE"]
        out = []
        for rec, v in _counted(spec, c[1:-1], 3, 3, "3 values: NODLIM KN E"):
            nodlim = _int(spec, rec, v, 0, None)
            kn, e = _floats(spec, rec, v, 1)
            if not kn > 0.0:
                raise _fail(spec, rec, 1, f"KN (normal stiffness) must be > 0; got {v[1]}")
            if not 0.0 < e <= 1.0:
                raise _fail(
                    spec, rec, 2, f"E (coefficient of restitution) must be in (0, 1]; got {v[2]}"
                )
            out.append(Hooke(nodlim, kn, e, _first(rec)))
        return "HOOKE", c[0], out

    def wallmat(self, c: list[Any]) -> _Card:
        """WALLMAT (our extension): SET E NU MU, the elastic material of a CONTACT set's walls."""
        spec = BY_NAME["WALLMAT"]
        out = []
        for rec, v in _counted(spec, c[1:-1], 4, 4, "4 values: SET E NU MU"):
            set_id = _int(spec, rec, v, 0)
            e, nu, mu = _floats(spec, rec, v, 1)
            if not e > 0.0:
                raise _fail(spec, rec, 1, f"E (the wall's Young's modulus) must be > 0; got {v[1]}")
            if not -1.0 < nu < 0.5:
                raise _fail(
                    spec,
                    rec,
                    2,
                    f"NU (the wall's Poisson's ratio) must lie in (-1, 0.5); got {v[2]}",
                )
            if not mu >= 0.0:
                raise _fail(
                    spec, rec, 3, f"MU (the wall's friction coefficient) must be >= 0; got {v[3]}"
                )
            out.append(WallMat(set_id, e, nu, mu, _first(rec)))
        return "WALLMAT", c[0], out

    def friction(self, c: list[Any]) -> _Card:
        spec = BY_NAME["FRICTION"]
        out = []
        # the LAW and ROLL words are the registries' names (a law's registration line is all
        # it takes for the deck to accept it)
        from x3dpd.physics.rolling import ROLLING_LAWS
        from x3dpd.physics.tangential_laws import TANGENTIAL_LAWS

        expected = "4 or 6 values: NODLIM LAW MUS MUK [ROLL MUR]"
        for tok in c[1:-1]:
            rec = [(tok.line, tok.column, str(tok))]
            v = _split(rec)
            _count(spec, rec, v, 4, 6, expected)
            if len(v) == 5:
                raise _fail(spec, rec, 5, f"ROLL needs its MUR: {expected}")
            nodlim = _int(spec, rec, v, 0, None)
            law = v[1].lower()
            if law not in TANGENTIAL_LAWS:
                raise _fail(
                    spec, rec, 1, f"LAW must be one of {', '.join(TANGENTIAL_LAWS)}; got {v[1]}"
                )
            mu_s, mu_k = _floats(spec, rec, v[:4], 2)
            for k, (name, mu) in enumerate((("MUS", mu_s), ("MUK", mu_k)), start=2):
                if not mu >= 0.0:
                    raise _fail(spec, rec, k, f"{name} must be >= 0; got {v[k]}")
            if mu_k > mu_s:
                raise _fail(
                    spec, rec, 3, f"MUK (kinetic) must not exceed MUS (static) {v[2]}; got {v[3]}"
                )
            if law != "mindlin" and mu_k != mu_s:
                raise _fail(
                    spec,
                    rec,
                    3,
                    f"the {law} law has one friction coefficient: MUK "
                    f"must equal MUS ({v[2]}); got {v[3]}",
                )
            roll, mu_r = "none", 0.0
            if len(v) == 6:
                roll = v[4].lower()
                if roll not in ROLLING_LAWS:
                    raise _fail(
                        spec, rec, 4, f"ROLL must be one of {', '.join(ROLLING_LAWS)}; got {v[4]}"
                    )
                (mu_r,) = _floats(spec, rec, v, 5)
                if not mu_r >= 0.0:
                    raise _fail(spec, rec, 5, f"MUR must be >= 0; got {v[5]}")
            out.append(Friction(nodlim, law, mu_s, mu_k, roll, mu_r, _first(rec)))
        return "FRICTION", c[0], out

    def shape(self, c: list[Any]) -> _Card:
        """A card of an analytic wall shape (x3dpd.geometry.shapes): SET, the node ids (two of
        them must differ), the lengths (each > 0)."""
        shape = BY_SHAPE_CARD[c[0].type]  # the grammar's terminal is the card's name
        spec = BY_NAME[shape.card]
        n_nodes, n = len(shape.node_fields), len(shape.fields)
        out = []
        for rec, v in _counted(spec, c[1:-1], n, n, f"{n} values: {' '.join(shape.fields)}"):
            ids = [_int(spec, rec, v, i) for i in range(1 + n_nodes)]
            params = _floats(spec, rec, v, 1 + n_nodes)
            for k, value in enumerate(params):
                if not value > 0.0:
                    raise _fail(
                        spec,
                        rec,
                        1 + n_nodes + k,
                        f"{shape.param_fields[k]} must be > 0; got {v[1 + n_nodes + k]}",
                    )
            if n_nodes == 2 and ids[1] == ids[2]:
                raise _fail(
                    spec,
                    rec,
                    2,
                    f"{shape.node_fields[1]} must differ from "
                    f"{shape.node_fields[0]} ({ids[1]}): the axis runs "
                    "from one to the other",
                )
            out.append(
                AnalyticWall(
                    shape.name,
                    ids[0],
                    tuple(ids[1:]),
                    tuple(params),
                    _first(rec),
                    _positions(rec, 1)[:n_nodes],
                )
            )
        return "ANALYTIC", c[0], out

    def contact(self, c: list[Any]) -> _Card:
        spec = BY_NAME["CONTACT"]
        split = next(i for i, x in enumerate(c) if isinstance(x, Token) and x.type == "END")
        triangles = []
        for rec, v in _counted(
            spec, c[1:split], 4, 4, "4 values per master triangle: SET N1 N2 N3"
        ):
            ids = [_int(spec, rec, v, i) for i in range(4)]
            triangles.append(Triangle(ids[0], (ids[1], ids[2], ids[3]), _first(rec)))
        slaves = []
        sspec = CONTACT_SLAVES
        for rec, v in _counted(
            sspec, c[split + 1 : -1], 2, None, "SET and at least one slave node id per slave record"
        ):
            ids = tuple(_int(sspec, rec, v, i) for i in range(len(v)))
            slaves.append(SlaveSet(ids[0], ids[1:], _positions(rec, 1), _first(rec)))
        return "CONTACT", c[0], Contact(tuple(triangles), tuple(slaves), _pos(c[0]))
