"""A configuration's cavity (x3dpd.design.configs): resized, refilled, given a clearance.

* :func:`resized` -- an axis-aligned box about its low corner, a CYLINDER or CAPSULE about its
  end A (``cavity_length``, ``cavity_size``, ``cavity_radius``);
* :func:`refilled` -- the cavity filled with the configuration's particles (``x3dpd fill``'s
  library, every sphere checked to fit; an analytic cavity through an inscribed mesh);
* :func:`with_clearance` -- the cavity's length set to the particle bed's extent plus the
  clearance (report Sections 10-11);
* :func:`config_error` -- an InputError at the configuration's line.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from x3dpd.api.decks import (
    BY_SHAPE_NAME,
    Contact,
    Deck,
    Node,
    Triangle,
    cavity_box,
    cavity_triangles,
    fill_positions,
    filled_deck,
)
from x3dpd.errors import InputError


def config_error(design, config, message: str):
    """Raise ``FILE:LINE: configuration NAME: message`` at the configuration's line."""
    where = f"{design.path}:{config.line}" if config.line else str(design.path)
    raise InputError(f"{where}: configuration {config.name}: {message}")


def with_clearance(design, config, deck: Deck, axis: int) -> Deck:
    """The cavity's length set to the particle bed's extent plus ``clearance`` (report Sections
    10-11: about twice the peak displacement), the bed centred in it: a box's far face along
    the drive moved, a cylinder's end B moved along its axis; the particles as filled."""
    c = float(config.values["clearance"])
    nodlim = deck.pdmp[0].nodlim if deck.pdmp else None
    if nodlim is None or not any(nd.nid > nodlim for nd in deck.nodes):
        config_error(design, config, "clearance needs particles (the bed it is measured from)")
    radius = float(deck.pdmp[0].rzero)
    xyz = {nd.nid: np.array([nd.x, nd.y, nd.z]) for nd in deck.nodes}
    wall = analytic_wall(deck, design.cavity_set)
    if wall is not None:
        if wall.shape != "cylinder":
            config_error(
                design, config, f"clearance: a {wall.shape} cavity has no flat ends to set it"
            )
        a, b = xyz[wall.nodes[0]], xyz[wall.nodes[1]]
        u = (b - a) / np.linalg.norm(b - a)
        moved = {wall.nodes[1]}
    else:
        tri, sid = cavity_triangles(deck, design.cavity_set)
        if cavity_box(tri) is None:
            config_error(design, config, "clearance needs a box or cylinder cavity")
        lo, hi = cavity_box(tri)
        a, u = lo, np.eye(3)[axis]
        moved = {
            k
            for cn in deck.contacts
            for t in cn.triangles
            if t.set_id == sid
            for k in t.nodes
            if abs(xyz[k][axis] - hi[axis]) <= 1e-12 * (1 + abs(hi[axis]))
        }
    along = {k: float((p - a) @ u) for k, p in xyz.items() if k > nodlim}
    bed = max(along.values()) - min(along.values()) + 2.0 * radius
    length = bed + c
    shift = c / 2.0 + radius - min(along.values())
    nodes = []
    for nd in deck.nodes:
        p = xyz[nd.nid]
        if nd.nid in moved:
            p = p + u * (length - float((p - a) @ u))
        elif nd.nid > nodlim:
            p = p + u * shift
        nodes.append(Node(nd.nid, *map(float, p)) if nd.nid in moved or nd.nid > nodlim else nd)
    return replace(deck, nodes=tuple(nodes))


def analytic_wall(deck: Deck, set_id: int | None):
    """The analytic wall record (CYLINDER, CAPSULE) bounding the cavity, or None when the
    cavity is triangulated (a CONTACT set with triangles)."""
    walls = deck.analytic_walls or ()
    if set_id is None and any(t for c in deck.contacts for t in c.triangles):
        return None
    for wall in walls:
        if set_id is None or wall.set_id == set_id:
            return wall
    return None


def resized(design, config, deck: Deck, axis: int) -> Deck:
    """The deck with its cavity resized: a box (CONTACT set) about its low corner, a cylinder
    or capsule (analytic wall A-B, radius) about its end A."""
    wall = analytic_wall(deck, design.cavity_set)
    if wall is not None:
        return _resized_wall(design, config, deck, wall)
    if "cavity_radius" in config.values:
        config_error(design, config, "cavity_radius needs a CYLINDER or CAPSULE cavity")
    try:
        tri, sid = cavity_triangles(deck, design.cavity_set)
    except InputError as exc:
        config_error(design, config, f"cannot resize the cavity: {exc}")
    box = cavity_box(tri)
    if box is None:
        config_error(
            design,
            config,
            "cavity_length / cavity_size need an axis-aligned box cavity "
            f"(CONTACT set {sid} is not one)",
        )
    lo, hi = box
    size = hi - lo
    new = np.array(config.values.get("cavity_size", size), float)
    if "cavity_length" in config.values:
        new[axis] = config.values["cavity_length"]
    ids = {k for c in deck.contacts for t in c.triangles if t.set_id == sid for k in t.nodes}
    nodes = tuple(
        Node(nd.nid, *map(float, lo + (np.array([nd.x, nd.y, nd.z]) - lo) * new / size))
        if nd.nid in ids
        else nd
        for nd in deck.nodes
    )
    return replace(deck, nodes=nodes)


