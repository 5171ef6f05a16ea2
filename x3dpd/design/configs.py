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

from x3dpd.api import build, check, fit_time_step, load_deck
from x3dpd.deck.cards import Deck, Node, Title
from x3dpd.deck.fill import _box, cavity_triangles, fill_positions, filled_deck, with_material
from x3dpd.deck.writer import format_deck
from x3dpd.design.baselines import particle_mass, without_particles
from x3dpd.design.design_file import Configuration, DesignFile
from x3dpd.errors import InputError
from x3dpd.physics.usrfrc import is_user_file

#: Keys that make a configuration refill its cavity.
REFILL = ("radius", "count", "fill_ratio", "particle_mass", "cavity_length", "cavity_size",
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
    if "cavity_length" in v or "cavity_size" in v:
        deck = _resized(design, config, deck, axis)
    if v.get("count") == 0:
        deck = without_particles(deck)
    elif any(k in v for k in REFILL):
        deck = _refilled(design, config, deck)
    deck = _with_step(design, config, deck)
    deck = replace(deck, title=Title(f"{design.title}\nconfiguration {config.name}"))
    report = check(deck)
    if report.exit_status != 0:
        first = (report.errors or report.warnings)[0]
        _fail(design, config, f"the deck made does not check clean: {getattr(first, 'message', first)}")
    values = _resolved(deck, axis, v)
    values["mass_ratio"] = (values["added_mass"] / report.structure_mass
                            if report.structure_mass > 0 else math.nan)
    head = [f"{config.name}.inp: configuration {config.name} of the design {design.path.name}",
            f"Made by `x3dpd design` from {design.structure.name}; do not edit (rerun the design).",
            *(f"  {k} = {val!r}" for k, val in v.items())]
    text = "".join(f"$ {line}".rstrip() + "\n" for line in head) + "$\n" + format_deck(deck)
    return Made(config, Path(), deck, values, text)


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


def _resized(design, config, deck: Deck, axis: int) -> Deck:
    """The deck with its box cavity (CONTACT set) resized about its low corner."""
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


def _refilled(design, config, deck: Deck) -> Deck:
    """The cavity refilled with the configuration's particles (x3dpd.deck.fill)."""
    v = config.values
    pd = deck.pdmp[0]
    radius = float(v.get("radius", pd.rzero))
    gap = float(v.get("gap", v.get("gap_fraction", 0.0) * radius))
    opts = {"radius": radius, "packing": v.get("packing", "cubic"), "gap": gap,
                "seed": v.get("seed"), "jitter": float(v.get("jitter", 0.0)), "set_id": design.cavity_set}
    try:
        volume = fill_positions(deck, n=1, **opts).volume
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
    return filled_deck(deck, fill, design.cavity_set)


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
    try:
        tri, _ = cavity_triangles(deck, None)
    except InputError:
        return out
    pts = tri.reshape(-1, 3)
    out["cavity_length"] = float(np.ptp(pts[:, axis]))
    if n:
        fill = fill_positions(deck, n=1, radius=out["radius"])
        out["fill_ratio"] = n * 4.0 / 3.0 * math.pi * out["radius"] ** 3 / fill.volume
        x = model.x0[model.particle_start:, axis]
        out["clearance"] = out["cavity_length"] - float(np.ptp(x) + 2.0 * out["radius"])
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
        if not path.exists() or path.read_text() != m.text:
            tmp = path.with_name(path.name + ".tmp")
            tmp.write_text(m.text)
            os.replace(tmp, path)
        for code in code_files(m.deck):
            src = (template_dir / code)
            if src.is_file() and not (folder / code).exists():
                (folder / code).parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(src, folder / code)
        done.append(replace(m, path=path, deck=load_deck(path)))
    return done
