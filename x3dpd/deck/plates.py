"""The PLATES card built into a deck's cards: a multiple individual particle (MIP) damper's
drilled plates, one sphere per hole (report Section 11.2; the card: x3dpd.deck.plates_card).

:func:`expand_plates` turns each plate into

* two structural nodes A and B, RBEL slaves of the plate's ``master``: A the bottom centre of
  the grid's first hole, B its top, so B - A runs along the holes' axis over their length
  L = thickness + shim;
* a HOLES wall (x3dpd.geometry.holes) of CONTACT set ``set``: RADIUS hole / 2, PITCH pitch;
* one sphere per hole (the first PDMP card's radius and material), a CONTACT slave set.

Numbering: the plates' nodes follow PDMP NODLIM (plate 1's A and B are NODLIM + 1 and
NODLIM + 2, ...), NODLIM moves past them (on the PDMP card and the HOOKE and FRICTION records
that name its group), and the spheres follow, plate by plate, hole by hole: plate 1's first
sphere is node NODLIM + 2P + 1 for P plates (NODLIM as written). The grid (x3dpd.geometry.holes:
rows along e1, e2) holds ``cols`` holes per row, rows filled in turn (the last may be short),
centred on the plate's centre ``at`` -- by default the plates are stacked along the axis from
the master node, an end plate before each. A sphere starts on its hole's axis: resting on the
bottom (``start=bottom``, the default), in the middle, at the top, or (``random``) anywhere
along its free length L - 2R, at rest. ``lumped=yes`` builds one hole for all of a plate's
holes: its sphere has the mass, moduli and weight of ``holes`` spheres (every modulus and the
plate's WALLMAT modulus and HOOKE stiffness scaled with them), which moves exactly as each of
``holes`` alike holes whose spheres start alike (Hertz's and HOOKE's forces are proportional to
the moduli and the stiffness: the same acceleration at every approach).

A PLATES deck's particles are its plates' spheres: the deck may not have particles of its own
and has one PDMP card. Every error is a DeckError at the plate's record or key.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from x3dpd.deck.cards import AnalyticWall, Contact, Deck, Node, Pdmp, Rbel, SlaveSet, Trace
from x3dpd.deck.plates_card import CARD, Plate, parse_plates
from x3dpd.errors import DeckError, InputError, Pos
from x3dpd.geometry.holes import grid_axes
from x3dpd.materials import in_units

__all__ = [
    "expand_plates",
    "grid_shape",
    "plate_layout",
    "plated_deck",
    "plates_from_specs",
    "sphere_ids",
]


def grid_shape(plate: Plate) -> tuple[int, int]:
    """(cols, rows) of a plate's grid (``lumped``: one hole)."""
    n = 1 if plate.lumped else plate.holes
    cols = min(plate.cols or math.ceil(math.sqrt(n)), n)
    return cols, math.ceil(n / cols)


