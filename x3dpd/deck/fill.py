"""Fill a deck's cavity with particles (``x3dpd fill``): positions, then a new deck.

:func:`fill_positions` places the spheres in the cavity of one CONTACT set of a template deck
(any closed triangulated cavity; x3dpd.geometry.packing). An axis-aligned box cavity with the
``cubic`` packing uses :func:`x3dpd.deck.generate.lattice_fill` (the lattice centred in the box,
the layout of the shipped beam decks). :func:`filled_deck` writes them into a copy of the
template: the old particles (nodes above the first PDMP card's NODLIM) are dropped with their
INITIAL and TRACE entries, the new ones get ids NODLIM+1..., the PDMP card gets the new radius,
the CONTACT set's slave list and the TRACE card (the template's structural traced nodes first,
then every particle, the order pmov.m expects) list them. A ``material`` from the library
(x3dpd.materials, by name) replaces the PDMP card's PRHO, PPOI, E0, E1, T1, PCOF (and further
Maxwell pairs), converted to the template's UNITS.

The time step is not this module's business (the deck layer cannot build a model):
:func:`x3dpd.api.fit_time_step` sets the DTMAX the new particles need.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from x3dpd.deck.cards import Contact, Deck, Node, Pdmp, SlaveSet, Trace
from x3dpd.deck.generate import lattice_fill
from x3dpd.errors import InputError
from x3dpd.geometry.cavity import enclosed_volume, geometry_size, merge_vertices, surface_edges
from x3dpd.geometry.packing import PACKINGS, pack
from x3dpd.geometry.triangle import inward_signs
from x3dpd.materials import in_units


@dataclass(frozen=True)
class Fill:
    """Result of :func:`fill_positions`: ``positions`` (m, 3), the cavity's ``volume``
    [length^3], the achieved ``fill_ratio`` (particle volume / cavity volume), whether the
    cavity is an axis-aligned ``box``, and ``requested`` (None: as many as fit)."""

    positions: np.ndarray
    radius: float
    volume: float
    box: bool
    requested: int | None

    @property
    def fill_ratio(self) -> float:
        n = self.positions.shape[0]
        return n * 4.0 / 3.0 * math.pi * self.radius**3 / self.volume if self.volume else 0.0


def _first_pdmp(deck: Deck):
    if not deck.pdmp:
        raise InputError(
            f"{deck.path}: the template has no PDMP card: it must give the "
            "particles' material (RZERO, PRHO, PPOI, E0, E1, T1, PCOF)"
        )
    return deck.pdmp[0]


def cavity_triangles(deck: Deck, set_id: int | None = None) -> tuple[np.ndarray, int]:
    """``(T, 3, 3)`` coordinates of the CONTACT triangles of set ``set_id`` (default: the first
    set) and that set id."""
    tris = [t for c in deck.contacts for t in c.triangles]
    if not tris:
        raise InputError(f"{deck.path}: the template has no CONTACT triangles to fill")
    sid = tris[0].set_id if set_id is None else int(set_id)
    mine = [t for t in tris if t.set_id == sid]
    if not mine:
        have = sorted({t.set_id for t in tris})
        raise InputError(f"{deck.path}: no CONTACT set {sid} (sets: {have})")
    xyz = {n.nid: (n.x, n.y, n.z) for n in deck.nodes}
    try:
        return np.array([[xyz[k] for k in t.nodes] for t in mine], dtype=float), sid
    except KeyError as exc:
        raise InputError(
            f"{deck.path}: CONTACT triangle node {exc.args[0]} has no coordinates"
        ) from None


def cavity_box(tri: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """``(lo, hi)`` when every triangle lies in a face plane of the bounding box."""
    pts = tri.reshape(-1, 3)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    tol = 1e-9 * float(np.max(hi - lo) or 1.0)
    for t in tri:
        on = [
            np.all(np.abs(t[:, k] - lo[k]) <= tol) or np.all(np.abs(t[:, k] - hi[k]) <= tol)
            for k in range(3)
        ]
        if not any(on):
            return None
    return lo, hi


def _stacking(deck: Deck) -> tuple[int, bool]:
    """Axis of gravity (largest BODY component; y without gravity) and whether it points down
    that axis (so layers fill from its low end)."""
    if deck.body is None:
        return 1, True
    g = np.array([deck.body.ax, deck.body.ay, deck.body.az])
    if not np.any(g):
        return 1, True
    k = int(np.argmax(np.abs(g)))
    return k, bool(g[k] < 0)


def fill_positions(
    deck: Deck,
    *,
    n: int | None,
    radius: float | None = None,
    packing: str = "cubic",
    gap: float = 0.0,
    seed: int | None = None,
    jitter: float = 0.0,
    set_id: int | None = None,
) -> Fill:
    """Place up to ``n`` spheres (None: as many as fit) in the template's cavity.

    ``radius`` defaults to the template's PDMP RZERO; ``gap`` is kept to the walls and between
    lattice neighbours; ``jitter`` (box + cubic only) moves each coordinate by up to
    ``jitter * gap / 2`` (reproducible with ``seed``).
    """
    if packing not in PACKINGS:
        raise InputError(f"packing {packing!r}: expected one of {', '.join(PACKINGS)}")
    r = float(radius if radius is not None else _first_pdmp(deck).rzero)
    if not (r > 0 and math.isfinite(r)):
        raise InputError(f"radius must be a positive number; got {r!r}")
    tri, sid = cavity_triangles(deck, set_id)
    signs = inward_signs(tri[:, 0], tri[:, 1], tri[:, 2], tri.reshape(-1, 3).mean(axis=0))
    pts = tri.reshape(-1, 3)
    closed, _ = surface_edges(merge_vertices(pts, geometry_size(pts)).reshape(-1, 3), signs)
    if not closed:
        raise InputError(
            f"{deck.path}: CONTACT set {sid} is not a closed surface: there is no cavity to fill"
        )
    volume = abs(enclosed_volume(tri[:, 0], tri[:, 1], tri[:, 2], signs))
    axis, upward = _stacking(deck)
    box = cavity_box(tri)
    if box is not None and packing == "cubic" and upward:
        lo, hi = box
        size = hi - lo
        pitch = 2.0 * r + gap
        counts = np.floor((size - 2.0 * gap - 2.0 * r) / pitch + 1e-9).astype(int) + 1
        fit = int(np.prod(counts)) if np.all(size >= 2.0 * (r + gap)) else 0
        m = fit if n is None else min(n, fit)
        pos = (
            lattice_fill(
                size, r, m, gap=gap, seed=seed, jitter=jitter, origin=tuple(lo), stack_axis=axis
            )
            if m
            else np.zeros((0, 3))
        )
    else:
        pos = pack(tri, r, n, packing=packing, gap=gap, stack_axis=axis, upward=upward, seed=seed)
    return Fill(pos, r, volume, box is not None, n)


def with_material(pd: Pdmp, material, units=None) -> Pdmp:
    """The PDMP card ``pd`` with the material fields of ``material`` (a library name or
    :class:`x3dpd.materials.Material`) in ``units`` (a UNITS card or None: inch-lbf-s)."""
    fields = in_units(material, units).pdmp_fields()
    return replace(pd, **fields)


def filled_deck(template: Deck, fill: Fill, set_id: int | None = None, material=None) -> Deck:
    """The template with its particles replaced by ``fill``'s (see the module docstring), of
    ``material`` (library name or Material; None: the template's PDMP material)."""
    pd = _first_pdmp(template)
    if material is not None:
        pd = with_material(pd, material, template.units)
    nodlim = pd.nodlim
    _, sid = cavity_triangles(template, set_id)
    structure = [nd for nd in template.nodes if nd.nid <= nodlim]
    ids = list(range(nodlim + 1, nodlim + 1 + fill.positions.shape[0]))
    nodes = tuple(structure) + tuple(Node(i, *map(float, p)) for i, p in zip(ids, fill.positions))
    contacts = []
    for c in template.contacts:
        slaves = []
        for s in c.slaves:
            kept = tuple(k for k in s.nodes if k <= nodlim)
            if s.set_id == sid:
                kept += tuple(ids)
            if kept:
                slaves.append(SlaveSet(s.set_id, kept))
        if any(t.set_id == sid for t in c.triangles) and not any(s.set_id == sid for s in slaves):
            slaves.append(SlaveSet(sid, tuple(ids)))
        contacts.append(Contact(c.triangles, tuple(slaves)))
    traced = [k for k in (template.trace.nodes if template.trace else ()) if k <= nodlim]
    return replace(
        template,
        nodes=nodes,
        pdmp=(replace(pd, rzero=fill.radius),) + tuple(template.pdmp[1:]),
        contacts=tuple(contacts),
        trace=Trace(tuple(traced + ids)),
        initials=tuple(i for i in template.initials if i.nid <= nodlim),
    )
