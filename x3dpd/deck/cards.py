"""Typed cards of an X3D deck: one frozen dataclass per card.

The parser (``parser.py``) produces a :class:`Deck`; the model builder (``x3dpd.model.build``)
checks cross references and turns it into arrays. No physics lives here.

Every record keeps the :class:`Pos` of its first token so that later checks (an undefined node,
a duplicate id) can still point at ``file:line:column``. Lists of node ids keep one ``Pos`` per id.

Units are whatever consistent set the deck uses (the report's decks use inch, lbf, second, so mass
is lbf s^2/in). ``docs/deck-reference.md`` documents every field.
"""

from __future__ import annotations

from dataclasses import dataclass, field


# Positions are defined with the errors that report them (a lower layer than the deck language).
from x3dpd.errors import NOWHERE, Pos  # noqa: E402,F401
from x3dpd.deck.modal_card import Modal, ModalFile, ModalMode, ModalShape  # noqa: E402,F401
from x3dpd.deck.plates_card import Plate  # noqa: E402,F401
from x3dpd.deck.temperature_card import Temperature  # noqa: E402,F401


@dataclass(frozen=True)
class Title:
    """TITLE: free text, kept verbatim (lines joined with newlines)."""

    text: str
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Parameters:
    """PARAMETERS: TIME TMAX TREST DTMIN DTMAX INCR INCMAX IREST NINTPL ISTAT ITRAC.

    TIME start time [s]; TMAX end time [s]; TREST restart-dump interval [s] (0 = none);
    DTMIN, DTMAX time-step bounds [s] (a constant step DTMAX; a step chosen by accuracy between
    them when DTMIN < DTMAX, x3dpd.solver.variable_step); INCR starting increment;
    INCMAX maximum number of increments; IREST 1 = resume from the last restart dump;
    NINTPL, ISTAT kept for X3D compatibility (no effect); ITRAC trace output every ITRAC steps.
    """

    time: float
    tmax: float
    trest: float
    dtmin: float
    dtmax: float
    incr: int
    incmax: float
    irest: int
    nintpl: int
    istat: int
    itrac: int
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Material:
    """One MATID record (our field map, see deck reference). Type 1 = discrete spring-damper
    along the global axes (X3D's); our extensions: type 2 = spring-damper along the line between
    two nodes, type 3 = rotational spring-damper about the global axes.

    Fields: MID TYPE MASS SCALE KX KY KZ C  [EXTRA...]. ``mass`` is an element mass lumped onto the
    element's nodes, ``scale`` multiplies stiffness and damping. Type 1: ``kx, ky, kz`` are
    translational stiffnesses along global axes [force/length], ``c`` the viscous damping
    [force s/length] applied along each free translational direction. Type 2: ``kx`` the
    stiffness and ``c`` the damping along the element's line (``ky = kz = 0``). Type 3: ``kx, ky,
    kz`` rotational stiffnesses [force length/rad], ``c`` the rotational damping [force length
    s/rad] about each axis. ``extra`` keeps the remaining X3D fields verbatim.
    """

    mid: int
    mtype: int
    mass: float
    scale: float
    kx: float
    ky: float
    kz: float
    c: float
    extra: tuple[float, ...] = ()
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Pdmp:
    """PDMP (report Appendix B): NODLIM RZERO PRHO PPOI E0 E1 T1 PCOF VX0 VY0 VZ0.

    Particles are nodes NODLIM+1 ... (the next PDMP group's NODLIM, or the highest node).
    ``extra_terms`` holds further Maxwell pairs (E2, T2, E3, T3, ...) -- our extension.
    """

    nodlim: int
    rzero: float
    prho: float
    ppoi: float
    e0: float
    e1: float
    t1: float
    pcof: float
    vx0: float = 0.0
    vy0: float = 0.0
    vz0: float = 0.0
    extra_terms: tuple[tuple[float, float], ...] = ()
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Body:
    """BODY: body (gravity) acceleration vector [length/s^2] applied to every node with mass."""

    ax: float
    ay: float
    az: float
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Trace:
    """TRACE: node ids to write to the trace file, in this order."""

    nodes: tuple[int, ...]
    positions: tuple[Pos, ...] = ()
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Node:
    """One NODE COORDINATES record: node id and x, y, z [length]."""

    nid: int
    x: float
    y: float
    z: float
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Element:
    """One ELEMENTS record: element id, material id, one node (to ground) or two nodes."""

    eid: int
    mid: int
    nodes: tuple[int, ...]
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Mass:
    """One MASS record: node, translational mass, rotary inertias Ixx Iyy Izz."""

    nid: int
    mass: float
    ixx: float
    iyy: float
    izz: float
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Rbel:
    """One RBEL record: master node, DOF code (digits of 1..6, e.g. 123456), slave nodes."""

    master: int
    dofs: tuple[int, ...]
    slaves: tuple[int, ...]
    slave_positions: tuple[Pos, ...] = ()
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Boundary:
    """One BOUNDARY CONDITIONS record: first node, last node, increment, fixed DOFs (1..6)."""

    first: int
    last: int
    inc: int
    dofs: tuple[int, ...]
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Triangle:
    """One master triangle of a CONTACT card: set id and three node ids."""

    set_id: int
    nodes: tuple[int, int, int]
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class SlaveSet:
    """One slave record of a CONTACT card: set id and its particle node ids."""

    set_id: int
    nodes: tuple[int, ...]
    positions: tuple[Pos, ...] = ()
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Contact:
    """CONTACT: master triangles (first END block) and slave node sets (second END block)."""

    triangles: tuple[Triangle, ...]
    slaves: tuple[SlaveSet, ...]
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Initial:
    """One INITIAL record: node and velocity (vx, vy, vz) or (vx, vy, vz, wx, wy, wz)."""

    nid: int
    velocity: tuple[float, ...]
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Usrfrc:
    """USRFRC (our extension): force specs, one per record, same syntax as ``--usrfrc``."""

    specs: tuple[str, ...]
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Hooke:
    """One HOOKE record (our extension): the PDMP group starting after node ``nodlim`` uses the
    linear spring-dashpot normal law with stiffness ``kn`` [force/length] and restitution ``e``
    (x3dpd.physics.hooke)."""

    nodlim: int
    kn: float
    e: float
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Friction:
    """One FRICTION record (our extension): the PDMP group starting after node ``nodlim`` uses
    the tangential law ``law`` (``coulomb``, ``regularized`` or ``mindlin``,
    x3dpd.physics.tangential_laws) with static and kinetic friction coefficients ``mu_s``,
    ``mu_k`` (they replace the group's PCOF), and the rolling-resistance law ``roll``
    (``none`` or ``epsd``, x3dpd.physics.rolling) with coefficient ``mu_r``."""

    nodlim: int
    law: str
    mu_s: float
    mu_k: float
    roll: str = "none"
    mu_r: float = 0.0
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class WallMat:
    """One WALLMAT record (our extension): the walls of CONTACT set ``set_id`` (its triangles
    and its analytic walls) are elastic with Young's modulus ``e`` [force/length^2], Poisson's
    ratio ``nu`` and friction coefficient ``mu`` against the particles
    (x3dpd.physics.wall_material). Without a record a wall is rigid."""

    set_id: int
    e: float
    nu: float
    mu: float
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class AnalyticWall:
    """One record of an analytic wall shape's card (our extension; CYLINDER, CAPSULE ...,
    x3dpd.geometry.shapes): the cavity of CONTACT slave set ``set_id`` is bounded by a
    ``shape`` ("cylinder") on the node ids ``nodes`` with the lengths ``params``, both in the
    card's field order (CYLINDER: NODE_A NODE_B, RADIUS)."""

    shape: str
    set_id: int
    nodes: tuple[int, ...]
    params: tuple[float, ...]
    pos: Pos = NOWHERE
    positions: tuple[Pos, ...] = ()  # where each node id stands (for messages)


