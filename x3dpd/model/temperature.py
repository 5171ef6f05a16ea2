"""A deck at temperature (the TEMPERATURE card; report Sections 6.4-6.5): properties at T, and
the expansion of the particles and the cavities from the assembly temperature T0 to T.

The deck's numbers are the materials at the assembly temperature T0 (default 70 °F): the PDMP
cards' E0, E1 ..., PPOI, PRHO, RZERO; WALLMAT's E and NU; the cavities' coordinates and lengths.
The TEMPERATURE card names the library material of each particle group and of each set's walls
(x3dpd.materials), and the library's tables carry those numbers to T. With s the thermal strain
of a material from T0 to T, s = (L(T) - L(T0)) / L(T0) (x3dpd.materials.thermal_strain; for a
mean coefficient alpha from the table's reference T0: s = alpha (T - T0), so a length L becomes
L (1 + alpha dT)), and E(T), nu(T) the tables' values:

    particles   RZERO' = RZERO (1 + s_p)                 the sphere grows
                PRHO'  = PRHO / (1 + s_p)^3              its mass stays the same
                E0', E1', E2' ... = E... E_p(T) / E_p(T0)    the relaxation times kept
                PPOI'  = PPOI nu_p(T) / nu_p(T0)
    walls       E' = E E_w(T) / E_w(T0), NU' = NU nu_w(T) / nu_w(T0)    (WALLMAT; MU kept)
                x' = c + (1 + s_w) (x - c)  for every node of the cavity's walls (its triangles
                and its analytic walls' axis nodes), every length of its analytic walls x (1 + s_w)
                (a radius), and its particles' centres carried along the same way

where c is the cavity's centre, the mean of its wall nodes (a cylinder's axis midpoint): a
cavity grows about itself, so each of a structure's cavities stays where it is. Friction (PCOF,
WALLMAT MU, FRICTION), a HOOKE card's stiffness and restitution, the structure (springs,
masses, modes) and the time step are the deck's at every temperature.

The transformation is of the cards, before the model is built (:func:`warmed`): the deck at T
is built by the same builder, so masses, rigid bodies' inertias, checks and the step's advice
all follow, and at T = T0 nothing moves -- the model is the deck's bit for bit. The model
carries what it did (:class:`AtTemperature`, ``Model.temperature``) for ``x3dpd check``:
:func:`check_lines` (the temperatures, each material's strain and ratios, each cavity's
clearance at T0 and at T) and :func:`check_findings` (a clearance that closes). The clearance
of a cavity is what one sphere of it (its largest) could travel alone
(:mod:`x3dpd.model.temperature_clearance`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from x3dpd.errors import DeckError, Pos
from x3dpd.materials import (
    MaterialError,
    check_temperature,
    format_temperature,
    material,
    properties_at,
    temperature_unit_for,
    thermal_strain,
)
from x3dpd.model.check_text import _ranges
from x3dpd.model.temperature_clearance import Clearance, clearances

CARD = "TEMPERATURE"


@dataclass(frozen=True)
class Change:
    """What one material does from T0 to T: a particle group's (``kind`` "particles", ``ident``
    its NODLIM) or a CONTACT set's walls' ("walls", the set id): thermal ``strain`` s, and the
    ratios E(T)/E(T0), nu(T)/nu(T0) of its tables."""

    kind: str
    ident: int
    material: str
    strain: float
    e_ratio: float
    nu_ratio: float


@dataclass(frozen=True)
class AtTemperature:
    """What the TEMPERATURE card did to a model: the ``operating`` and ``assembly``
    temperatures [K] (``origin``: what set the operating one, "" for the card), each
    material's :class:`Change` and each cavity's :class:`Clearance` at both."""

    operating: float
    assembly: float
    origin: str
    changes: tuple[Change, ...]
    clearances: tuple[Clearance, ...]


def _error(deck, message: str, pos: Pos) -> DeckError:
    return DeckError(message, deck.path, pos.line, pos.column, CARD)


def _change(deck, kind: str, ident: int, record) -> Change:
    """The :class:`Change` of ``record``'s material from the card's T0 to its T."""
    card = deck.temperature
    unit = card.operating.unit
    name = material(record.material).name
    for reading, what in ((card.assembly, "ASSEMBLY"), (card.operating, "OPERATING")):
        try:
            check_temperature(name, reading.kelvin, unit)
        except MaterialError as exc:
            origin = f" ({reading.origin})" if reading.origin else ""
            raise _error(deck, f"{what} {reading.text}{origin}: {exc}", reading.pos) from None
    k0, k = card.assembly.kelvin, card.operating.kelvin
    at0, at = properties_at(name, k0, unit=unit), properties_at(name, k, unit=unit)
    try:
        strain = thermal_strain(name, f"{k0!r}K", f"{k!r}K")
    except MaterialError:
        raise _error(
            deck,
            f"material {name!r} has no expansion data (room-temperature values only): it "
            f"cannot go from {format_temperature(k0, unit)} to {format_temperature(k, unit)}",
            record.pos,
        ) from None
    return Change(kind, ident, name, strain, at.E / at0.E, at.nu / at0.nu)


def _changes(deck, model) -> tuple[dict[int, Change], dict[int, Change]]:
    """The change of each PDMP group (by its index) and of each cavity's walls (by its
    index), from the card's records; DeckError for a group or a cavity with particles that has
    no material, or a record that names none."""
    card = deck.temperature
    groups = [c.nodlim for c in deck.pdmp]
    sets = [int(s) for s in model.cavity_set_ids]
    for records, known, what in (
        (card.particles, groups, "PDMP group NODLIM"),
        (card.walls, sets, "CONTACT set with walls"),
    ):
        for r in records:
            if r.ident is not None and r.ident not in known:
                listed = ", ".join(map(str, known)) or "none"
                raise _error(deck, f"{r.ident} names no {what} (they are: {listed})", r.pos)
    by_group, by_cavity = {}, {}
    for k, nodlim in enumerate(groups):
        record = card.material_of("particles", nodlim)
        if record is None:
            raise _error(
                deck,
                f"PDMP group NODLIM {nodlim} has no material: give PARTICLES {nodlim} MATERIAL "
                "(or PARTICLES MATERIAL for every group)",
                card.pos,
            )
        by_group[k] = _change(deck, "particles", nodlim, record)
    for c, sid in enumerate(sets):
        record = card.material_of("walls", sid)
        if record is None and np.any(model.particle_cavity == c):
            raise _error(
                deck,
                f"the walls of CONTACT set {sid} have no material: give WALLS {sid} MATERIAL "
                "(or WALLS MATERIAL for every set)",
                card.pos,
            )
        if record is not None:
            by_cavity[c] = _change(deck, "walls", sid, record)
    return by_group, by_cavity


def _scaled_pdmp(card, change: Change):
    s = change.strain
    return replace(
        card,
        rzero=card.rzero * (1.0 + s),
        prho=card.prho / (1.0 + s) ** 3,
        ppoi=card.ppoi * change.nu_ratio,
        e0=card.e0 * change.e_ratio,
        e1=card.e1 * change.e_ratio,
        extra_terms=tuple((e * change.e_ratio, tau) for e, tau in card.extra_terms),
    )


def _moved_nodes(deck, model, by_cavity: dict[int, Change]) -> dict[int, tuple]:
    """New (x, y, z) of every node a cavity moves: its wall nodes and its particles, each
    cavity about its centre by its walls' strain; DeckError for a node two cavities move
    apart."""
    tri_cavity = model.face_cavity[model.tri_face]
    p0 = model.particle_start
    moved: dict[int, tuple] = {}
    owner: dict[int, int] = {}
    for c, change in by_cavity.items():
        if change.strain == 0.0:
            continue
        walls = np.concatenate(
            [
                model.tri_nodes[tri_cavity == c].reshape(-1),
                model.shape_nodes[model.shape_cavity == c].reshape(-1),
            ]
        )
        walls = np.unique(walls)
        centre = model.x0[walls].mean(axis=0)
        mine = np.concatenate([walls, p0 + np.flatnonzero(model.particle_cavity == c)])
        grown = centre + (1.0 + change.strain) * (model.x0[mine] - centre)
        for i, x in zip(mine.tolist(), grown):
            nid = int(model.node_ids[i])
            new = tuple(float(v) for v in x)
            if nid in moved and moved[nid] != new:
                raise _error(
                    deck,
                    f"node {nid} belongs to the walls of CONTACT sets {owner[nid]} and "
                    f"{change.ident}, which grow about their own centres: give each cavity its "
                    "own nodes",
                    deck.temperature.pos,
                )
            moved[nid], owner[nid] = new, change.ident
    return moved


def deck_at_temperature(deck, model, by_group: dict, by_cavity: dict):
    """The cards at the operating temperature (the module docstring's equations); ``model`` is
    the deck built as it stands (at T0)."""
    pdmp = tuple(_scaled_pdmp(card, by_group[k]) for k, card in enumerate(deck.pdmp))
    by_set = {ch.ident: ch for ch in by_cavity.values()}
    wallmat = deck.wallmat
    if wallmat is not None:
        wallmat = tuple(
            replace(w, e=w.e * by_set[w.set_id].e_ratio, nu=w.nu * by_set[w.set_id].nu_ratio)
            if w.set_id in by_set
            else w
            for w in wallmat
        )
    walls = deck.analytic_walls
    if walls is not None:
        walls = tuple(
            replace(w, params=tuple(p * (1.0 + by_set[w.set_id].strain) for p in w.params))
            if w.set_id in by_set
            else w
            for w in walls
        )
    moved = _moved_nodes(deck, model, by_cavity)
    nodes = tuple(
        replace(nd, x=moved[nd.nid][0], y=moved[nd.nid][1], z=moved[nd.nid][2])
        if nd.nid in moved
        else nd
        for nd in deck.nodes
    )
    return replace(deck, pdmp=pdmp, wallmat=wallmat, analytic_walls=walls, nodes=nodes)


def warmed(deck, model, build: Callable):
    """The model of ``deck`` at its TEMPERATURE card's operating temperature: ``model`` is the
    deck built as it stands (at the assembly temperature), ``build(cards)`` the builder. Raises
    :class:`DeckError` at the card for a material or temperature it cannot take."""
    card = deck.temperature
    by_group, by_cavity = _changes(deck, model)
    hot = model
    if card.operating.kelvin != card.assembly.kelvin:
        hot = build(deck_at_temperature(deck, model, by_group, by_cavity))
    changes = tuple(by_group.values()) + tuple(by_cavity.values())
    at = AtTemperature(
        card.operating.kelvin,
        card.assembly.kelvin,
        card.operating.origin,
        changes,
        tuple(clearances(model, hot)),
    )
    return replace(hot, temperature=at)


def _degrees(model, kelvin: float) -> str:
    return format_temperature(kelvin, temperature_unit_for(model.units))


def _grouped(items, key) -> dict[tuple, list[int]]:
    """Items with equal ``key(item)[0]`` (what they say) gathered, with their ids ``key[1]``."""
    out: dict[tuple, list[int]] = {}
    for item in items:
        what, ident = key(item)
        out.setdefault(what, []).append(ident)
    return out


def check_lines(model) -> list[str]:
    """What ``x3dpd check`` prints of a model at temperature: the temperatures, each
    material's change and each cavity's clearance at both, cavities that say the same on one
    line ([] without a TEMPERATURE card)."""
    at = model.temperature
    if at is None:
        return []
    t, t0 = _degrees(model, at.operating), _degrees(model, at.assembly)
    origin = f" ({at.origin})" if at.origin else ""
    out = [f"{t}{origin}; the deck's numbers at the assembly temperature {t0}"]
    changes = _grouped(
        at.changes,
        lambda ch: ((ch.kind, ch.material, ch.strain, ch.e_ratio, ch.nu_ratio), ch.ident),
    )
    for (kind, name, strain, e_ratio, nu_ratio), ids in changes.items():
        many = "s" if len(ids) > 1 else ""
        who = f"particle group{many} NODLIM" if kind == "particles" else f"walls of set{many}"
        out.append(
            f"{who} {_ranges(ids)}: {name}, strain {strain:+.4g}, E x{e_ratio:.6g}, "
            f"nu x{nu_ratio:.6g}"
        )
    gaps = _grouped(at.clearances, lambda c: ((c.what, c.assembly, c.operating), c.set_id))
    for (what, before, after), ids in gaps.items():
        out.append(
            f"clearance, set{'s' if len(ids) > 1 else ''} {_ranges(ids)}, {what}: {before:.6g} "
            f"at {t0}, {after:.6g} at {t} ({after - before:+.3g})"
        )
    return out


def check_findings(model) -> list[tuple[str, str, list[str]]]:
    """(code, headline, details) of each cavity whose clearance closes at the operating
    temperature: one sphere of it has no room left along a direction."""
    at = model.temperature
    if at is None:
        return []
    shut = [c for c in at.clearances if c.operating <= 0.0]
    if not shut:
        return []
    t, t0 = _degrees(model, at.operating), _degrees(model, at.assembly)
    return [
        (
            "clearance-closes",
            f"{len(shut)} cavity clearance{'s close' if len(shut) > 1 else ' closes'} at {t}: "
            "the particles and walls expand differently from the assembly temperature "
            f"{t0}, and a sphere has no room left to move (it is gripped)",
            [
                f"set {c.set_id} {c.what}: {c.assembly:.6g} at {t0}, {c.operating:.6g} at {t}"
                for c in shut
            ],
        )
    ]


__all__ = [
    "AtTemperature",
    "Change",
    "Clearance",
    "check_findings",
    "check_lines",
    "clearances",
    "deck_at_temperature",
    "warmed",
]
