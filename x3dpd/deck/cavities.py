"""Several identical cavities on a structure: copies of a deck's cavity, each with the same
particles (``x3dpd design``'s ``cavities`` key, docs/design.md "Several cavities").

:func:`with_cavities` turns a deck with one filled cavity into a deck with ``count`` of them.
A copy is the cavity rigidly moved: its wall nodes (the CONTACT triangles' nodes of the set,
or an analytic wall's axis nodes) become new structural nodes translated by the copy's offset,
RBEL slaves of a master node (the original cavity's master, or the one ``masters`` names for
that copy), with the originals' BOUNDARY DOFs and the MASS of the original's slave nodes (a
housing's mass goes with its copy; the master's own mass is the structure's and is not
copied). The copy has its own CONTACT set (and its WALLMAT record, analytic wall), and its own
particles: the original cavity's, moved by the same offset, with their INITIAL velocities. So
cavity k holds exactly the particles of cavity 0, placed alike.

Offsets: copy k on master M sits at x(M) - x(M0) + j * ``spacing``, where M0 is the original's
master and j counts the earlier cavities on M (the original is cavity 0 on M0). Particles of
different cavities never touch (x3dpd.geometry.cells pairs a cavity's own particles only), so
the spacing matters for the picture and, when the master rotates, for the moment arm.

Node ids: the copies' wall nodes take NODLIM+1 ..., the first PDMP card's NODLIM grows by their
number and the particles follow (HOOKE and FRICTION records of that group follow its NODLIM;
INITIAL and TRACE are renumbered; a USRFRC spec naming a particle node is refused). One PDMP
group only.
"""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np

from x3dpd.deck.cards import (
    Boundary,
    Contact,
    Deck,
    Node,
    Rbel,
    SlaveSet,
    Trace,
    Triangle,
)
from x3dpd.errors import InputError

#: Space left between neighbouring copies, as a fraction of the cavity's extent.
SPACING_GAP = 0.25


def cavity_set(deck: Deck, set_id: int | None = None) -> int:
    """The CONTACT set id of the cavity (default: the first triangle's set, else the first
    analytic wall's)."""
    tris = [t for c in deck.contacts for t in c.triangles]
    walls = list(deck.analytic_walls or ())
    have = sorted({t.set_id for t in tris} | {w.set_id for w in walls})
    if set_id is None:
        if not have:
            raise InputError(f"{deck.path}: no cavity (no CONTACT triangles, no analytic wall)")
        return tris[0].set_id if tris else walls[0].set_id
    if int(set_id) not in have:
        raise InputError(f"{deck.path}: no CONTACT set {set_id} (sets: {have})")
    return int(set_id)


def _wall_nodes(deck: Deck, sid: int) -> list[int]:
    """The structural nodes that bound cavity ``sid``, in first-use order."""
    ids = [k for c in deck.contacts for t in c.triangles if t.set_id == sid for k in t.nodes]
    ids += [k for w in deck.analytic_walls or () if w.set_id == sid for k in w.nodes]
    return list(dict.fromkeys(ids))


def cavity_master(deck: Deck, set_id: int | None = None) -> int:
    """The master node of the rigid body (RBEL) the cavity's walls belong to."""
    sid = cavity_set(deck, set_id)
    body = {k: rb.master for rb in deck.rbels for k in (rb.master, *rb.slaves)}
    owners = {body.get(k) for k in _wall_nodes(deck, sid)}
    if len(owners) != 1 or None in owners:
        raise InputError(
            f"{deck.path}: cavity set {sid}: its wall nodes are not all in one "
            "rigid body (RBEL) -- several cavities need the cavity on a master node"
        )
    return owners.pop()


def check_masters(deck: Deck, masters, set_id: int | None = None) -> None:
    """Raise InputError unless ``masters`` can carry copies of cavity ``set_id``: the first is
    the cavity's own master, and each is a node of the deck, a structural one (not beyond the
    first PDMP card's NODLIM) and no other rigid body's slave."""
    masters = tuple(masters)
    master0 = cavity_master(deck, set_id)
    if masters[0] != master0:
        raise InputError(
            f"masters: the first is the deck's own cavity's master node {master0}, got {masters[0]}"
        )
    ids = {n.nid for n in deck.nodes}
    nodlim = deck.pdmp[0].nodlim if deck.pdmp else max(ids, default=0)
    in_body = {k: rb.master for rb in deck.rbels for k in (rb.master, *rb.slaves)}
    for m in masters:
        if m not in ids:
            raise InputError(f"masters: node {m} is not a node of {deck.path}")
        if m > nodlim or in_body.get(m, m) != m:
            raise InputError(
                f"masters: node {m} is not a structural node (<= NODLIM {nodlim}) "
                "that may be a rigid body's master"
            )


