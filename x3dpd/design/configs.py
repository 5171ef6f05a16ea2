# Over 400 lines: a design's configurations: every [vary] variable's deck edit in one place.
"""The configurations of a design (x3dpd.design.design_file): one deck each, made from the
structure deck by resizing its cavity, filling it (``x3dpd fill``'s library) and setting the
particles' material (x3dpd.materials), then written to ``OUT/configs/NAME/NAME.inp``.

Every deck is made in memory first; a fill that cannot fit, a cavity that cannot be resized or
a deck ``x3dpd check`` does not pass clean is an InputError at the configuration's line, before
anything is written or run. A written deck is read back (:func:`x3dpd.api.load_deck`) and that
deck is what runs, so each configuration's deck runs on its own as it stands
(``x3dpd OUT/configs/NAME/NAME.inp``).

Several cavities (``cavities`` N): the configuration's cavity, as resized and filled, copied
N - 1 times onto the structure's master node(s) with its particles (x3dpd.deck.cavities).

Time step: ``dt`` when the configuration gives one, else the step ``x3dpd check`` recommends
for the configuration's particles (50 steps per contact, x3dpd.model.timestep; shortened to
divide the structure deck's trace interval by :func:`x3dpd.api.fit_time_step`, as ``x3dpd
fill`` does), ITRAC scaled to keep the trace interval. Softer contacts (``stiffness_scale``
f): every modulus of the particles scaled by f and that step lengthened by f^(-2/5)
(:func:`x3dpd.api.soft_step`, as ``x3dpd study --stiffness-scale``).
"""

from __future__ import annotations

import math
import os
import shutil
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from x3dpd.api import (
    build,
    check,
    fit_time_step,
    load_deck,
    rules_of_thumb,
    soft_step,
    softened,
)
from x3dpd.api.decks import (
    Deck,
    Title,
    cavity_set,
    cavity_triangles,
    check_masters,
    default_spacing,
    fill_positions,
    format_deck,
    is_user_file,
    with_cavities,
    with_material,
    with_temperature,
)
from x3dpd.design.baselines import particle_mass, without_particles
from x3dpd.design.config_cavity import (
    analytic_wall,
    config_error,
    refilled,
    resized,
    wall_length,
    wall_volume,
    with_clearance,
)
from x3dpd.design.config_mip import MIP_KEYS, make_mip
from x3dpd.design.design_file import Configuration, DesignFile
from x3dpd.design.levels import deck_at_level
from x3dpd.errors import InputError
from x3dpd.materials import from_kelvin, temperature_unit_for

#: Keys that make a configuration refill its cavity.
REFILL = (
    "radius",
    "count",
    "fill_ratio",
    "particle_mass",
    "cavity_length",
    "cavity_size",
    "cavity_radius",
    "packing",
    "gap",
    "gap_fraction",
    "jitter",
    "seed",
)


@dataclass(frozen=True)
class Made:
    """A configuration's deck: ``path`` of its file, the ``deck`` read back from it, the
    ``values`` it resolved to (material, radius, count, fill ratio, added mass, cavity
    length, clearance, dt) and the evaluation's ``drive`` point (node id, dof)."""

    config: Configuration
    path: Path
    deck: Deck
    values: dict
    text: str
    drive: tuple[int, int] | None = None


def code_files(deck: Deck) -> list[str]:
    """The Python files the deck's USRFRC card names (code that runs with the deck), told from
    the deck's folder as the model builder tells them."""
    folder = Path(deck.path).parent
    return [
        spec.strip() for card in deck.usrfrc for spec in card.specs if is_user_file(spec, folder)
    ]


