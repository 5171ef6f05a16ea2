"""A structure whose own frequency and damping depend on the drive level (report Section 11.3,
Table 6: the MIP test apparatus from 132 Hz, zeta 0.047 at 150 lbf to 127 Hz, 0.070 at 1200
lbf), so that a damper is credited only with what it adds to the structure at that level.

A design's ``[levels]`` table (docs/design.md) lists the structure's natural frequency f and
damping ratio zeta at drive levels F; at a drive between two levels both are interpolated
linearly in F, and a drive outside the table is an error. At each drive the spring-mounted
structure (the driven node's MATID type 1 spring to ground, x3dpd.model.linear_structure) gets

    k = m (2 pi f)^2,    c = 2 zeta sqrt(k m),

m its mass along the drive without the particles, so that its undamped baseline (the deck
without particles, in closed form) is the level's measured mode, and the damper's and the
baselines' runs share that structure.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from x3dpd.api.decks import Deck, build_model, expand_plates
from x3dpd.api.structures import linear_sdof
from x3dpd.errors import InputError


#: The keys of ``[levels]``.
LEVEL_KEYS = ("force", "frequency", "zeta")


@dataclass(frozen=True)
class Levels:
    """``[levels]``: the structure's frequency [Hz] and damping ratio at drive levels."""

    force: tuple[float, ...]
    frequency: tuple[float, ...]
    zeta: tuple[float, ...]

    def at(self, drive: float) -> tuple[float, float]:
        """(f, zeta) at ``drive``, linear in the drive between the table's levels."""
        lo, hi = self.force[0], self.force[-1]
        if not lo <= drive <= hi:
            raise InputError(
                f"a drive of {drive:g} is outside the levels' table ({lo:g} to {hi:g}): "
                "give its frequency and zeta in [levels]"
            )
        return (
            float(np.interp(drive, self.force, self.frequency)),
            float(np.interp(drive, self.force, self.zeta)),
        )


def at_level(deck: Deck, node: int, dof: int, frequency: float, zeta: float) -> Deck:
    """``deck`` with the spring to ground of ``node`` along ``dof`` (1-3) and its damper set to
    the mode ``frequency`` [Hz], ``zeta`` (module docstring); a deck with a PLATES card keeps
    it (the card is built only to find the structure's mass)."""
    model = build_model(expand_plates(deck))  # a PLATES card not built yet: built here
    sdof = linear_sdof(model, node, dof, ignore_particles=True)
    springs = [
        e for e in deck.elements if len(e.nodes) == 1 and e.nodes[0] == node and _spring(deck, e)
    ]
    shared = [e for e in deck.elements if springs and e.mid == springs[0].mid]
    if sdof is None or len(springs) != 1 or len(shared) != 1:
        raise InputError(
            f"[levels] set a spring-mounted structure's mode: node {node} needs one MATID "
            "type 1 spring to ground of its own along the drive (it has "
            f"{len(springs)}), on a structure that is a linear SDOF there"
        )
    k = sdof.m * (2.0 * math.pi * frequency) ** 2
    c = 2.0 * zeta * math.sqrt(k * sdof.m)
    axis = ("kx", "ky", "kz")[dof - 1]
    materials = tuple(
        replace(m, **{axis: k}, c=c) if m.mid == springs[0].mid else m for m in deck.materials
    )
    return replace(deck, materials=materials)


def deck_at_level(design, config, deck: Deck, drive, level) -> Deck:
    """A design configuration's ``deck`` with the structure's mode at drive ``level`` (None:
    as it is) at the evaluation's ``drive`` (node, dof); an InputError at its line."""
    from x3dpd.design.config_cavity import config_error

    if level is None:
        return deck
    f, zeta = design.levels.at(level)
    try:
        return at_level(deck, drive[0], drive[1], f, zeta)
    except InputError as exc:
        config_error(design, config, str(exc))


def _spring(deck: Deck, element) -> bool:
    return any(m.mid == element.mid and m.mtype == 1 for m in deck.materials)


def read_levels(r, table: dict, ev):
    """A design file's ``[levels]`` (``r`` its x3dpd.design.design_reader.Reader, ``ev`` its
    evaluation): equal lists, drive levels rising, every drive of
    ``[evaluate]`` inside them; None without the table."""
    if not table:
        return None
    r.known(table, LEVEL_KEYS, ("levels",))
    lists = {}
    for k in LEVEL_KEYS:
        if not isinstance(table.get(k), list) or not table[k]:
            r.fail(("levels", k), f"expected {k} = [...], one value per level")
        lists[k] = tuple(float(r.number(v, ("levels", k))) for v in table[k])
    if len({len(v) for v in lists.values()}) > 1:
        r.fail(("levels",), "force, frequency and zeta need one value per level each")
    if any(b <= a for a, b in zip(lists["force"], lists["force"][1:])):
        r.fail(("levels", "force"), "expected rising drive levels")
    if any(z >= 1.0 for z in lists["zeta"]):
        r.fail(("levels", "zeta"), "expected damping ratios below 1")
    levels = Levels(lists["force"], lists["frequency"], lists["zeta"])
    for drive in ev.drives:
        try:
            levels.at(drive)
        except InputError as exc:
            r.fail(("evaluate", "drives"), str(exc))
    if ev.kind == "ringdown":
        r.fail(("levels",), "a ring-down releases its drive: give [levels] with a sweep or dwell")
    return levels