def cavity_extent(deck: Deck, set_id: int | None = None) -> np.ndarray:
    """The cavity's bounding-box size (x, y, z) [length]: of its triangles' nodes, or of an
    analytic wall's axis widened by its radius on every side (a capsule's caps included)."""
    sid = cavity_set(deck, set_id)
    xyz = {n.nid: np.array([n.x, n.y, n.z]) for n in deck.nodes}
    pts = [xyz[k] for c in deck.contacts for t in c.triangles if t.set_id == sid for k in t.nodes]
    for w in deck.analytic_walls or ():
        if w.set_id == sid:
            radius = float(w.params[0])
            pts += [xyz[k] + s * radius for k in w.nodes[:2] for s in (-1.0, 1.0)]
    pts = np.array(pts)
    return pts.max(axis=0) - pts.min(axis=0)


def default_spacing(deck: Deck, set_id: int | None, drive_axis: int) -> tuple[float, ...]:
    """Side by side: along the first axis that is neither the drive's nor gravity's (the BODY
    card's largest component), the cavity's extent there plus :data:`SPACING_GAP` of it."""
    gravity = None
    if deck.body is not None and any((deck.body.ax, deck.body.ay, deck.body.az)):
        gravity = int(np.argmax(np.abs([deck.body.ax, deck.body.ay, deck.body.az])))
    free = [k for k in range(3) if k not in (drive_axis, gravity)] or [
        k for k in range(3) if k != drive_axis
    ]
    out = np.zeros(3)
    out[free[0]] = cavity_extent(deck, set_id)[free[0]] * (1.0 + SPACING_GAP)
    return tuple(float(v) for v in out)


def _fixed_dofs(deck: Deck) -> dict[int, set[int]]:
    out: dict[int, set[int]] = {}
    for rec in deck.boundaries:
        if rec.inc > 0:
            for nid in range(rec.first, rec.last + 1, rec.inc):
                out.setdefault(nid, set()).update(rec.dofs)
    return out