def make_configurations(design: DesignFile) -> list[Made]:
    """Every configuration's deck, made and checked in memory (files not written yet)."""
    template = load_deck(design.structure)
    code = code_files(template)
    if code and not design.usrfrc_code:
        raise InputError(
            f"{design.where('structure')}: structure: {design.structure.name} names the code "
            f"file {code[0]} (USRFRC), which every configuration would run; a design runs a "
            "deck's code only with usrfrc_code = true"
        )
    _check_masters(design, template)
    try:
        drive = drive_point(design, template)
    except InputError:  # an evaluation needs one: require_drive says so
        drive = None
    if design.levels is None or drive is None:
        return [_make(design, template, c, drive) for c in design.configurations]
    # the structure's own mode at each drive level (x3dpd.design.levels): a deck per level
    drives = design.evaluation.drives
    return [
        _make(
            design,
            template,
            replace(c, name=c.name + (f"_F{f:g}" if len(drives) > 1 else "")),
            drive,
            level=f,
        )
        for c in design.configurations
        for f in drives
    ]


def require_drive(design: DesignFile, made: list[Made]) -> None:
    """Raise :func:`drive_point`'s InputError when the configurations have no drive point
    (before a design writes anything: every evaluation drives and measures one)."""
    if any(m.drive is None for m in made):
        drive_point(design, load_deck(design.structure))


def drive_point(design: DesignFile, template: Deck) -> tuple[int, int]:
    """(node id, dof) the evaluation drives and measures: ``[evaluate] node`` and ``dof``,
    else the structure deck's USRFRC drive, else its cavity's master along x (docs/design.md)
    -- taken from the structure deck, so that a configuration without particles (``count =
    0``: no cavity) is driven where the others are."""
    from x3dpd.design.spec import default_drive_point

    ev = design.evaluation
    node, dof = ev.node, ev.dof
    if node is None or dof is None:
        try:
            d_node, d_dof = default_drive_point(template)
        except InputError:
            raise InputError(
                f"{design.where('evaluate')}: evaluate: {design.structure.name} has no USRFRC "
                "drive and no cavity master node to drive; give node and dof in [evaluate]"
            ) from None
        node, dof = (d_node if node is None else node), (d_dof if dof is None else dof)
    return int(node), int(dof)


def _check_masters(design: DesignFile, template: Deck) -> None:
    """``[cavity] masters``: nodes that can carry the cavity's copies, and used by some
    configuration (one with more than one cavity)."""
    masters = design.cavity_masters
    if masters is None:
        return
    where = f"{design.where('cavity', 'masters')}: cavity.masters"
    try:
        check_masters(template, masters, design.cavity_set)
    except InputError as exc:
        raise InputError(f"{where}: {str(exc).removeprefix('masters: ')}") from None
    if not any(c.values.get("cavities", 1) > 1 for c in design.configurations):
        raise InputError(
            f"{where}: master nodes for several cavities, but no configuration has more than "
            "one (give cavities = N in [fill], [vary] or a [[configuration]])"
        )


def _make(
    design: DesignFile, template: Deck, config: Configuration, drive, level: float | None = None
) -> Made:
    """The configuration's deck, made and checked in memory; ``drive`` its evaluation's
    (node, dof), None when there is none (:func:`require_drive` says so); ``level`` the drive
    whose ``[levels]`` mode the structure takes (x3dpd.design.levels), None: the deck's own."""
    v = config.values
    if any(k in v for k in MIP_KEYS):
        return make_mip(design, template, config, drive, level, _made)
    deck = template
    pd = deck.pdmp[0] if deck.pdmp else None
    if pd is None and any(k in v for k in REFILL + ("material",)) and v.get("count") != 0:
        config_error(
            design,
            config,
            f"{design.structure.name} has no PDMP card to give the "
            "particles a material; start from a deck with particles",
        )
    if "temperature" in v:  # the materials at it, checked here to name the configuration
        try:
            deck = with_temperature(deck, v["temperature"], origin="the design's temperature")
            build(deck)
        except InputError as exc:
            config_error(design, config, f"temperature: {getattr(exc, 'message', exc)}")
    if "material" in v:
        deck = replace(deck, pdmp=(with_material(pd, v["material"], deck.units),) + deck.pdmp[1:])
        pd = deck.pdmp[0]
    dof = drive[1] if drive else (design.evaluation.dof or 1)
    axis = max(0, min(2, dof - 1))  # the axis the evaluation drives along
    if any(k in v for k in ("cavity_length", "cavity_size", "cavity_radius")):
        deck = resized(design, config, deck, axis)
    if v.get("count") == 0:
        deck = without_particles(deck)
    elif any(k in v for k in REFILL):
        deck = refilled(design, config, deck)
    if "clearance" in v:
        deck = with_clearance(design, config, deck, axis)
    if v.get("cavities", 1) > 1 and v.get("count") != 0:
        deck = _with_cavities(design, config, deck, axis)
    deck = _with_step(design, config, deck)
    deck = replace(deck, title=Title(f"{design.title}\nconfiguration {config.name}"))
    deck = deck_at_level(design, config, deck, drive, level)
    report = check(deck)
    if report.exit_status != 0:
        first = (report.errors or report.warnings)[0]
        message = getattr(first, "headline", None) or getattr(first, "message", first)
        config_error(design, config, f"the deck made does not check clean: {message}")
    values = _resolved(deck, axis, v, design.cavity_set)
    return _made(design, config, deck, deck, values, report, drive, level)


