"""A deck driven and then released: the ring-down a design evaluates (x3dpd.design.design_runs)
and ``x3dpd ringdown DECK`` runs (x3dpd.testlab.ringdown), with its run configured once and the
free part continuing it (report Section 4.1, Figure 6).

The analysis itself (Hilbert envelope, matched-slope spline, local log decrement) is
:func:`x3dpd.analysis.ringdown.damping_vs_amplitude`.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.api import run, run_config
from x3dpd.api.decks import Deck, build_model
from x3dpd.api.measurements import (
    Ringdown,
    cycles_needed,
    damping_vs_amplitude,
    rest_offset,
)
from x3dpd.errors import InputError
from x3dpd.units import standard_gravity

#: Samples per cycle recorded for a deck's ring-down (the analysis needs >= ~20).
SAMPLES_PER_CYCLE = 100


def signal_of(time: np.ndarray, position: np.ndarray, dof: int, g: float, **options) -> Ringdown:
    """Ring-down analysis of one node's coordinate along ``dof`` about its rest position."""
    x = position[:, dof - 1]
    return damping_vs_amplitude(time, x - rest_offset(x), g=g, **options)


def ringdown_of_deck(
    deck: Deck,
    node: int,
    dof: int,
    *,
    drive_until: float,
    ring: float,
    drive: tuple[str, ...] = (),
    dt: float | None = None,
    g: float | None = None,
    **options,
) -> Ringdown:
    """Drive a deck (its USRFRC card, or ``drive`` specs) until ``drive_until``, release it and
    record ``ring`` seconds of free ring-down of ``node`` along ``dof``; analyse that. ``g``:
    one standard gravity for dB re 1 g, by default in the deck's units (its UNITS card)."""
    if g is None:
        g = standard_gravity(deck.unit_system)
    if dof not in (1, 2, 3):
        raise InputError(f"--dof {dof}: the ring-down reads a coordinate, dof 1, 2 or 3")
    driven = run_config(
        deck, tmax=drive_until, dt=dt, usrfrc=drive, keep_trace=False, trace_nodes=(node,)
    )
    reason = ring_too_short(driven.model, node, dof, ring, **options)
    if reason is not None:
        raise InputError(f"ring {ring:g} s (--ring, a design's ring): {reason}")
    forced = run(driven)
    period = _period(driven.model, node, dof)
    itrac = max(1, int(period / (SAMPLES_PER_CYCLE * driven.step.dt)))
    free = run(
        driven,  # the same run released: the drive replaced by none, recorded finely
        tmax=forced.summary["t_end"] + ring,
        usrfrc=(f"constant:node={node},dof={dof},amp=0",),
        usrfrc_mode="replace",
        initial_state=forced.final_state,
        itrac=itrac,
        keep_trace=True,
    )
    return signal_of(free.trace.time, free.trace.position[:, 0], dof, g, **options)


def _period(model, node: int, dof: int) -> float:
    """A guess of the structure's period for the recording rate: 2 pi sqrt(m / k), or a modal
    structure's first mode's."""
    i = model.index_of(node)
    ms = model.modal
    if ms is not None and i in set(ms.nodes.tolist()) and np.any(ms.omega > 0):
        return 2.0 * math.pi / float(ms.omega[ms.omega > 0].min())
    k = float(np.sum(model.spring_k[:, dof - 1]))
    m = float(np.sum(model.rigid_mass)) if model.rigid_mass.size else float(model.mass[i])
    return 2.0 * math.pi * math.sqrt(m / k) if k > 0 and m > 0 else 0.01


def ring_too_short(model, node: int, dof: int, ring: float, **options) -> str | None:
    """Why ``ring`` [s] is too short for the analysis, or None, on a structure whose frequency
    is known before the run: one rigid body on one spring element along ``dof`` (the report's
    beams), f = sqrt(k / m) / (2 pi) with m the body's mass. Its particles only add mass, so
    the ring holds fewer cycles than this bound counts: a refusal is safe. Other structures
    are checked by the analysis after the run (None here)."""
    i = model.index_of(node)
    k = model.spring_k[:, dof - 1]
    if model.modal is not None or model.rigid_mass.size != 1 or np.count_nonzero(k) != 1:
        return None
    if i != int(model.rigid_master[0]) or not np.any(model.spring_nodes[k != 0] == i):
        return None
    f = math.sqrt(float(k[k != 0][0]) / float(model.rigid_mass[0])) / (2.0 * math.pi)
    pieces = {key: options[key] for key in ("piece_cycles", "trim_cycles") if key in options}
    needed = cycles_needed(**pieces)
    if ring * f >= needed:
        return None
    return (
        f"at most {ring * f:.1f} cycles of the structure's {f:.4g} Hz (its particles only lower "
        f"it); the ring-down analysis needs at least {needed:.0f}: give {1.5 * needed / f:.2g} s "
        "or more (half again: the particles' mass and the record's first and last zero "
        "crossings take some)"
    )


def check_design_rings(design, made) -> None:
    """A ring-down design's ``ring`` against every configuration (:func:`ring_too_short`),
    before anything runs or is written: the first too short, at the file's line."""
    ev = design.evaluation
    if ev.kind != "ringdown":
        return
    for m in made:
        if m.drive is None:
            continue
        reason = ring_too_short(build_model(m.deck), m.drive[0], m.drive[1], ev.ring)
        if reason is not None:
            raise InputError(
                f"{design.where('evaluate', 'ring')}: evaluate.ring = {ev.ring:g} s, "
                f"configuration {m.config.name}: {reason}"
            )
