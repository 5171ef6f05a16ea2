"""Baselines of a damper design (report Section 8.3, Figures 45-48): the structure without its
particles (``undamped``) and with their mass added rigidly to the driven node (``added-mass``).

When what is left is a linear single-degree-of-freedom structure -- one body (a node and the
nodes rigidly linked to it) free along the driven direction only, springs and dashpots to ground
-- its steady-state response to F sin(w t) is known in closed form (any vibration textbook;
report Section 8.2's model, Figure 43):

    X = F / sqrt((k - m w^2)^2 + (c w)^2),   phi = -atan2(c w, k - m w^2),

with m the body's mass, k and c the sums of the springs' stiffness and damping along the drive.
The energy the dashpot dissipates per cycle is pi c w X^2. Anything else is simulated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from x3dpd.deck.cards import Deck, Mass
from x3dpd.errors import InputError
from x3dpd.model.build import build_model
from x3dpd.model.model import Model

#: Baseline names accepted by ``--baseline``, in the order they are run.
BASELINES = ("undamped", "added-mass")


@dataclass(frozen=True)
class Sdof:
    """A linear SDOF structure: mass m, stiffness k [force/length], damping c [force s/length]."""

    m: float
    k: float
    c: float

    def response(self, drive: float, omega: float) -> tuple[float, float]:
        """Steady-state amplitude X [length] and phase phi [rad] under drive sin(omega t)."""
        re, im = self.k - self.m * omega ** 2, self.c * omega
        return drive / math.hypot(re, im), -math.atan2(im, re)

    def dissipated_per_cycle(self, amplitude: float, omega: float) -> float:
        """Energy the dashpot takes per cycle, pi c w X^2 [force length]."""
        return math.pi * self.c * omega * amplitude ** 2


def particle_mass(model: Model) -> float:
    """Total mass of the particles of a built model [mass]."""
    return float(np.sum(model.mass[model.particle_start:]))


def without_particles(deck: Deck) -> Deck:
    """The deck with its particles, PDMP and CONTACT cards removed (the undamped structure)."""
    if not deck.pdmp:
        return deck
    first = min(p.nodlim for p in deck.pdmp)
    keep = {n.nid for n in deck.nodes if n.nid <= first}
    trace = deck.trace
    if trace is not None:
        nodes = tuple(n for n in trace.nodes if n in keep)
        trace = replace(trace, nodes=nodes, positions=()) if nodes else None
    return replace(deck, pdmp=(), contacts=(), trace=trace,
                   nodes=tuple(n for n in deck.nodes if n.nid in keep),
                   initials=tuple(i for i in deck.initials if i.nid in keep))


def with_added_mass(deck: Deck, node: int, mass: float) -> Deck:
    """The particle-free deck with ``mass`` added to ``node``'s MASS record (added-mass baseline)."""
    bare = without_particles(deck)
    masses = list(bare.masses)
    for i, rec in enumerate(masses):
        if rec.nid == node:
            masses[i] = replace(rec, mass=rec.mass + mass)
            break
    else:
        masses.append(Mass(nid=node, mass=mass, ixx=0.0, iyy=0.0, izz=0.0))
    return replace(bare, masses=tuple(masses))


def linear_sdof(model: Model, node: int, dof: int) -> Sdof | None:
    """The closed-form SDOF of a particle-free model driven at ``node`` along ``dof``, or None.

    None unless: no particles; ``dof`` is a translation (1-3); the driven node's body (the node,
    or the rigid body it is master of) is free along ``dof`` and fixed in every other DOF; every
    other node is fixed along ``dof``; every spring joins the body to ground along the global
    axes (MATID type 1: an axial or rotational element, types 2 and 3, is not in this form).
    """
    if model.n_particles or dof not in (1, 2, 3):
        return None
    if model.axial_nodes.shape[0] or model.rotational_nodes.shape[0]:
        return None
    try:
        i = model.index_of(node)
    except KeyError:
        return None
    d = dof - 1
    body = {i}
    mass = float(model.mass[i])
    for b, master in enumerate(model.rigid_master):
        if master == i:
            body |= set(model.rigid_slaves[model.rigid_ptr[b]:model.rigid_ptr[b + 1]].tolist())
            mass = float(model.rigid_mass[b])
        elif i in model.rigid_slaves[model.rigid_ptr[b]:model.rigid_ptr[b + 1]]:
            return None
    free = ~model.fixed[i]
    if not free[d] or np.count_nonzero(free) != 1:
        return None
    others = [j for j in range(model.n_nodes) if j not in body]
    if others and not np.all(model.fixed[others, d]):
        return None
    k = c = 0.0
    for (a, b), ks, cs in zip(model.spring_nodes, model.spring_k, model.spring_c):
        if b != -1 or a not in body:
            return None
        k += float(ks[d])
        c += float(cs[d])
    return Sdof(m=mass, k=k, c=c) if mass > 0 and k > 0 else None


def baseline_decks(deck: Deck, names, node: int) -> dict[str, Deck]:
    """The baseline decks asked for, by name (``BASELINES``)."""
    unknown = [n for n in names if n not in BASELINES]
    if unknown:
        raise InputError(f"--baseline: unknown baseline {unknown[0]!r}; expected a comma list "
                         f"of {', '.join(BASELINES)}")
    out = {}
    if "undamped" in names:
        out["undamped"] = without_particles(deck)
    if "added-mass" in names:
        out["added-mass"] = with_added_mass(deck, node, particle_mass(build_model(deck)))
    return out