# Over 80 lines: a cavity's nodes, walls, particles and records copied with one renumbering map.
def with_cavities(
    deck: Deck,
    count: int,
    *,
    set_id: int | None = None,
    masters: tuple[int, ...] | None = None,
    spacing: tuple[float, float, float] = (0.0, 0.0, 1.0),
) -> Deck:
    """``deck`` with ``count`` identical cavities (module doc): cavity 0 is the deck's own (set
    ``set_id``), cavity k >= 1 a copy on master ``masters[k]`` (default: all on the original's
    master), each holding the original's particles moved alike. Raises InputError when the
    deck has more than one PDMP group, the cavity is not on a master node, or a master named
    is not a structural node outside every other rigid body."""
    if count < 1:
        raise InputError(f"cavities = {count}: expected 1 or more")
    if count == 1:
        return deck
    if len(deck.pdmp) != 1:
        raise InputError(
            f"{deck.path}: several cavities need one PDMP card (the deck has {len(deck.pdmp)})"
        )
    sid = cavity_set(deck, set_id)
    master0 = cavity_master(deck, sid)
    masters = tuple(masters) if masters else (master0,) * count
    if len(masters) < count:
        raise InputError(
            f"cavities = {count}: masters lists {len(masters)} master nodes; give one per cavity"
        )
    check_masters(deck, masters, sid)
    nodlim = deck.pdmp[0].nodlim
    named = [
        int(k)
        for card in deck.usrfrc
        for spec in card.specs
        for k in re.findall(r"\bnode=(\d+)", spec)
    ]
    if any(k > nodlim for k in named):
        raise InputError(
            f"{deck.path}: USRFRC names particle node {max(named)}; the particles "
            "are renumbered when the cavity is copied"
        )
    xyz = {n.nid: np.array([n.x, n.y, n.z]) for n in deck.nodes}
    walls = _wall_nodes(deck, sid)
    slaves0 = {s for rb in deck.rbels if rb.master == master0 for s in rb.slaves}
    fixed = _fixed_dofs(deck)
    mass_of = {m.nid: m for m in deck.masses}
    own = [s for c in deck.contacts for s in c.slaves if s.set_id == sid]
    particles = [k for s in own for k in s.nodes]
    if not particles:
        raise InputError(f"{deck.path}: cavity set {sid} holds no particles to copy")
    next_set = (
        max(
            [t.set_id for c in deck.contacts for t in c.triangles]
            + [w.set_id for w in deck.analytic_walls or ()]
            + [s.set_id for c in deck.contacts for s in c.slaves]
        )
        + 1
    )
    new_nodlim = nodlim + (count - 1) * len(walls)
    # particles renumbered: the deck's own first (in id order), then each copy's
    old_particles = sorted(k for k in xyz if k > nodlim)
    pid = {k: new_nodlim + 1 + i for i, k in enumerate(old_particles)}
    nodes = [n for n in deck.nodes if n.nid <= nodlim]
    nodes += [Node(pid[n.nid], n.x, n.y, n.z) for n in deck.nodes if n.nid > nodlim]
    triangles = [t for c in deck.contacts for t in c.triangles]
    rbels = {rb.master: rb for rb in deck.rbels}
    masses, bounds, analytic = list(deck.masses), list(deck.boundaries), []
    wallmat = list(deck.wallmat or ())
    slave_sets = [
        SlaveSet(s.set_id, tuple(pid.get(k, k) for k in s.nodes))
        for c in deck.contacts
        for s in c.slaves
    ]
    initial_of = {i.nid: i for i in deck.initials}
    initials = [replace(i, nid=pid.get(i.nid, i.nid)) for i in deck.initials]
    next_node, next_particle = nodlim + 1, new_nodlim + 1 + len(old_particles)
    placed: dict[int, int] = {}
    spacing = np.asarray(spacing, float)
    for k in range(1, count):
        m = masters[k]
        j = placed.get(m, 1 if m == master0 else 0)
        placed[m] = j + 1
        offset = xyz[m] - xyz[master0] + j * spacing
        new = {w: next_node + i for i, w in enumerate(walls)}
        next_node += len(walls)
        nodes += [Node(new[w], *map(float, xyz[w] + offset)) for w in walls]
        rb = rbels.get(m, Rbel(m, (1, 2, 3, 4, 5, 6), ()))
        rbels[m] = replace(rb, slaves=rb.slaves + tuple(new[w] for w in walls), slave_positions=())
        masses += [replace(mass_of[w], nid=new[w]) for w in walls if w in mass_of and w in slaves0]
        bounds += _ranges([(new[w], tuple(sorted(fixed[w]))) for w in walls if fixed.get(w)])
        sid_k = next_set + k - 1
        triangles += [
            Triangle(sid_k, tuple(new[n] for n in t.nodes))
            for c in deck.contacts
            for t in c.triangles
            if t.set_id == sid
        ]
        analytic += [
            replace(w, set_id=sid_k, nodes=tuple(new[n] for n in w.nodes), positions=())
            for w in deck.analytic_walls or ()
            if w.set_id == sid
        ]
        wallmat += [replace(w, set_id=sid_k) for w in deck.wallmat or () if w.set_id == sid]
        ids = list(range(next_particle, next_particle + len(particles)))
        next_particle += len(particles)
        nodes += [Node(i, *map(float, xyz[p] + offset)) for i, p in zip(ids, particles)]
        initials += [
            replace(initial_of[p], nid=i) for i, p in zip(ids, particles) if p in initial_of
        ]
        slave_sets.append(SlaveSet(sid_k, tuple(ids)))
    pd = replace(deck.pdmp[0], nodlim=new_nodlim)
    traced = [k for k in (deck.trace.nodes if deck.trace else ()) if k <= nodlim]
    contacts = (Contact(tuple(triangles), tuple(slave_sets)),)
    return replace(
        deck,
        nodes=tuple(nodes),
        pdmp=(pd,),
        rbels=tuple(rbels.values()),
        masses=tuple(masses),
        boundaries=tuple(bounds),
        contacts=contacts,
        initials=tuple(initials),
        analytic_walls=(
            tuple(deck.analytic_walls) + tuple(analytic)
            if deck.analytic_walls is not None
            else None
        ),
        wallmat=tuple(wallmat) if deck.wallmat is not None else None,
        trace=Trace(tuple(traced + list(range(new_nodlim + 1, next_particle)))),
        hooke=_regrouped(deck.hooke, nodlim, new_nodlim),
        friction=_regrouped(deck.friction, nodlim, new_nodlim),
    )


def _ranges(rows: list[tuple[int, tuple[int, ...]]]) -> list[Boundary]:
    """BOUNDARY records for (node, fixed DOFs) rows: runs of consecutive ids with the same
    DOFs in one record."""
    out: list[Boundary] = []
    for nid, dofs in rows:
        last = out[-1] if out else None
        if last is not None and last.dofs == dofs and last.last + 1 == nid:
            out[-1] = replace(last, last=nid)
        else:
            out.append(Boundary(nid, nid, 1, dofs))
    return out


def _regrouped(records, nodlim: int, new_nodlim: int):
    """HOOKE / FRICTION records of the PDMP group after ``nodlim`` moved to ``new_nodlim``."""
    if records is None:
        return None
    return tuple(replace(r, nodlim=new_nodlim) if r.nodlim == nodlim else r for r in records)