def _resized_wall(design, config, deck: Deck, wall) -> Deck:
    """A cylinder's or capsule's axis end B moved along A-B to ``cavity_length``, its radius
    set to ``cavity_radius``."""
    v = config.values
    if "cavity_size" in v:
        config_error(
            design,
            config,
            f"cavity_size is a box's; this cavity is a {wall.shape} "
            "(give cavity_length, cavity_radius)",
        )
    xyz = {nd.nid: np.array([nd.x, nd.y, nd.z]) for nd in deck.nodes}
    a, b = (xyz[k] for k in wall.nodes[:2])
    nodes = deck.nodes
    if "cavity_length" in v:
        moved = a + (b - a) / np.linalg.norm(b - a) * v["cavity_length"]
        nodes = tuple(
            Node(nd.nid, *map(float, moved)) if nd.nid == wall.nodes[1] else nd for nd in nodes
        )
    params = wall.params
    if "cavity_radius" in v:
        params = (float(v["cavity_radius"]),) + tuple(params[1:])
    walls = tuple(replace(w, params=params) if w is wall else w for w in deck.analytic_walls)
    return replace(deck, nodes=nodes, analytic_walls=walls)


#: Facets around of the inscribed mesh an analytic cavity is filled through.
FILL_FACETS = 64


def _meshed(deck: Deck, wall) -> tuple[Deck, tuple]:
    """The deck with its analytic wall also given as CONTACT triangles of an inscribed mesh
    (x3dpd.geometry.shapes: corners on the wall, so a sphere that fits the mesh fits the
    wall) on new nodes above every other: what x3dpd.deck.fill packs into."""
    xyz = {nd.nid: (nd.x, nd.y, nd.z) for nd in deck.nodes}
    ends = np.array([xyz[k] for k in wall.nodes[:2]], float)
    verts, tris = BY_SHAPE_NAME[wall.shape].mesh(ends, wall.params, FILL_FACETS)
    first = max(xyz) + 1
    nodes = deck.nodes + tuple(Node(first + k, *map(float, p)) for k, p in enumerate(verts))
    mesh = tuple(Triangle(wall.set_id, tuple(int(first + i) for i in t)) for t in tris)
    contacts = deck.contacts or (Contact((), ()),)
    contacts = (replace(contacts[0], triangles=contacts[0].triangles + mesh),) + contacts[1:]
    return replace(deck, nodes=nodes, contacts=contacts), mesh


def refilled(design, config, deck: Deck) -> Deck:
    """The cavity refilled (x3dpd.deck.fill); an analytic cavity through its inscribed mesh."""
    wall = analytic_wall(deck, design.cavity_set)
    if wall is None:
        return _refilled_mesh(design, config, deck, wall_set=None)
    meshed, mesh = _meshed(deck, wall)
    out = _refilled_mesh(
        design, config, meshed, wall_set=wall.set_id, volume=wall_volume(deck, wall)
    )
    drop = set(mesh)
    return replace(
        out,
        contacts=tuple(
            replace(c, triangles=tuple(t for t in c.triangles if t not in drop))
            for c in out.contacts
        ),
    )


def wall_volume(deck: Deck, wall) -> float:
    """Interior volume of a cylinder (pi R^2 L) or capsule (pi R^2 L + 4/3 pi R^3) [length^3]."""
    length, radius = wall_length(deck, wall), float(wall.params[0])
    extra = 4.0 / 3.0 * math.pi * radius**3 if wall.shape == "capsule" else 0.0
    return math.pi * radius**2 * length + extra


def wall_length(deck: Deck, wall) -> float:
    """|B - A| of an analytic wall's axis nodes [length]."""
    xyz = {nd.nid: np.array([nd.x, nd.y, nd.z]) for nd in deck.nodes}
    return float(np.linalg.norm(xyz[wall.nodes[1]] - xyz[wall.nodes[0]]))


def _refilled_mesh(
    design, config, deck: Deck, wall_set: int | None, volume: float | None = None
) -> Deck:
    """The cavity refilled with the configuration's particles (x3dpd.deck.fill)."""
    v = config.values
    pd = deck.pdmp[0]
    radius = float(v.get("radius", pd.rzero))
    gap = float(v.get("gap", v.get("gap_fraction", 0.0) * radius))
    opts = {
        "radius": radius,
        "packing": v.get("packing", "cubic"),
        "gap": gap,
        "seed": v.get("seed"),
        "jitter": float(v.get("jitter", 0.0)),
        "set_id": design.cavity_set,
    }
    try:
        volume = volume or fill_positions(deck, n=1, **opts).volume
        one = 4.0 / 3.0 * math.pi * radius**3
        if "count" in v:
            n = int(v["count"])
        elif "fill_ratio" in v:
            n = math.floor(v["fill_ratio"] * volume / one + 1e-9)
        elif "particle_mass" in v:
            n = round(v["particle_mass"] / (pd.prho * one))
        else:
            n = sum(1 for nd in deck.nodes if nd.nid > pd.nodlim)
        if n < 1:
            config_error(design, config, f"{n} particles of radius {radius:g}: nothing to fill")
        fill = fill_positions(deck, n=n, **opts)
    except InputError as exc:
        config_error(design, config, str(exc))
    got = fill.positions.shape[0]
    if got < n:
        config_error(
            design,
            config,
            f"only {got} of {n} spheres of radius {radius:g} fit in the "
            f"cavity ({opts['packing']} packing, gap {gap:g}, cavity volume "
            f"{volume:.6g}); a fill that cannot fit",
        )
    return filled_deck(deck, fill, opts["set_id"])
