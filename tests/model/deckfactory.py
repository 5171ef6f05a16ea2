"""Small hand-made decks for the model tests, built directly as typed cards.

``cube_deck()`` is a unit-cube cavity (corner nodes 1-8, rigidly linked to master node 9 at the
origin, which sits on a spring to ground along x) holding particles from node 10 on. Every record
has its own line number (listed below) so that error tests can check positions.
"""

from __future__ import annotations

from dataclasses import replace

from x3dpd.deck.cards import (
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
    Pos,
    Rbel,
    SlaveSet,
    Trace,
    Triangle,
)

LINE_PARAMETERS = 2
LINE_MATERIAL = 10
LINE_PDMP = 20
LINE_BODY = 25
LINE_ELEMENT = 30
LINE_MASS = 40
LINE_RBEL = 50
LINE_BOUNDARY = 60
LINE_TRIANGLE = 70  # triangle k (0-based) is on line 70 + k
LINE_SLAVES = 90
LINE_NODE = 100  # node id n is on line 100 + n

CORNERS = {
    1: (0, 0, 0),
    2: (1, 0, 0),
    3: (1, 1, 0),
    4: (0, 1, 0),
    5: (0, 0, 1),
    6: (1, 0, 1),
    7: (1, 1, 1),
    8: (0, 1, 1),
}
#: The twelve triangles, all wound so that (p1-p0) x (p2-p0) points inward, with that normal.
TRIANGLES = (
    ((1, 2, 3), (0, 0, 1)),
    ((1, 3, 4), (0, 0, 1)),  # z = 0, wound +z (inward)
    ((5, 7, 6), (0, 0, -1)),
    ((5, 8, 7), (0, 0, -1)),  # z = 1, wound -z (inward)
    ((1, 6, 2), (0, 1, 0)),
    ((1, 5, 6), (0, 1, 0)),  # y = 0, wound +y (inward)
    ((4, 3, 7), (0, -1, 0)),
    ((4, 7, 8), (0, -1, 0)),  # y = 1, wound -y (inward)
    ((1, 4, 8), (1, 0, 0)),
    ((1, 8, 5), (1, 0, 0)),  # x = 0, wound +x (inward)
    ((2, 6, 7), (-1, 0, 0)),
    ((2, 7, 3), (-1, 0, 0)),
)  # x = 1, wound -x (inward)
MASTER = 9
RADIUS = 0.1
DENSITY = 7.0
KX = 100.0
SCALE = 2.0
C = 0.5
MASTER_MASS = 1.5


def pos(line: int, column: int = 1) -> Pos:
    return Pos(line, column)


def node(nid: int, x: float, y: float, z: float) -> Node:
    return Node(nid, float(x), float(y), float(z), pos(LINE_NODE + nid))


def triangles(flip=(), set_id: int = 1, first_line: int = LINE_TRIANGLE):
    """The cube's triangles, with those numbered in ``flip`` (0-based) wound the other way."""
    out = []
    for k, ((a, b, c), _) in enumerate(TRIANGLES):
        nodes = (a, c, b) if k in flip else (a, b, c)
        out.append(Triangle(set_id, nodes, pos(first_line + k)))
    return tuple(out)


def slave_set(ids, set_id: int = 1, line: int = LINE_SLAVES) -> SlaveSet:
    ids = tuple(ids)
    return SlaveSet(set_id, ids, tuple(pos(line, 5 + 4 * k) for k in range(len(ids))), pos(line))


def cube_deck(particles=((0.5, 0.5, 0.5),), flip=(), **over) -> Deck:
    """The unit-cube deck with the given particle centres (nodes 10, 11, ...)."""
    ids = tuple(range(10, 10 + len(particles)))
    nodes = [node(n, *xyz) for n, xyz in CORNERS.items()]
    nodes.append(node(MASTER, 0, 0, 0))
    nodes += [node(n, *xyz) for n, xyz in zip(ids, particles)]
    deck = Deck(
        path="cube.inp",
        parameters=Parameters(
            0.0, 1.0, 0.0, 1e-7, 1e-7, 0, 1e9, 0, 5, 0, 100, pos(LINE_PARAMETERS)
        ),
        materials=(Material(2, 1, 0.0, SCALE, KX, 0.0, 0.0, C, pos=pos(LINE_MATERIAL)),),
        pdmp=(Pdmp(MASTER, RADIUS, DENSITY, 0.3, 2.0e7, 0.0, 1.0, 0.0, pos=pos(LINE_PDMP)),),
        body=Body(0.0, -10.0, 0.0, pos(LINE_BODY)),
        nodes=tuple(nodes),
        elements=(Element(1, 2, (MASTER,), pos(LINE_ELEMENT)),),
        masses=(Mass(MASTER, MASTER_MASS, 0.1, 0.2, 0.3, pos(LINE_MASS)),),
        rbels=(
            Rbel(
                MASTER,
                (1, 2, 3, 4, 5, 6),
                tuple(range(1, 9)),
                tuple(pos(LINE_RBEL, 10 + 3 * k) for k in range(8)),
                pos(LINE_RBEL),
            ),
        ),
        boundaries=(Boundary(1, MASTER, 1, (2, 3, 4, 5, 6), pos(LINE_BOUNDARY)),),
        contacts=(Contact(triangles(flip), (slave_set(ids),) if ids else ()),),
    )
    return replace(deck, **over)


def with_nodes(deck: Deck, *extra: Node) -> Deck:
    return replace(deck, nodes=deck.nodes + tuple(extra))


__all__ = [
    "Body",
    "Boundary",
    "Contact",
    "Deck",
    "Element",
    "Initial",
    "Mass",
    "Material",
    "Node",
    "Parameters",
    "Pdmp",
    "Pos",
    "Rbel",
    "SlaveSet",
    "Trace",
    "Triangle",
    "replace",
]
