"""The settings a study runs: a ladder of time steps and the scene's fidelity choices.

A :class:`Setting` says how one run differs from the deck: its step ``dt``, its contact law
(``"deck"`` as written, or ``"elastic"``: the Maxwell terms dropped, Hertz with the long-term
modulus E0), its friction law, its contact stiffness (``stiffness``: every modulus of the
particles' law scaled, E0, E1, E2 ..., the relaxation times kept, with the step lengthened to
match, :func:`x3dpd.api.soft_step`), and, for a perturbed repeat, the seed of the perturbation.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from x3dpd.api import soft_step, softened

#: Default ladder of steps, as multiples of the deck's DTMAX.
LADDER = (0.25, 0.5, 1.0, 2.0, 4.0, 8.0)
#: Perturbed repeats of the deck's own setting for a chaotic scene.
REPEATS = 3
#: Size of a repeat's perturbation of particle positions, as a fraction of the radius.
PERTURBATION = 1e-9
#: The tangential laws a study offers as fidelity choices (docs/physics.md): the report's
#: regularised and bare Coulomb laws and Hertz-Mindlin with its tangential history.
FRICTION_CHOICES = ("regularized", "coulomb", "mindlin")


@dataclass(frozen=True)
class Setting:
    """One run of a study: ``dt`` [s], ``contact`` ("deck" | "elastic"), ``friction``
    ("regularized" | "coulomb" | "mindlin"), ``repeat`` (0: unperturbed; k: perturbed with seed k),
    ``own`` (the deck's own setting), ``auto`` (a step chosen by accuracy up to ``dt``)."""

    dt: float
    contact: str = "deck"
    friction: str = "regularized"
    repeat: int = 0
    own: bool = False
    auto: bool = False  # the step chosen by accuracy (x3dpd.run(dt="auto")) up to dt
    stiffness: float = 1.0  # the particles' moduli scaled by this (softer contacts)

    @property
    def label(self) -> str:
        parts = [f"dt auto <= {self.dt:.3g}" if self.auto else f"dt {self.dt:.3g}"]
        if self.contact != "deck":
            parts.append(self.contact)
        if self.stiffness != 1.0:
            parts.append(f"E x {self.stiffness:.3g}")
        if self.friction != "regularized":
            parts.append(self.friction)
        if self.repeat:
            parts.append(f"repeat {self.repeat}")
        return " ".join(parts)


def ladder(dt_deck: float, *, dts=None, viscoelastic: bool, friction: bool,
           chaotic: bool, stiffness=(), friction_law: str = "regularized") -> list[Setting]:
    """The settings to run: every step of ``dts`` (default DTMAX x :data:`LADDER`) with the
    deck's physics, the fidelity choices at the deck's step, and perturbed repeats of the
    deck's setting for a chaotic scene, and the softer contacts of ``stiffness`` (scales of
    the particles' moduli, each at :func:`soft_step` of the deck's step). The deck's own
    setting is marked ``own``. Every setting runs the deck's tangential law ``friction_law``
    but the friction fidelity choices, which run the other laws of :data:`FRICTION_CHOICES`.
    (The step chosen by accuracy is added by :func:`x3dpd.study.run_study`.)"""
    steps = sorted({float(d) for d in (dts if dts else [dt_deck * f for f in LADDER])}
                   | {float(dt_deck)})
    law = friction_law
    out = [Setting(d, own=np.isclose(d, dt_deck, rtol=1e-12, atol=0.0), friction=law)
           for d in steps]
    if viscoelastic:
        out.append(Setting(dt_deck, contact="elastic", friction=law))
    if friction:
        out += [Setting(dt_deck, friction=other) for other in FRICTION_CHOICES if other != law]
    out += [Setting(soft_step(dt_deck, f), stiffness=float(f), friction=law) for f in stiffness]
    if chaotic:
        out += [Setting(dt_deck, repeat=k, friction=law) for k in range(1, REPEATS + 1)]
    return out


def deck_for(deck, setting: Setting):
    """The deck a setting runs: the elastic law drops every Maxwell term; a softer contact
    scales every modulus (E0, E1, E2 ...; the relaxation times kept); a repeat moves each
    particle by up to PERTURBATION x its radius (seeded)."""
    if setting.contact == "elastic":
        deck = replace(deck, pdmp=tuple(replace(p, e1=0.0, extra_terms=()) for p in deck.pdmp))
    if setting.stiffness != 1.0:
        deck = softened(deck, setting.stiffness)
    if setting.repeat:
        rng = np.random.default_rng(setting.repeat)
        first = min(p.nodlim for p in deck.pdmp) if deck.pdmp else None
        radius = {p.nodlim: p.rzero for p in deck.pdmp}
        nodes = []
        for n in deck.nodes:
            if first is not None and n.nid > first:
                r = radius[max(k for k in radius if k < n.nid)]
                dx = rng.uniform(-1.0, 1.0, 3) * PERTURBATION * r
                n = replace(n, x=n.x + dx[0], y=n.y + dx[1], z=n.z + dx[2])
            nodes.append(n)
        deck = replace(deck, nodes=tuple(nodes))
    return deck