def plate_layout(plate: Plate, bottom: np.ndarray, axis: int):
    """(A, B, hole centres (N, 3) at the holes' bottom) of a plate whose centre at its holes'
    bottom is ``bottom``, holes along coordinate ``axis`` (1-3)."""
    u = np.eye(3)[axis - 1]
    _, e1, e2 = grid_axes(np.zeros(3), u)
    cols, rows = grid_shape(plate)
    a = bottom - 0.5 * plate.pitch * ((cols - 1) * e1 + (rows - 1) * e2)
    k = np.arange(1 if plate.lumped else plate.holes)
    centres = a + plate.pitch * ((k % cols)[:, None] * e1 + (k // cols)[:, None] * e2)
    return a, a + plate.length * u, centres


def sphere_ids(deck: Deck) -> list[tuple[int, int]]:
    """(first, last) sphere node id of each plate of an unexpanded deck's PLATES card."""
    nodlim = deck.pdmp[0].nodlim
    first = nodlim + 2 * len(deck.plates) + 1
    out = []
    for p in deck.plates:
        n = 1 if p.lumped else p.holes
        out.append((first, first + n - 1))
        first += n
    return out


def plates_from_specs(specs, what: str = "--plates") -> tuple[Plate, ...]:
    """PLATES records from ``key=value`` lines (``x3dpd fill --plates``); an InputError naming
    the line and the word. The k-th record's position is line k (a later DeckError of
    :func:`expand_plates` names its line)."""
    out = []
    for k, spec in enumerate(specs, 1):
        try:
            out += parse_plates([(spec, k, 1)])
        except DeckError as exc:
            raise InputError(f"{what} {spec!r}: {exc.message} (at column {exc.column})") from None
    return tuple(out)


def plated_deck(template: Deck, plates, *, radius=None, material=None) -> Deck:
    """The structure of ``template`` (its particles, their slave sets, INITIAL and TRACE
    entries dropped) with the PLATES card ``plates``, not yet built (:func:`expand_plates`;
    the writer writes the card as it is). The spheres take the template's first PDMP card,
    or ``material`` (a library name or Material, in the template's units), and ``radius``;
    TRACE keeps the template's structural nodes and adds each plate's first sphere."""
    pd = template.pdmp[0] if template.pdmp else None
    if pd is None:
        if material is None or radius is None:
            raise InputError(
                f"{template.path}: no PDMP card: give the spheres' material and "
                "radius (--material, --radius)"
            )
        nodlim = max((n.nid for n in template.nodes), default=0)
        pd = Pdmp(nodlim, float(radius), 0.0, 0.0, 0.0, 0.0, 1.0, 0.0)
    if material is not None:
        pd = replace(pd, **in_units(material, template.units).pdmp_fields())
    if radius is not None:
        pd = replace(pd, rzero=float(radius))
    keep = {n.nid for n in template.nodes if n.nid <= pd.nodlim}
    contacts = []
    for c in template.contacts:
        sets = tuple(s for s in c.slaves if all(k in keep for k in s.nodes))
        if c.triangles or sets:
            contacts.append(replace(c, slaves=sets))
    deck = replace(
        template,
        pdmp=(pd,),
        plates=tuple(plates),
        contacts=tuple(contacts),
        nodes=tuple(n for n in template.nodes if n.nid in keep),
        initials=tuple(i for i in template.initials if i.nid in keep),
    )
    traced = [k for k in (template.trace.nodes if template.trace else ()) if k in keep]
    return replace(deck, trace=Trace(tuple(traced + [a for a, _ in sphere_ids(deck)])))


def expand_plates(deck: Deck) -> Deck:
    """``deck`` with its PLATES card built into nodes, RBEL slaves, HOLES walls and spheres
    (module docstring); a deck without one as it is."""
    if not deck.plates:
        return deck
    plates = deck.plates
    _check_deck(deck)
    pd = deck.pdmp[0]
    radius = pd.rzero
    nodes = {n.nid: n for n in deck.nodes}
    axis_default = _drive_axis(deck)
    taken = {t.set_id for c in deck.contacts for t in c.triangles}
    taken |= {s.set_id for c in deck.contacts for s in c.slaves}
    taken |= {w.set_id for w in deck.analytic_walls or ()}
    seen: dict[int, Pos] = {}
    top: np.ndarray | None = None
    new_nodes, walls, sets, slaves = [], [], [], {}
    nid = pd.nodlim + 1
    spheres = []
    for plate in plates:
        _check_plate(deck, plate, radius, nodes, taken, seen)
        axis = plate.axis or axis_default
        if axis is None:
            raise _error(
                deck,
                plate.pos,
                "give axis= (x, y or z): the deck has no USRFRC "
                "drive whose DOF would give the holes' axis",
            )
        u = np.eye(3)[axis - 1]
        master = nodes[plate.master]
        if plate.at is not None:
            bottom = np.array(plate.at, dtype=float)
        else:
            start = np.array([master.x, master.y, master.z]) if top is None else top
            bottom = start + plate.end * u
        a, b, centres = plate_layout(plate, bottom, axis)
        top = bottom + plate.length * u
        new_nodes += [
            Node(nid, *map(float, a), plate.pos),
            Node(nid + 1, *map(float, b), plate.pos),
        ]
        slaves.setdefault(plate.master, []).extend([nid, nid + 1])
        walls.append(
            AnalyticWall(
                "holes",
                plate.set_id,
                (nid, nid + 1),
                (0.5 * plate.hole, plate.pitch),
                plate.pos,
                (plate.where("master"),) * 2,
            )
        )
        spheres.append((plate, centres + _starts(plate, radius, len(centres))[:, None] * u))
        nid += 2
    nodlim = nid - 1
    for plate, where in spheres:
        ids = tuple(range(nid, nid + len(where)))
        new_nodes += [Node(i, *map(float, p), plate.pos) for i, p in zip(ids, where)]
        sets.append(SlaveSet(plate.set_id, ids, (plate.pos,) * len(ids), plate.pos))
        nid += len(ids)
    return _lumped(
        replace(
            deck,
            plates=None,
            pdmp=(replace(pd, nodlim=nodlim),),
            hooke=_renamed(deck.hooke, pd.nodlim, nodlim),
            friction=_renamed(deck.friction, pd.nodlim, nodlim),
            nodes=deck.nodes + tuple(new_nodes),
            rbels=_with_slaves(deck.rbels, slaves),
            analytic_walls=(deck.analytic_walls or ()) + tuple(walls),
            contacts=_with_sets(deck.contacts, sets),
        ),
        plates,
    )


def _check_deck(deck: Deck) -> None:
    first = deck.plates[0]
    if len(deck.pdmp) != 1:
        raise _error(
            deck,
            first.pos,
            f"the spheres' material and radius are the PDMP card's: "
            f"a PLATES deck needs one PDMP card; it has {len(deck.pdmp)}",
        )
    nodlim = deck.pdmp[0].nodlim
    own = [n for n in deck.nodes if n.nid > nodlim]
    if own:
        raise _error(
            deck,
            first.pos,
            f"node {own[0].nid} is above PDMP NODLIM {nodlim}: a "
            "PLATES deck's particles are its plates' spheres (give NODLIM the "
            "structure's last node)",
        )
    lumped = {p.lumped for p in deck.plates}
    if lumped == {True} and len({p.holes for p in deck.plates}) > 1:
        raise _error(
            deck,
            first.where("lumped"),
            "lumped plates share the PDMP card's "
            "scaled material: give every plate the same number of holes",
        )
    if len(lumped) > 1:
        raise _error(
            deck,
            first.where("lumped"),
            "lump every plate or none (their spheres share one PDMP card)",
        )


def _check_plate(deck, plate: Plate, radius: float, nodes, taken, seen) -> None:
    """A plate's own numbers against the spheres' radius and the deck's nodes and sets."""
    free = plate.thickness + plate.shim - 2.0 * radius
    if not free > 0.0:
        raise _error(
            deck,
            plate.where("shim"),
            f"free length = thickness + shim - sphere "
            f"diameter = {plate.thickness:g} + {plate.shim:g} - {2.0 * radius:g} = "
            f"{free:.6g}: it must be > 0 (the sphere must fit its hole)",
        )
    if plate.shim < 0.0:
        raise _error(deck, plate.where("shim"), f"shim must be >= 0; got {plate.shim:g}")
    if not plate.hole > 2.0 * radius:
        raise _error(
            deck,
            plate.where("hole"),
            f"hole diameter {plate.hole:g} must exceed the "
            f"sphere's diameter {2.0 * radius:g} (PDMP RZERO {radius:g})",
        )
    if not plate.pitch > plate.hole:
        raise _error(
            deck,
            plate.where("pitch"),
            f"pitch {plate.pitch:g} must exceed the hole "
            f"diameter {plate.hole:g}: holes wider than the pitch overlap",
        )
    cols, rows = grid_shape(replace(plate, lumped=False))
    span = ((cols - 1) * plate.pitch + plate.hole, (rows - 1) * plate.pitch + plate.hole)
    if span[0] > plate.size[0] or span[1] > plate.size[1]:
        raise _error(
            deck,
            plate.where("size"),
            f"{plate.holes} holes of diameter "
            f"{plate.hole:g} at pitch {plate.pitch:g} ({cols} x {rows}) span "
            f"{span[0]:.6g} x {span[1]:.6g}: larger than the plate, "
            f"{plate.size[0]:g} x {plate.size[1]:g}",
        )
    if plate.master not in nodes:
        raise _error(
            deck,
            plate.where("master"),
            f"master node {plate.master} is not defined (NODE COORDINATES)",
        )
    if plate.set_id in taken or plate.set_id in seen:
        line = seen[plate.set_id].line if plate.set_id in seen else 0
        raise _error(
            deck,
            plate.where("set"),
            f"set {plate.set_id} is already used "
            + (
                f"by the plate at line {line}"
                if line
                else "by the deck's CONTACT card or analytic walls"
            )
            + ": each plate needs a set of its own",
        )
    seen[plate.set_id] = plate.pos


def _starts(plate: Plate, radius: float, n: int) -> np.ndarray:
    """Each sphere's centre above its hole's bottom, along the axis [length]."""
    lo, hi = radius, plate.length - radius
    if plate.start == "random":
        return lo + (hi - lo) * np.random.default_rng(plate.seed).random(n)
    return np.full(n, {"bottom": lo, "middle": 0.5 * (lo + hi), "top": hi}[plate.start])


def _drive_axis(deck: Deck) -> int | None:
    """The DOF 1-3 of the deck's first built-in USRFRC law, or None."""
    for card in deck.usrfrc:
        for spec in card.specs:
            head, _, body = spec.partition(":")
            if head.strip().lower() in ("sine", "sweep", "step", "constant", "random"):
                for pair in body.split(","):
                    key, _, value = pair.partition("=")
                    if key.strip().lower() == "dof" and value.strip() in ("1", "2", "3"):
                        return int(value)
    return None


def _renamed(records, old: int, new: int):
    """HOOKE or FRICTION records with the PDMP group's NODLIM ``old`` renamed ``new``."""
    if records is None:
        return None
    return tuple(replace(r, nodlim=new) if r.nodlim == old else r for r in records)


def _with_slaves(rbels, slaves: dict[int, list[int]]):
    """The RBEL records with the plates' nodes added to their masters' bodies (a new record
    for a master that had none)."""
    out, done = [], set()
    for r in rbels:
        if r.master in slaves and r.master not in done:
            extra = tuple(slaves[r.master])
            r = replace(
                r,
                slaves=r.slaves + extra,
                slave_positions=r.slave_positions + (r.pos,) * len(extra)
                if r.slave_positions
                else (),
            )
            done.add(r.master)
        out.append(r)
    for master, ids in slaves.items():
        if master not in done:
            out.append(Rbel(master, (1, 2, 3, 4, 5, 6), tuple(ids)))
    return tuple(out)


def _with_sets(contacts, sets):
    if contacts:
        first = contacts[0]
        return (replace(first, slaves=first.slaves + tuple(sets)),) + contacts[1:]
    return (Contact((), tuple(sets)),)


def _lumped(deck: Deck, plates) -> Deck:
    """``lumped`` plates: the spheres' mass and moduli, the plates' WALLMAT moduli and the
    HOOKE stiffness scaled by the plates' hole count (module docstring)."""
    if not plates[0].lumped:
        return deck
    n = float(plates[0].holes)
    pd = deck.pdmp[0]
    pd = replace(
        pd,
        prho=pd.prho * n,
        e0=pd.e0 * n,
        e1=pd.e1 * n,
        extra_terms=tuple((e * n, t) for e, t in pd.extra_terms),
    )
    ours = {p.set_id for p in plates}
    wallmat = deck.wallmat and tuple(
        replace(w, e=w.e * n) if w.set_id in ours else w for w in deck.wallmat
    )
    hooke = deck.hooke and tuple(replace(h, kn=h.kn * n) for h in deck.hooke)
    return replace(deck, pdmp=(pd,), wallmat=wallmat, hooke=hooke)


def _error(deck: Deck, at: Pos, message: str) -> DeckError:
    return DeckError(message, deck.path, at.line, at.column, CARD)
