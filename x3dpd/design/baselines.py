"""Baselines of a damper design (report Section 8.3, Figures 45-48): the structure without its
particles (``undamped``) and with their mass added rigidly to the driven node (``added-mass``).

When what is left is a linear single-degree-of-freedom structure -- one body (a node and the
nodes rigidly linked to it) free along the driven direction only, springs and dashpots to ground
-- its steady-state response to F sin(w t) is known in closed form (any vibration textbook;
report Section 8.2's model, Figure 43):

    X = F / sqrt((k - m w^2)^2 + (c w)^2),   phi = -atan2(c w, k - m w^2),

with m the body's mass, k and c the sums of the springs' stiffness and damping along the drive.
The energy the dashpot dissipates per cycle is pi c w X^2. A modal structure (MODAL card) without
other springs is linear too: its receptance from the modes (x3dpd.physics.modal.receptance),
the deck's mass and, for the added-mass baseline, the particles' mass coupled in
(x3dpd.model.build_modal). Anything else is simulated.

A base drive (the base node moved on u = U sin(w t), x3dpd.design.drive) has a closed form when
the structure is a linear SDOF on that base: one body free along the drive only, springs and
dashpots k_b, c_b to the base node and k_g, c_g to ground (:class:`BaseSdof`):

    m x'' + (c_b + c_g) x' + (k_b + k_g) x = k_b u + c_b u',
    X / U = T(w) = (k_b + i c_b w) / (k_b + k_g - m w^2 + i (c_b + c_g) w),

the absolute motion's transmissibility (with k_g = c_g = 0 the textbook (k + i c w) /
(k - m w^2 + i c w)). Any other linear structure -- lumped masses on springs to each other, to
ground and to the base, modes with springs attached, under a force or a base drive -- is solved in
the frequency domain by x3dpd.design.linear_system (x3dpd.design.closed_form picks the form).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from x3dpd.api.decks import Deck, Mass, build_model
from x3dpd.api.structures import (  # noqa: F401  (re-exported: their old home)
    ModalLinear,
    Model,
    Sdof,
    linear_modal,
    linear_sdof,
    rigid_body,
)
from x3dpd.errors import InputError

#: Baseline names accepted by ``--baseline``, in the order they are run.
BASELINES = ("undamped", "added-mass")


@dataclass(frozen=True)
class BaseSdof:
    """A linear SDOF on a moving base (module doc): mass m [mass], spring k_base [force/length]
    and dashpot c_base [force s/length] to the base, k_ground and c_ground to ground; ``body``
    the node id of its (master) node."""

    m: float
    k_base: float
    c_base: float
    k_ground: float
    c_ground: float
    body: int

    def transmissibility(self, omega: float) -> complex:
        """T = X / U, the body's complex absolute amplitude per base amplitude at ``omega``."""
        k, c = self.k_base + self.k_ground, self.c_base + self.c_ground
        return complex(self.k_base, self.c_base * omega) / complex(k - self.m * omega**2, c * omega)

    def response(self, base_amplitude: float, omega: float) -> tuple[float, float]:
        """Steady-state amplitude X [length] and phase [rad] against the base's sin(omega t)
        under a base motion of amplitude ``base_amplitude`` [length]."""
        t = self.transmissibility(omega)
        return abs(base_amplitude * t), math.atan2(t.imag, t.real)

    def dissipated_per_cycle(self, base_amplitude: float, omega: float) -> float:
        """Energy the dashpots take per cycle, pi w (c_b |X - U|^2 + c_g |X|^2) [force length]
        (= the base's work per cycle in the steady state)."""
        x = base_amplitude * self.transmissibility(omega)
        return (
            math.pi
            * omega
            * (self.c_base * abs(x - base_amplitude) ** 2 + self.c_ground * abs(x) ** 2)
        )


def base_sdof(model: Model, base: int, dof: int) -> BaseSdof | None:
    """The closed-form SDOF of a particle-free model whose ``base`` node is moved along
    ``dof``, or None.

    None unless: no particles, no modal structure, ``dof`` a translation; the springs from the
    base's side (the base and the rigid body it is master of) lead to one body (a node and the
    nodes rigidly linked to it), free along ``dof`` only; every other node is fixed along
    ``dof``; every spring joins that body to the base's side or to ground (or the base's side
    to ground, which the base's motion overrides), along the global axes (MATID type 1).
    """
    if model.n_particles or model.modal is not None or dof not in (1, 2, 3):
        return None
    if model.axial_nodes.shape[0] or model.rotational_nodes.shape[0]:
        return None
    try:
        i = model.index_of(base)
    except KeyError:
        return None
    d = dof - 1
    base_side, _, master = rigid_body(model, i)
    if master != i:
        return None
    partners = {
        int(b if a in base_side else a)
        for a, b in model.spring_nodes
        if (a in base_side) != (b in base_side) and a >= 0 and b >= 0
    }
    if not partners:
        return None
    body, mass, body_master = rigid_body(model, partners.pop())
    if any(p not in body for p in partners):
        return None
    free = ~model.fixed[body_master]
    if not free[d] or np.count_nonzero(free) != 1:
        return None
    others = [j for j in range(model.n_nodes) if j not in body and j not in base_side]
    if others and not np.all(model.fixed[others, d]):
        return None
    k_b = c_b = k_g = c_g = 0.0
    for (a, b), ks, cs in zip(model.spring_nodes, model.spring_k, model.spring_c):
        ends = {
            ("body" if n in body else "base" if n in base_side else "ground" if n < 0 else "other")
            for n in (int(a), int(b))
        }
        if ends == {"body", "base"}:
            k_b += float(ks[d])
            c_b += float(cs[d])
        elif ends == {"body", "ground"}:
            k_g += float(ks[d])
            c_g += float(cs[d])
        elif "other" in ends or ends == {"body"}:
            return None
    if not (mass > 0 and k_b > 0):
        return None
    return BaseSdof(mass, k_b, c_b, k_g, c_g, int(model.node_ids[body_master]))