def _made(design, config, deck, written, values, report, drive, level) -> Made:
    """The Made of a checked deck (``written``: what its file holds, the same deck or a deck
    whose PLATES card ``deck`` has built)."""
    v = config.values
    values["mass_ratio"] = (
        values["added_mass"] / report.structure_mass if report.structure_mass > 0 else math.nan
    )
    if level is not None:
        values["level"] = level
    values["notes"] = tuple(f"{n.text} ({n.section})" for n in _rules(design, deck, drive))
    head = [
        f"{config.name}.inp: configuration {config.name} of the design {design.path.name}",
        f"Made by `x3dpd design` from {design.structure.name}; do not edit (rerun the design).",
        *(f"  {k} = {val!r}" for k, val in v.items()),
    ]
    if level is not None:
        f, zeta = design.levels.at(level)
        head.append(f"  the structure at the {level:g} drive level: {f:g} Hz, zeta {zeta:g}")
    text = "".join(f"$ {line}".rstrip() + "\n" for line in head) + "$\n" + format_deck(written)
    return Made(config, Path(), deck, values, text, drive)


def _rules(design: DesignFile, deck: Deck, drive: tuple[int, int] | None) -> list:
    """The report's rules of thumb (x3dpd.api.rules_of_thumb) for the configuration under the
    evaluation's drive at its largest level at ``drive`` (node, dof): a sine at the dwell's or
    ring-down's frequency, a sweep over the band; the deck's own USRFRC drive for a ring-down
    without one."""
    ev = design.evaluation
    if not ev.drives or not ev.frequencies:
        return rules_of_thumb(deck)
    if drive is None:
        return []
    node, dof = drive
    amp, lo, hi = (float(v) for v in (max(ev.drives), min(ev.frequencies), max(ev.frequencies)))
    spec = (
        f"sine:node={node},dof={dof},amp={amp!r},hz={lo!r}"
        if lo == hi
        else f"sweep:node={node},dof={dof},amp={amp!r},f0={lo!r},f1={hi!r},rate=1"
    )
    return rules_of_thumb(replace(deck, usrfrc=()), usrfrc=(spec,))


def _with_cavities(design, config, deck: Deck, axis: int) -> Deck:
    """The configuration's cavity and particles copied to ``cavities`` identical cavities
    (x3dpd.deck.cavities): on the masters of ``[cavity] masters``, else side by side on the
    cavity's own master, ``[cavity] spacing`` apart (default: beside each other across the
    drive and gravity)."""
    try:
        spacing = design.cavity_spacing or default_spacing(deck, design.cavity_set, axis)
        return with_cavities(
            deck,
            int(config.values["cavities"]),
            set_id=design.cavity_set,
            masters=design.cavity_masters,
            spacing=spacing,
        )
    except InputError as exc:
        config_error(design, config, f"cavities: {exc}")


