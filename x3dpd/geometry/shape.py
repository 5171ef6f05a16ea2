"""The description every analytic wall shape gives of itself (x3dpd.geometry.shapes).

Kept apart from the registry so that a shape module can import it while the registry imports
the shape modules.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

#: Largest number of nodes a shape may have (A and B).
MAX_SHAPE_NODES = 2


@dataclass(frozen=True)
class Shape:
    """One analytic wall shape (a module of x3dpd.geometry; see the module docstring).

    ``clearance(points (N, 3), radii (N,), ends (k, 3), params (P,))`` returns the gap of each
    sphere to the nearest part [length] (negative: overlap) and whether its centre is inside;
    ``volume(ends, params)`` [length^3]; ``extent(ends, params)`` the bounding box (lo, hi);
    ``mesh(ends, params, n)`` a closed triangulation (vertices, triangles) with ``n`` facets
    around, for the viewers and tests; ``describe(ends, params)`` its size in messages
    ("radius 0.2, length 0.263"); ``problem(ends, params)`` what makes the shape impossible
    (coinciding axis nodes ...), or None. ``ends`` holds the positions of the shape's nodes, in
    card order.
    """

    name: str                      # lower case: "cylinder"; its effect is "cylinder_contact"
    card: str                      # the deck keyword: "CYLINDER"
    node_fields: tuple[str, ...]   # ("NODE_A", "NODE_B"): one or two
    param_fields: tuple[str, ...]  # ("RADIUS",): lengths, each > 0
    part_names: tuple[str, ...]    # the contact entities one shape consists of
    locate_parts: object           # compiled, see the module docstring
    clearance: Callable
    volume: Callable
    extent: Callable
    mesh: Callable
    describe: Callable
    problem: Callable
    #: edges (E, 2) into ``mesh(ends, params, n)``'s vertices that the viewers draw as its
    #: outline; None: the mesh's creases (a cylinder's rims). A smooth shape has none and
    #: names its own (a capsule: where the hemispheres meet the bore)
    outline: Callable | None = None
    #: for a shape whose particles sit each alone in a cell no other reaches (a drilled
    #: plate's holes): ``cells(points (N, 3), ends, params)`` -> (N, k) int, the cell of each
    #: point; a set of such walls has no pair contacts, and two particles in one cell are
    #: refused. None: the particles share the cavity
    cells: Callable | None = None
    #: ``constants(ends, params)`` -> floats the locator reads after the card's lengths,
    #: ``params[c, len(param_fields):]``: computed once by the model builder from the deck's
    #: geometry, so only for a wall that never turns (the builder refuses one on a body free
    #: to turn). None: the locator reads the card's lengths only
    constants: Callable | None = None
    #: how many floats ``constants`` returns
    n_constants: int = 0
    #: compiled ``clear_of(x, na, nb, params, c, px, py, pz, r) -> bool``: True only where no
    #: part can touch the sphere (every part's overlap from ``locate_parts`` <= 0, proved in
    #: floating point, not only in exact arithmetic), cheaper than locating the parts; the step
    #: loop then skips a sphere whose parts' contacts are all closed. None: always locate
    clear_of: object | None = None
    #: how messages name the nodes, in card order, and all of them
    node_words: tuple[str, ...] = ("axis node A", "axis node B")
    nodes_word: str = "axis nodes"
    module: str = ""               # the defining module (set by the registry)
    doc: str = ""                  # one line for docs and messages

    @property
    def key(self) -> str:
        """The four letters X3D reads of a keyword."""
        return self.card[:4]

    @property
    def effect(self) -> str:
        return f"{self.name}_contact"

    @property
    def parts(self) -> int:
        return len(self.part_names)

    @property
    def fields(self) -> tuple[str, ...]:
        """A record's fields: SET, the nodes, the parameters."""
        return ("SET",) + self.node_fields + self.param_fields
