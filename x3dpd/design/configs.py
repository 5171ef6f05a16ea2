"""The configurations of a design (x3dpd.design.design_file): one deck each, made from the
structure deck by resizing its cavity, filling it (``x3dpd fill``'s library) and setting the
particles' material (x3dpd.materials), then written to ``OUT/configs/NAME/NAME.inp``.

Every deck is made in memory first; a fill that cannot fit, a cavity that cannot be resized or
a deck ``x3dpd check`` does not pass clean is an InputError at the configuration's line, before
anything is written or run. A written deck is read back (:func:`x3dpd.api.load_deck`) and that
deck is what runs, so each configuration's deck runs on its own as it stands
(``x3dpd OUT/configs/NAME/NAME.inp``).

Time step: ``dt`` when the configuration gives one, else the step ``x3dpd check`` recommends
for the configuration's particles (50 steps per contact, x3dpd.model.timestep; floored to 3
digits by :func:`x3dpd.api.fit_time_step`, as ``x3dpd fill`` does), ITRAC scaled to keep the
trace interval.
"""

from __future__ import annotations

import math
import os
import shutil
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from x3dpd.api import build, check, fit_time_step, load_deck, rules_of_thumb
from x3dpd.deck.cards import Deck, Node, Title
from x3dpd.deck.fill import _box, cavity_triangles, fill_positions, filled_deck, with_material
from x3dpd.deck.writer import format_deck
from x3dpd.design.baselines import particle_mass, without_particles
from x3dpd.design.design_file import Configuration, DesignFile
from x3dpd.errors import InputError
from x3dpd.physics.usrfrc import is_user_file

#: Keys that make a configuration refill its cavity.
REFILL = ("radius", "count", "fill_ratio", "particle_mass", "cavity_length", "cavity_size",
          "cavity_radius",
          "packing", "gap", "gap_fraction", "jitter", "seed")


@dataclass(frozen=True)
class Made:
    """A configuration's deck: ``path`` of its file, the ``deck`` read back from it, and the
    ``values`` it resolved to (material, radius, count, fill ratio, added mass, cavity
    length, clearance, dt)."""

    config: Configuration
    path: Path
    deck: Deck
    values: dict
    text: str


def code_files(deck: Deck) -> list[str]:
    """The Python files the deck's USRFRC card names (code that runs with the deck)."""
    return [spec.strip() for card in deck.usrfrc for spec in card.specs if is_user_file(spec)]


def make_configurations(design: DesignFile) -> list[Made]:
    """Every configuration's deck, made and checked in memory (files not written yet)."""
    template = load_deck(design.structure)
    code = code_files(template)
    if code and not design.usrfrc_code:
        raise InputError(
            f"{design.where('structure')}: structure: {design.structure.name} names the code "
            f"file {code[0]} (USRFRC), which every configuration would run; a design runs a "
            "deck's code only with usrfrc_code = true")
    return [_make(design, template, c) for c in design.configurations]


def _fail(design: DesignFile, config: Configuration, message: str):
    where = f"{design.path}:{config.line}" if config.line else str(design.path)
    raise InputError(f"{where}: configuration {config.name}: {message}")


def _make(design: DesignFile, template: Deck, config: Configuration) -> Made:
    v = config.values
    deck = template
    pd = deck.pdmp[0] if deck.pdmp else None
    if pd is None and any(k in v for k in REFILL + ("material",)) and v.get("count") != 0:
        _fail(design, config, f"{design.structure.name} has no PDMP card to give the particles "
              "a material; start from a deck with particles")
    if "material" in v:
        deck = replace(deck, pdmp=(with_material(pd, v["material"], deck.units),)
                       + deck.pdmp[1:])
        pd = deck.pdmp[0]
    axis = _drive_axis(design, template)
    if any(k in v for k in ("cavity_length", "cavity_size", "cavity_radius")):
        deck = _resized(design, config, deck, axis)
    if v.get("count") == 0:
        deck = without_particles(deck)
    elif any(k in v for k in REFILL):
        deck = _refilled(design, config, deck)
    if "clearance" in v:
        deck = _with_clearance(design, config, deck, axis)
    deck = _with_step(design, config, deck)
    deck = replace(deck, title=Title(f"{design.title}\nconfiguration {config.name}"))
    report = check(deck)
    if report.exit_status != 0:
        first = (report.errors or report.warnings)[0]
        message = getattr(first, "message", first)
        _fail(design, config, f"the deck made does not check clean: {message}")
    values = _resolved(deck, axis, v)
    values["mass_ratio"] = (values["added_mass"] / report.structure_mass
                            if report.structure_mass > 0 else math.nan)
    values["notes"] = tuple(f"{n.text} ({n.section})" for n in _rules(design, deck))
    head = [f"{config.name}.inp: configuration {config.name} of the design {design.path.name}",
            f"Made by `x3dpd design` from {design.structure.name}; do not edit (rerun the design).",
            *(f"  {k} = {val!r}" for k, val in v.items())]
    text = "".join(f"$ {line}".rstrip() + "\n" for line in head) + "$\n" + format_deck(deck)
    return Made(config, Path(), deck, values, text)


