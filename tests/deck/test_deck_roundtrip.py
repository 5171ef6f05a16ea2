"""parse(format(deck)) == deck for random decks, also after random edits of the text's form.

Positions aside, the writer's text must give back every card bit for bit: floats are written in
shortest round-trip form, so extreme exponents, subnormals and -0.0 must survive.
"""

from __future__ import annotations

import math
import re

import pytest
from deck_helpers import strip_positions
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from x3dpd.deck import (
    Body,
    Boundary,
    Contact,
    Deck,
    Element,
    Initial,
    Mass,
    Material,
    Node,
    Parameters,
    Pdmp,
    Rbel,
    SlaveSet,
    Title,
    Trace,
    Triangle,
    Usrfrc,
    WallMat,
    format_deck,
    parse_deck,
    write_deck,
)

ids = st.integers(1, 10**9)
reals = st.floats(allow_nan=False, allow_infinity=False)
nonneg = st.floats(0.0, allow_infinity=False)
positive = st.floats(0.0, exclude_min=True, allow_infinity=False)
ints = st.integers(-(10**6), 10**6)
dof_sets = st.lists(st.integers(1, 6), min_size=1, max_size=6, unique=True).map(tuple)
text_chars = st.characters(
    codec="utf-8", exclude_characters="$\n\r", exclude_categories=("Cc", "Cs", "Zl", "Zp")
)


def _writable_line(line: str) -> bool:
    return bool(line.strip(" \t,")) and line == line.rstrip() and line.strip().upper() != "END"


title_lines = st.text(text_chars, min_size=1, max_size=30).filter(_writable_line)
specs = st.text(text_chars, min_size=1, max_size=40).map(str.strip).filter(_writable_line)


@st.composite
def parameters(draw):
    dtmax = draw(positive)
    time = draw(reals)
    return Parameters(
        time,
        draw(st.floats(time, allow_infinity=False)),
        draw(reals),
        draw(st.floats(0.0, dtmax)),
        dtmax,
        draw(ints),
        draw(reals),
        draw(ints),
        draw(ints),
        draw(ints),
        draw(st.integers(1, 10**6)),
    )


materials = st.builds(
    Material,
    ids,
    ints,
    nonneg,
    reals,
    reals,
    reals,
    reals,
    reals,
    st.lists(reals, max_size=20).map(tuple),
)
pdmps = st.builds(
    Pdmp,
    st.integers(0, 10**9),
    positive,
    positive,
    reals,
    reals,
    reals,
    reals,
    reals,
    reals,
    reals,
    reals,
    st.lists(st.tuples(reals, reals), max_size=4).map(tuple),
)
nodes = st.builds(Node, ids, reals, reals, reals)
elements = st.builds(Element, ids, ids, st.lists(ids, min_size=1, max_size=2).map(tuple))
masses = st.builds(Mass, ids, nonneg, nonneg, nonneg, nonneg)
rbels = st.builds(Rbel, ids, dof_sets, st.lists(ids, min_size=1, max_size=40).map(tuple))
boundaries = st.builds(
    lambda first, span, inc, dofs: Boundary(first, first + span, inc, dofs),
    ids,
    st.integers(0, 1000),
    st.integers(1, 100),
    dof_sets,
)
triangles = st.builds(Triangle, ids, st.tuples(ids, ids, ids))
slave_sets = st.builds(SlaveSet, ids, st.lists(ids, min_size=1, max_size=40).map(tuple))
contacts = st.builds(
    Contact, st.lists(triangles, max_size=5).map(tuple), st.lists(slave_sets, max_size=3).map(tuple)
)
initials = st.builds(
    Initial, ids, st.one_of(st.tuples(reals, reals, reals), st.tuples(*[reals] * 6))
)


def _maybe(strategy):
    return st.one_of(st.none(), strategy)


def _some(strategy, n=5):
    return st.lists(strategy, max_size=n).map(tuple)


decks = st.builds(
    Deck,
    title=_maybe(st.builds(Title, st.lists(title_lines, max_size=4).map("\n".join))),
    parameters=_maybe(parameters()),
    materials=_some(materials),
    pdmp=_some(pdmps, 3),
    body=_maybe(st.builds(Body, reals, reals, reals)),
    trace=_maybe(st.builds(Trace, st.lists(ids, min_size=1, max_size=30).map(tuple))),
    nodes=_some(nodes, 20),
    elements=_some(elements),
    masses=_some(masses),
    rbels=_some(rbels),
    boundaries=_some(boundaries),
    contacts=_some(contacts, 2),
    initials=_some(initials),
    usrfrc=_some(st.builds(Usrfrc, st.lists(specs, min_size=1, max_size=3).map(tuple)), 2),
    wallmat=_maybe(
        st.lists(
            st.builds(WallMat, ids, positive, st.floats(-0.999, 0.499), nonneg),
            min_size=1,
            max_size=3,
        ).map(tuple)
    ),
).filter(lambda d: format_deck(d).strip())