def base_structure(model: Model, base: int, dof: int, response: tuple[int, int]) -> BaseSdof | None:
    """The :class:`BaseSdof` measured at ``response`` (node, dof): its body along the drive,
    else None (simulated)."""
    sdof = base_sdof(model, base, dof)
    if sdof is None or response[1] != dof:
        return None
    try:
        i = model.index_of(response[0])
    except KeyError:
        return None
    body, _, _ = rigid_body(model, model.index_of(sdof.body))
    return sdof if i in body else None


def cavity_master(deck: Deck) -> int | None:
    """The RBEL master of the first wall node (CONTACT triangles' first nodes, then analytic
    walls') that is linked to one, or None."""
    walls = [tri.nodes[0] for contact in deck.contacts for tri in contact.triangles]
    walls += [w.nodes[0] for w in deck.analytic_walls or ()]
    for node in walls:
        for rb in deck.rbels:
            if node in rb.slaves or node == rb.master:
                return rb.master
    return None


def base_mass_node(deck: Deck, base: int, dof: int) -> int | None:
    """Where a base drive's added-mass baseline puts the particles' mass: the body of the
    undamped structure's :class:`BaseSdof`, else the first cavity's master, else None."""
    sdof = base_sdof(build_model(without_particles(deck)), base, dof)
    return sdof.body if sdof is not None else cavity_master(deck)


def linear_structure(model: Model, node: int, dof: int, response: tuple[int, int] | None = None):
    """The closed-form linear structure of a particle-free model driven at ``node`` along
    ``dof``: an :class:`Sdof`, a :class:`ModalLinear`, or None (see :func:`linear_sdof`,
    :func:`linear_modal`). ``response`` (node, dof): measured there instead (a modal structure
    only: an SDOF's other nodes do not move)."""
    if response is None or tuple(response) == (node, dof):
        return linear_sdof(model, node, dof) or linear_modal(model, node, dof)
    drive = linear_modal(model, node, dof)
    if drive is None:
        return None
    try:
        i = model.index_of(response[0])
    except KeyError:
        return None
    return drive.measured_at(model.modal.shape_at(i, response[1] - 1))


def particle_mass(model: Model) -> float:
    """Total mass of the particles of a built model [mass]."""
    return float(np.sum(model.mass[model.particle_start :]))


def without_particles(deck: Deck) -> Deck:
    """The deck with its particles removed (the undamped structure), and with them the cards
    that describe them or their walls: PDMP, CONTACT, the analytic walls, HOOKE and FRICTION
    (records per PDMP group) and WALLMAT (per CONTACT set)."""
    if not deck.pdmp:
        return deck
    first = min(p.nodlim for p in deck.pdmp)
    keep = {n.nid for n in deck.nodes if n.nid <= first}
    trace = deck.trace
    if trace is not None:
        nodes = tuple(n for n in trace.nodes if n in keep)
        trace = replace(trace, nodes=nodes, positions=()) if nodes else None
    return replace(
        deck,
        pdmp=(),
        contacts=(),
        analytic_walls=None,
        hooke=None,
        friction=None,
        wallmat=None,
        trace=trace,
        nodes=tuple(n for n in deck.nodes if n.nid in keep),
        initials=tuple(i for i in deck.initials if i.nid in keep),
    )


def with_added_mass(deck: Deck, node: int, mass: float) -> Deck:
    """The particle-free deck with ``mass`` added to ``node``'s MASS record (added-mass baseline).
    A modal structure couples it into its modes (HOUSING added; with HOUSING included the
    deck's mass on modal nodes is taken as already in the modes, so there is no such baseline).
    """
    if deck.modal is not None and deck.modal.housing == "included":
        raise InputError(
            "the added-mass baseline needs the deck's mass to be added to the modes "
            "(MODAL HOUSING added); this deck's modes include its housing"
        )
    bare = without_particles(deck)
    masses = list(bare.masses)
    for i, rec in enumerate(masses):
        if rec.nid == node:
            masses[i] = replace(rec, mass=rec.mass + mass)
            break
    else:
        masses.append(Mass(nid=node, mass=mass, ixx=0.0, iyy=0.0, izz=0.0))
    return replace(bare, masses=tuple(masses))


def baseline_decks(deck: Deck, names, node: int | None) -> dict[str, Deck]:
    """The baseline decks asked for, by name (``BASELINES``); ``node`` takes the particles'
    mass in the added-mass one (the driven node; a base drive's :func:`base_mass_node`)."""
    unknown = [n for n in names if n not in BASELINES]
    if unknown:
        raise InputError(
            f"--baseline: unknown baseline {unknown[0]!r}; expected a comma list "
            f"of {', '.join(BASELINES)}"
        )
    out = {}
    if "undamped" in names:
        out["undamped"] = without_particles(deck)
    if "added-mass" in names:
        if node is None:
            raise InputError(
                "--baseline added-mass: with --drive base the particles' mass goes "
                "to the body spring-mounted on the base, or to the first cavity's "
                "master; this deck has neither"
            )
        out["added-mass"] = with_added_mass(deck, node, particle_mass(build_model(deck)))
    return out