def _rules(design: DesignFile, deck: Deck) -> list:
    """The report's rules of thumb (x3dpd.api.rules_of_thumb) for the configuration under the
    evaluation's drive at its largest level: a sine at the dwell's or ring-down's frequency, a
    sweep over the band; the deck's own USRFRC drive for a ring-down without one."""
    from x3dpd.design.spec import default_drive_point

    ev = design.evaluation
    if not ev.drives or not ev.frequencies:
        return rules_of_thumb(deck)
    node, dof = ev.node, ev.dof
    if node is None or dof is None:
        try:
            d_node, d_dof = default_drive_point(deck)
        except InputError:
            return []
        node, dof = (d_node if node is None else node), (d_dof if dof is None else dof)
    amp, lo, hi = max(ev.drives), min(ev.frequencies), max(ev.frequencies)
    spec = (f"sine:node={node},dof={dof},amp={amp!r},hz={lo!r}" if lo == hi else
            f"sweep:node={node},dof={dof},amp={amp!r},f0={lo!r},f1={hi!r},rate=1")
    return rules_of_thumb(replace(deck, usrfrc=()), usrfrc=(spec,))


def _drive_axis(design: DesignFile, deck: Deck) -> int:
    """Index 0-2 of the axis the evaluation drives along."""
    from x3dpd.design.spec import default_drive_point

    dof = design.evaluation.dof
    if dof is None:
        try:
            dof = default_drive_point(deck)[1]
        except InputError:
            dof = 1
    return max(0, min(2, dof - 1))


def _with_clearance(design, config, deck: Deck, axis: int) -> Deck:
    """The cavity's length set to the particle bed's extent plus ``clearance`` (report Sections
    10-11: about twice the peak displacement), the bed centred in it: a box's far face along
    the drive moved, a cylinder's end B moved along its axis; the particles as filled."""
    c = float(config.values["clearance"])
    nodlim = deck.pdmp[0].nodlim if deck.pdmp else None
    if nodlim is None or not any(nd.nid > nodlim for nd in deck.nodes):
        _fail(design, config, "clearance needs particles (the bed it is measured from)")
    radius = float(deck.pdmp[0].rzero)
    xyz = {nd.nid: np.array([nd.x, nd.y, nd.z]) for nd in deck.nodes}
    wall = _analytic_wall(deck, design.cavity_set)
    if wall is not None:
        if wall.shape != "cylinder":
            _fail(design, config, f"clearance: a {wall.shape} cavity has no flat ends to set it")
        a, b = xyz[wall.nodes[0]], xyz[wall.nodes[1]]
        u = (b - a) / np.linalg.norm(b - a)
        moved = {wall.nodes[1]}
    else:
        tri, sid = cavity_triangles(deck, design.cavity_set)
        if _box(tri) is None:
            _fail(design, config, "clearance needs a box or cylinder cavity")
        lo, hi = _box(tri)
        a, u = lo, np.eye(3)[axis]
        moved = {k for cn in deck.contacts for t in cn.triangles if t.set_id == sid
                 for k in t.nodes if abs(xyz[k][axis] - hi[axis]) <= 1e-12 * (1 + abs(hi[axis]))}
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


def _analytic_wall(deck: Deck, set_id: int | None):
    """The analytic wall record (CYLINDER, CAPSULE) bounding the cavity, or None when the
    cavity is triangulated (a CONTACT set with triangles)."""
    walls = deck.analytic_walls or ()
    if set_id is None and any(t for c in deck.contacts for t in c.triangles):
        return None
    for wall in walls:
        if set_id is None or wall.set_id == set_id:
            return wall
    return None