def _with_step(design, config, deck: Deck) -> Deck:
    """DTMAX the configuration's ``dt``, else the step ``x3dpd check`` recommends for its
    particles (x3dpd.api.fit_time_step, as ``x3dpd fill``); ITRAC keeps the trace interval. A
    ``stiffness_scale`` f scales the particles' moduli by f and that step by f^(-2/5)."""
    scale = config.values.get("stiffness_scale", 1.0)
    try:
        if scale == 1.0 or not deck.pdmp:  # no particles: nothing to soften
            return fit_time_step(deck, dt=config.values.get("dt")).deck
        if deck.hooke is not None:
            config_error(
                design,
                config,
                "stiffness_scale scales the particles' Hertz moduli "
                "(PDMP E0, E1 ...); this deck's contacts follow its HOOKE card",
            )
        dt = config.values.get("dt") or fit_time_step(deck).dt
        return fit_time_step(softened(deck, scale), dt=soft_step(dt, scale)).deck
    except InputError as exc:
        if str(exc).startswith(str(design.path)):
            raise
        config_error(design, config, f"{exc}; give dt")


def _resolved(deck: Deck, axis: int, values: dict, set_id: int | None) -> dict:
    """What the configuration came to: material, radius, count (over every cavity), cavities,
    fill ratio (of a cavity), added mass [mass], the cavity's length along the drive and the
    clearance there (cavity length - the particle bed's extent) [length], dt [s] and the
    stiffness scale. With several cavities, the deck's own cavity (``set_id``) is measured:
    the others are its copies."""
    model = build(deck)
    n = int(model.n_particles)
    pd = deck.pdmp[0] if deck.pdmp else None
    out = {
        "material": values.get("material", "deck" if n else ""),
        "radius": float(pd.rzero) if (pd and n) else 0.0,
        "count": n,
        "cavities": int(values.get("cavities", 1)) if n else 0,
        "added_mass": particle_mass(model),
        "dt": float(deck.parameters.dtmax),
        "stiffness_scale": float(values.get("stiffness_scale", 1.0)) if n else 1.0,
        "temperature": _degrees(deck, model),
        "fill_ratio": math.nan,
        "cavity_length": math.nan,
        "clearance": math.nan,
    }
    try:
        sid = cavity_set(deck, set_id)
    except InputError:
        return out
    x = model.x0[model.particle_start :]
    if n:
        x = x[model.particle_cavity == list(model.cavity_set_ids).index(sid)]
    wall = analytic_wall(deck, sid)
    if wall is not None:  # along the cylinder's or capsule's axis
        xyz = {nd.nid: np.array([nd.x, nd.y, nd.z]) for nd in deck.nodes}
        a, b = xyz[wall.nodes[0]], xyz[wall.nodes[1]]
        direction = (b - a) / max(np.linalg.norm(b - a), 1e-300)
        extra = 2.0 * float(wall.params[0]) if wall.shape == "capsule" else 0.0
        out["cavity_length"] = wall_length(deck, wall) + extra
        volume = wall_volume(deck, wall)
        along = (x - a) @ direction
    else:
        tri, _ = cavity_triangles(deck, sid)
        pts = tri.reshape(-1, 3)
        out["cavity_length"] = float(np.ptp(pts[:, axis]))
        try:
            volume = fill_positions(deck, n=1, radius=out["radius"] or 1.0, set_id=sid).volume
        except InputError:  # not a closed cavity (a wall): no volume to fill
            volume = math.nan
        along = x[:, axis]
    if n:
        out["fill_ratio"] = along.size * 4.0 / 3.0 * math.pi * out["radius"] ** 3 / volume
        out["clearance"] = out["cavity_length"] - float(np.ptp(along) + 2.0 * out["radius"])
    return out


def _degrees(deck: Deck, model) -> float:
    """The operating temperature of a deck with a TEMPERATURE card on its UNITS card's scale
    (degF for inch decks, degC for metric ones) to 12 digits, NaN without one."""
    if model.temperature is None:
        return math.nan
    system = deck.unit_system
    degrees = from_kelvin(model.temperature.operating, temperature_unit_for(system))
    return float(f"{degrees:.12g}")  # 70 F back as 70, not 69.99999999999996


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
            src = template_dir / code
            if src.is_file() and not (folder / code).exists():
                (folder / code).parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(src, folder / code)
        done.append(replace(m, path=path, deck=load_deck(path)))
    return done