@dataclass(frozen=True)
class UnitRecord:
    """One record of an effect unit's own card (our extension; x3dpd.physics.effect_units):
    the values of the card's fields in order (a node field's an int: the node id)."""

    unit: str
    values: tuple[float | int, ...]
    pos: Pos = NOWHERE
    positions: tuple[Pos, ...] = ()  # where each value stands (for messages)


@dataclass(frozen=True)
class Units:
    """UNITS (our extension): the deck's unit system, ``LENGTH FORCE TIME`` (x3dpd.units)."""

    length: str = "in"
    force: str = "lbf"
    time: str = "s"
    pos: Pos = NOWHERE

    @property
    def system(self) -> tuple[str, str, str]:
        return (self.length, self.force, self.time)


@dataclass(frozen=True)
class Deck:
    """A whole parsed deck. Cards that may repeat are tuples, in file order."""

    path: str = "<deck>"
    title: Title | None = None
    parameters: Parameters | None = None
    materials: tuple[Material, ...] = ()
    pdmp: tuple[Pdmp, ...] = ()
    body: Body | None = None
    trace: Trace | None = None
    nodes: tuple[Node, ...] = ()
    elements: tuple[Element, ...] = ()
    masses: tuple[Mass, ...] = ()
    rbels: tuple[Rbel, ...] = ()
    boundaries: tuple[Boundary, ...] = ()
    contacts: tuple[Contact, ...] = ()
    initials: tuple[Initial, ...] = ()
    usrfrc: tuple[Usrfrc, ...] = field(default_factory=tuple)
    hooke: tuple[Hooke, ...] | None = None  # None: no HOOKE card
    wallmat: tuple[WallMat, ...] | None = None  # None: no WALLMAT card (rigid walls)
    friction: tuple[Friction, ...] | None = None  # None: no FRICTION card
    #: records of the analytic wall cards in file order (None: no such card)
    analytic_walls: tuple[AnalyticWall, ...] | None = None
    units: Units | None = None
    modal: Modal | None = None  # MODAL card (x3dpd.deck.modal_card); None: no modal structure
    #: PLATES card (x3dpd.deck.plates_card) not yet built into the deck's cards; a deck read
    #: from a file has it built (x3dpd.deck.plates.expand_plates) and None here
    plates: tuple[Plate, ...] | None = None
    #: records of the effect units' own cards in file order (None: no such card)
    unit_records: tuple[UnitRecord, ...] | None = None
    #: TEMPERATURE card (x3dpd.deck.temperature_card); None: the deck's numbers as they stand
    temperature: Temperature | None = None

    @property
    def unit_system(self) -> tuple[str, str, str] | None:
        """The (length, force, time) units of its UNITS card, None without one (inch-lbf-s:
        x3dpd.units.DEFAULT)."""
        return self.units.system if self.units is not None else None