def _resized(design, config, deck: Deck, axis: int) -> Deck:
    """The deck with its cavity resized: a box (CONTACT set) about its low corner, a cylinder
    or capsule (analytic wall A-B, radius) about its end A."""
    wall = _analytic_wall(deck, design.cavity_set)
    if wall is not None:
        return _resized_wall(design, config, deck, wall)
    if "cavity_radius" in config.values:
        _fail(design, config, "cavity_radius needs a CYLINDER or CAPSULE cavity")
    try:
        tri, sid = cavity_triangles(deck, design.cavity_set)
    except InputError as exc:
        _fail(design, config, f"cannot resize the cavity: {exc}")
    box = _box(tri)
    if box is None:
        _fail(design, config, "cavity_length / cavity_size need an axis-aligned box cavity "
              f"(CONTACT set {sid} is not one)")
    lo, hi = box
    size = hi - lo
    new = np.array(config.values.get("cavity_size", size), float)
    if "cavity_length" in config.values:
        new[axis] = config.values["cavity_length"]
    ids = {k for c in deck.contacts for t in c.triangles if t.set_id == sid for k in t.nodes}
    nodes = tuple(Node(nd.nid, *map(float, lo + (np.array([nd.x, nd.y, nd.z]) - lo)
                                    * new / size)) if nd.nid in ids else nd
                  for nd in deck.nodes)
    return replace(deck, nodes=nodes)


def _resized_wall(design, config, deck: Deck, wall) -> Deck:
    """A cylinder's or capsule's axis end B moved along A-B to ``cavity_length``, its radius
    set to ``cavity_radius``."""
    v = config.values
    if "cavity_size" in v:
        _fail(design, config, f"cavity_size is a box's; this cavity is a {wall.shape} "
              "(give cavity_length, cavity_radius)")
    xyz = {nd.nid: np.array([nd.x, nd.y, nd.z]) for nd in deck.nodes}
    a, b = (xyz[k] for k in wall.nodes[:2])
    nodes = deck.nodes
    if "cavity_length" in v:
        moved = a + (b - a) / np.linalg.norm(b - a) * v["cavity_length"]
        nodes = tuple(Node(nd.nid, *map(float, moved)) if nd.nid == wall.nodes[1] else nd
                      for nd in nodes)
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
    from x3dpd.deck.cards import Contact, Triangle
    from x3dpd.geometry.shapes import BY_SHAPE_NAME

    xyz = {nd.nid: (nd.x, nd.y, nd.z) for nd in deck.nodes}
    ends = np.array([xyz[k] for k in wall.nodes[:2]], float)
    verts, tris = BY_SHAPE_NAME[wall.shape].mesh(ends, wall.params, FILL_FACETS)
    first = max(xyz) + 1
    nodes = deck.nodes + tuple(Node(first + k, *map(float, p)) for k, p in enumerate(verts))
    mesh = tuple(Triangle(wall.set_id, tuple(int(first + i) for i in t)) for t in tris)
    contacts = deck.contacts or (Contact((), ()),)
    contacts = (replace(contacts[0], triangles=contacts[0].triangles + mesh),) + contacts[1:]
    return replace(deck, nodes=nodes, contacts=contacts), mesh


def _refilled(design, config, deck: Deck) -> Deck:
    """The cavity refilled (x3dpd.deck.fill); an analytic cavity through its inscribed mesh."""
    wall = _analytic_wall(deck, design.cavity_set)
    if wall is None:
        return _refilled_mesh(design, config, deck, wall_set=None)
    meshed, mesh = _meshed(deck, wall)
    out = _refilled_mesh(design, config, meshed, wall_set=wall.set_id,
                         volume=_wall_volume(deck, wall))
    drop = set(mesh)
    return replace(out, contacts=tuple(replace(c, triangles=tuple(
        t for t in c.triangles if t not in drop)) for c in out.contacts))


def _wall_volume(deck: Deck, wall) -> float:
    """Interior volume of a cylinder (pi R^2 L) or capsule (pi R^2 L + 4/3 pi R^3) [length^3]."""
    length, radius = _wall_length(deck, wall), float(wall.params[0])
    extra = 4.0 / 3.0 * math.pi * radius ** 3 if wall.shape == "capsule" else 0.0
    return math.pi * radius ** 2 * length + extra


def _wall_length(deck: Deck, wall) -> float:
    """|B - A| of an analytic wall's axis nodes [length]."""
    xyz = {nd.nid: np.array([nd.x, nd.y, nd.z]) for nd in deck.nodes}
    return float(np.linalg.norm(xyz[wall.nodes[1]] - xyz[wall.nodes[0]]))