def _same(parsed: Deck, deck: Deck) -> bool:
    return strip_positions(parsed) == strip_positions(deck)


def _same_bits(a, b) -> bool:
    """Equal, and floats equal bit for bit (so -0.0 != 0.0)."""
    if isinstance(a, float):
        return isinstance(b, float) and math.copysign(1, a) == math.copysign(1, b) and a == b
    if isinstance(a, tuple):
        return len(a) == len(b) and all(_same_bits(x, y) for x, y in zip(a, b, strict=True))
    if hasattr(a, "__dataclass_fields__"):
        return all(_same_bits(getattr(a, f), getattr(b, f)) for f in a.__dataclass_fields__)
    return a == b


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(decks)
def test_format_then_parse_gives_the_same_cards(deck):
    parsed = parse_deck(format_deck(deck))
    assert _same(parsed, deck)
    assert _same_bits(strip_positions(parsed), strip_positions(deck))


# -- the same cards, written in other legal forms ------------------------------------------------

_CANONICAL = {
    "TITLE": "titl",
    "PARAMETERS": "para",
    "MATID": "mati",
    "PDMP": "pdmp",
    "BODY": "body",
    "TRACE": "trac",
    "NODE COORDINATES": "node",
    "ELEMENTS": "elem",
    "MASS": "mass",
    "RBEL": "rbel",
    "BOUNDARY CONDITIONS": "boun",
    "CONTACT": "cont",
    "INITIAL": "init",
    "USRFRC": "usrf",
}
_NUMBER = re.compile(r"(?<![\w.])([+-]?\d[\d.]*)(e)([+-]?\d+)")


@st.composite
def restyled(draw, text: str) -> str:
    """``text`` with keywords shortened or re-cased, separators, exponents and comments varied."""
    out = []
    in_text_card = False
    for line in text.split("\n"):
        if in_text_card and line != "END":
            pass  # a TITLE line or USRFRC spec: only a comment may be added
        elif line in _CANONICAL:
            short = _CANONICAL[line]
            word = draw(
                st.sampled_from(
                    [line, line.lower(), short, short.upper(), short.capitalize() + "xyz"]
                )
            )
            in_text_card = line in ("TITLE", "USRFRC")
            line = word
        elif line == "END":
            line = draw(st.sampled_from(["END", "end", "  End"]))
            in_text_card = False
        elif not in_text_card and not line.startswith("$"):
            sep = draw(st.sampled_from([" ", ", ", ",", "\t", "   ", " ,"]))
            line = (
                line.replace(" ", sep)
                if not line.endswith("&")
                else line[:-2].replace(" ", sep) + draw(st.sampled_from([" &", ", &", "&"]))
            )
            line = _NUMBER.sub(lambda m: m[1] + draw(st.sampled_from("eEdD")) + m[3], line)
        if draw(st.booleans()):
            line += " $ " + draw(st.text(text_chars, max_size=8))
        out.append(line)
        if draw(st.integers(0, 9)) == 0:
            out.append(draw(st.sampled_from(["", "$", "   ", "$ note & END"])))
    return "\n".join(out)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data(), decks)
def test_other_legal_forms_give_the_same_cards(data, deck):
    text = data.draw(restyled(format_deck(deck)))
    assert _same(parse_deck(text), deck)


def test_write_deck_is_atomic_and_round_trips(tmp_path):
    deck = Deck(body=Body(0.0, -386.1, 0.0), trace=Trace((25, 26)))
    path = tmp_path / "out.inp"
    path.write_text("old contents")
    write_deck(deck, path)
    assert _same(parse_deck(path.read_text()), deck)
    assert [p.name for p in tmp_path.iterdir()] == ["out.inp"]  # no temporary file left


def test_writer_refuses_what_the_language_cannot_hold():
    for bad in (
        Deck(body=Body(math.inf, 0, 0)),
        Deck(title=Title("a\nEND")),
        Deck(title=Title("cost $5")),
        Deck(trace=Trace((1.5,))),
        Deck(usrfrc=(Usrfrc(("",)),)),
        Deck(usrfrc=(Usrfrc((" , ,",)),)),
        Deck(title=Title(",")),
        Deck(rbels=(Rbel(1, (), (2,)),)),
    ):
        with pytest.raises(ValueError):
            format_deck(bad)
