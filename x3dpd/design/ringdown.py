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
from x3dpd.api.decks import Deck
from x3dpd.api.measurements import G_IN_S2, Ringdown, damping_vs_amplitude, rest_offset
from x3dpd.errors import InputError

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
    g: float = G_IN_S2,
    **options,
) -> Ringdown:
    """Drive a deck (its USRFRC card, or ``drive`` specs) until ``drive_until``, release it and
    record ``ring`` seconds of free ring-down of ``node`` along ``dof``; analyse that."""
    if dof not in (1, 2, 3):
        raise InputError(f"--dof {dof}: the ring-down reads a coordinate, dof 1, 2 or 3")
    driven = run_config(
        deck, tmax=drive_until, dt=dt, usrfrc=drive, keep_trace=False, trace_nodes=(node,)
    )
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
