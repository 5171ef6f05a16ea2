"""A design configuration that is a multiple individual particle (MIP) damper: drilled plates,
one sphere per hole (report Section 11; the PLATES card, x3dpd.deck.plates), in place of the
structure deck's particles (docs/design.md, "A MIP damper").

The configuration's keys (in ``[mip]``, ``[fill]``, ``[vary]`` or a ``[[configuration]]``)
make one PLATES record per value of ``thickness``: set k for the k-th plate, on the driven
node (the evaluation's node) with the holes' axis along the driven DOF, ``holes`` holes of
diameter ``hole`` at ``pitch`` in a ``plate_size`` square, the ``shim``, ``end_plate`` between
stacked plates, the spheres' ``start`` and ``seed``, ``lumped``. The spheres are the structure
deck's PDMP card's, or ``material`` and ``radius``'s. The deck written keeps the PLATES card
(its reader builds the holes); the structure deck's own plates (a PLATES deck) are replaced.
"""

from __future__ import annotations

import math

import numpy as np

#: The keys of a MIP configuration (x3dpd.design.design_file.CONFIG_KEYS ends with them).
MIP_KEYS = (
    "holes",
    "pitch",
    "hole",
    "thickness",
    "shim",
    "plate_size",
    "end_plate",
    "lumped",
    "start",
)
#: What a MIP configuration must give (the others have defaults: shim 0, end_plate 0, the
#: spheres at rest on the holes' bottoms, not lumped).
MIP_REQUIRED = ("holes", "pitch", "hole", "thickness", "plate_size")


def make_mip(design, template, config, drive, level, made):
    """A MIP damper's configuration (module docstring): its deck with the PLATES card (written
    so) and built (run and checked), made by ``made`` (x3dpd.design.configs' Made of a
    checked deck) at the ``[levels]`` mode of drive ``level`` (None: the deck's own)."""
    from dataclasses import replace

    from x3dpd.api import build, check, fit_time_step
    from x3dpd.api.decks import Title, expand_plates
    from x3dpd.design.baselines import particle_mass
    from x3dpd.design.config_cavity import config_error
    from x3dpd.design.configs import drive_point
    from x3dpd.design.levels import deck_at_level

    if drive is None:
        drive_point(design, template)  # no drive node to put the plates on: its error
    written, deck = mip_decks(design, config, template, drive)
    written = replace(written, title=Title(f"{design.title}\nconfiguration {config.name}"))
    step = fit_time_step(deck, dt=config.values.get("dt"))
    written = deck_at_level(
        design, config, replace(written, parameters=step.deck.parameters), drive, level
    )
    deck = expand_plates(written)
    report = check(deck)
    if report.exit_status != 0:
        first = (report.errors or report.warnings)[0]
        message = getattr(first, "headline", None) or getattr(first, "message", first)
        config_error(design, config, f"the deck made does not check clean: {message}")
    pd = deck.pdmp[0]
    values = {
        "material": config.values.get("material", "deck"),
        "radius": float(pd.rzero),
        "added_mass": particle_mass(build(deck)),
        "dt": float(deck.parameters.dtmax),
        "stiffness_scale": 1.0,
        **mip_values(deck, written),
    }
    return made(design, config, deck, written, values, report, drive, level)


def mip_decks(design, config, template, drive):
    """(the deck to write, with its PLATES card; the same deck built) of a MIP configuration;
    an InputError at the configuration's line."""
    from x3dpd.api.decks import Plate, expand_plates, plated_deck
    from x3dpd.design.config_cavity import config_error
    from x3dpd.design.design_file import CONFIG_KEYS
    from x3dpd.errors import InputError

    v = config.values
    missing = [k for k in MIP_REQUIRED if k not in v]
    if missing:
        config_error(design, config, f"a MIP damper needs {', '.join(missing)} (docs/design.md)")
    # the amount, cavity and packing keys (count ... jitter) place no sphere in a hole
    other = [
        k for k in CONFIG_KEYS[CONFIG_KEYS.index("count") : CONFIG_KEYS.index("seed")] if k in v
    ]
    if other:
        config_error(
            design,
            config,
            f"{', '.join(other)} does not apply to a MIP damper (one "
            "sphere per hole: holes, thickness ... place them)",
        )
    node, dof = drive
    plates = tuple(
        Plate(
            set_id=k + 1,
            master=node,
            holes=int(v["holes"]),
            pitch=float(v["pitch"]),
            hole=float(v["hole"]),
            thickness=float(t),
            size=(float(v["plate_size"]),) * 2,
            shim=float(v.get("shim", 0.0)),
            end=float(v.get("end_plate", 0.0)),
            axis=dof,
            start=v.get("start", "bottom"),
            seed=int(v.get("seed", 0)),
            lumped=bool(v.get("lumped", False)),
        )
        for k, t in enumerate(v["thickness"])
    )
    try:
        deck = plated_deck(
            _structure(template), plates, radius=v.get("radius"), material=v.get("material")
        )
        return deck, expand_plates(deck)
    except InputError as exc:
        config_error(design, config, f"the plates: {getattr(exc, 'message', exc)}")


def _structure(template):
    """The template without its own plates (a PLATES deck as read: their HOLES walls, nodes
    and RBEL slaves), so that a configuration's plates replace them."""
    from dataclasses import replace

    walls = [w for w in template.analytic_walls or () if w.shape == "holes"]
    if not walls:
        return template
    gone = {n for w in walls for n in w.nodes}
    rbels = tuple(
        replace(r, slaves=tuple(s for s in r.slaves if s not in gone), slave_positions=())
        for r in template.rbels
    )
    return replace(
        template,
        analytic_walls=tuple(w for w in template.analytic_walls if w.shape != "holes") or None,
        nodes=tuple(n for n in template.nodes if n.nid not in gone),
        rbels=tuple(r for r in rbels if r.slaves),
    )


def mip_values(deck, plates_deck) -> dict:
    """design.csv's columns of a MIP configuration (its first plate's hole): ``cavity_length``
    the hole's length, ``clearance`` its free length, ``fill_ratio`` a sphere's volume over
    its hole's, ``count`` the spheres (a lumped plate's stand-ins counted as its holes),
    ``cavities`` the plates."""
    first = plates_deck.plates[0]
    r = deck.pdmp[0].rzero
    sphere = 4.0 / 3.0 * math.pi * r**3
    return {
        "count": int(sum(p.holes for p in plates_deck.plates)),
        "cavities": len(plates_deck.plates),
        "cavity_length": first.length,
        "clearance": first.length - 2.0 * r,
        "fill_ratio": sphere / (math.pi * (0.5 * first.hole) ** 2 * first.length),
        "free_lengths": tuple(float(np.round(p.length - 2.0 * r, 12)) for p in plates_deck.plates),
    }