def _refilled_mesh(design, config, deck: Deck, wall_set: int | None,
                   volume: float | None = None) -> Deck:
    """The cavity refilled with the configuration's particles (x3dpd.deck.fill)."""
    v = config.values
    pd = deck.pdmp[0]
    radius = float(v.get("radius", pd.rzero))
    gap = float(v.get("gap", v.get("gap_fraction", 0.0) * radius))
    opts = {"radius": radius, "packing": v.get("packing", "cubic"), "gap": gap,
            "seed": v.get("seed"), "jitter": float(v.get("jitter", 0.0)),
            "set_id": design.cavity_set}
    try:
        volume = volume or fill_positions(deck, n=1, **opts).volume
        one = 4.0 / 3.0 * math.pi * radius ** 3
        if "count" in v:
            n = int(v["count"])
        elif "fill_ratio" in v:
            n = math.floor(v["fill_ratio"] * volume / one + 1e-9)
        elif "particle_mass" in v:
            n = round(v["particle_mass"] / (pd.prho * one))
        else:
            n = sum(1 for nd in deck.nodes if nd.nid > pd.nodlim)
        if n < 1:
            _fail(design, config, f"{n} particles of radius {radius:g}: nothing to fill")
        fill = fill_positions(deck, n=n, **opts)
    except InputError as exc:
        _fail(design, config, str(exc))
    got = fill.positions.shape[0]
    if got < n:
        _fail(design, config, f"only {got} of {n} spheres of radius {radius:g} fit in the "
              f"cavity ({opts['packing']} packing, gap {gap:g}, cavity volume {volume:.6g}); "
              "a fill that cannot fit")
    return filled_deck(deck, fill, opts["set_id"])


def _with_step(design, config, deck: Deck) -> Deck:
    """DTMAX the configuration's ``dt``, else the step ``x3dpd check`` recommends for its
    particles (x3dpd.api.fit_time_step, as ``x3dpd fill``); ITRAC keeps the trace interval."""
    try:
        return fit_time_step(deck, dt=config.values.get("dt")).deck
    except InputError as exc:
        _fail(design, config, f"{exc}; give dt")


def _resolved(deck: Deck, axis: int, values: dict) -> dict:
    """What the configuration came to: material, radius, count, fill ratio, added mass
    [mass], cavity length along the drive and the clearance there (cavity length - the
    particle bed's extent) [length], dt [s]."""
    model = build(deck)
    n = int(model.n_particles)
    pd = deck.pdmp[0] if deck.pdmp else None
    out = {"material": values.get("material", "deck" if n else ""),
           "radius": float(pd.rzero) if (pd and n) else 0.0, "count": n,
           "added_mass": particle_mass(model), "dt": float(deck.parameters.dtmax),
           "fill_ratio": math.nan, "cavity_length": math.nan, "clearance": math.nan}
    wall = _analytic_wall(deck, None)
    if wall is not None:   # along the cylinder's or capsule's axis
        xyz = {nd.nid: np.array([nd.x, nd.y, nd.z]) for nd in deck.nodes}
        a, b = xyz[wall.nodes[0]], xyz[wall.nodes[1]]
        direction = (b - a) / max(np.linalg.norm(b - a), 1e-300)
        extra = 2.0 * float(wall.params[0]) if wall.shape == "capsule" else 0.0
        out["cavity_length"] = _wall_length(deck, wall) + extra
        volume = _wall_volume(deck, wall)
        along = (model.x0[model.particle_start:] - a) @ direction
    else:
        try:
            tri, _ = cavity_triangles(deck, None)
        except InputError:
            return out
        pts = tri.reshape(-1, 3)
        out["cavity_length"] = float(np.ptp(pts[:, axis]))
        volume = fill_positions(deck, n=1, radius=out["radius"] or 1.0).volume
        along = model.x0[model.particle_start:, axis]
    if n:
        out["fill_ratio"] = n * 4.0 / 3.0 * math.pi * out["radius"] ** 3 / volume
        out["clearance"] = out["cavity_length"] - float(np.ptp(along) + 2.0 * out["radius"])
    return out


def write_configurations(made: list[Made], out: Path, design: DesignFile) -> list[Made]:
    """Write each deck to OUT/configs/NAME/NAME.inp (unchanged files left as they are; a deck
    code file copied beside it) and read it back."""
    done = []
    template_dir = design.structure.parent
    for m in made:
        folder = out / "configs" / m.config.name
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{m.config.name}.inp"
        if not path.exists() or path.read_text(encoding="utf-8") != m.text:
            tmp = path.with_name(path.name + ".tmp")
            tmp.write_text(m.text, encoding="utf-8")
            os.replace(tmp, path)
        for code in code_files(m.deck):
            src = (template_dir / code)
            if src.is_file() and not (folder / code).exists():
                (folder / code).parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(src, folder / code)
        done.append(replace(m, path=path, deck=load_deck(path)))
    return done
