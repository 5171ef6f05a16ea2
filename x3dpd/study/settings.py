"""The settings a study runs: a ladder of time steps and the scene's fidelity choices.

A :class:`Setting` says how one run differs from the deck: its step ``dt``, its contact law
(``"deck"`` as written, or ``"elastic"``: the Maxwell terms dropped, Hertz with the long-term
modulus E0), its friction law, its contact stiffness (``stiffness``: every modulus of the
particles' law scaled, E0, E1, E2 ..., the relaxation times kept, with the step lengthened to
match, :func:`x3dpd.api.soft_step`), its walls (``walls``: the deck's, ``"rigid"``, or a
material of the library x3dpd.materials on every cavity, :func:`wall_records`), and, for a
perturbed repeat, the seed of the perturbation.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from x3dpd.api import DEFAULT_FRICTION, soft_step, softened

#: Default ladder of steps, as multiples of the deck's DTMAX.
LADDER = (0.25, 0.5, 1.0, 2.0, 4.0, 8.0)
#: Perturbed repeats of the deck's own setting for a chaotic scene.
REPEATS = 3
#: Size of a repeat's perturbation of particle positions, as a fraction of the radius.
PERTURBATION = 1e-9
#: The tangential laws a study offers as fidelity choices (docs/physics.md): the report's
#: regularised and bare Coulomb laws and Hertz-Mindlin with its tangential history.
FRICTION_CHOICES = ("regularized", "coulomb", "mindlin")
#: The wall choice that is the deck's own walls (its WALLMAT card, or rigid without one).
DECK_WALLS = "deck"


@dataclass(frozen=True)
class Setting:
    """One run of a study: ``dt`` [s], ``contact`` ("deck" | "elastic"), ``friction`` (a
    tangential law, default x3dpd.api.DEFAULT_FRICTION), ``repeat`` (0: unperturbed; k:
    perturbed with seed k), ``own`` (the deck's own setting), ``auto`` (a step chosen by
    accuracy up to ``dt``)."""

    dt: float
    contact: str = "deck"
    friction: str = DEFAULT_FRICTION
    repeat: int = 0
    own: bool = False
    auto: bool = False  # the step chosen by accuracy (x3dpd.run(dt="auto")) up to dt
    stiffness: float = 1.0  # the particles' moduli scaled by this (softer contacts)
    walls: str = DECK_WALLS  # "deck", "rigid" or a material name of x3dpd.materials

    @property
    def label(self) -> str:
        parts = [f"dt auto <= {self.dt:.3g}" if self.auto else f"dt {self.dt:.3g}"]
        if self.contact != "deck":
            parts.append(self.contact)
        if self.stiffness != 1.0:
            parts.append(f"E x {self.stiffness:.3g}")
        if self.friction != DEFAULT_FRICTION:
            parts.append(self.friction)
        if self.walls != DECK_WALLS:
            parts.append(f"walls {self.walls}")
        if self.repeat:
            parts.append(f"repeat {self.repeat}")
        return " ".join(parts)


def ladder(
    dt_deck: float,
    *,
    dts=None,
    viscoelastic: bool,
    friction: bool,
    chaotic: bool,
    stiffness=(),
    friction_law: str = DEFAULT_FRICTION,
    walls=(),
) -> list[Setting]:
    """The settings to run: every step of ``dts`` (default DTMAX x :data:`LADDER`) with the
    deck's physics, the fidelity choices at the deck's step, and perturbed repeats of the
    deck's setting for a chaotic scene, and the softer contacts of ``stiffness`` (scales of
    the particles' moduli, each at :func:`soft_step` of the deck's step). The deck's own
    setting is marked ``own``. Every setting runs the deck's tangential law ``friction_law``
    but the friction fidelity choices, which run the other laws of :data:`FRICTION_CHOICES`,
    and the deck's walls but the wall choices ``walls`` (each "rigid" or a library material,
    at the deck's step and law).
    (The step chosen by accuracy is added by :func:`x3dpd.study.run_study`.)"""
    steps = sorted(
        {float(d) for d in (dts if dts else [dt_deck * f for f in LADDER])} | {float(dt_deck)}
    )
    law = friction_law
    out = [
        Setting(d, own=np.isclose(d, dt_deck, rtol=1e-12, atol=0.0), friction=law) for d in steps
    ]
    if viscoelastic:
        out.append(Setting(dt_deck, contact="elastic", friction=law))
    if friction:
        out += [Setting(dt_deck, friction=other) for other in FRICTION_CHOICES if other != law]
    out += [Setting(dt_deck, friction=law, walls=w) for w in walls]
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
    if setting.walls != DECK_WALLS:
        deck = replace(deck, wallmat=wall_records(deck, setting.walls))
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


def wall_records(deck, walls: str):
    """The WALLMAT records (x3dpd.deck.cards.WallMat) that give every cavity of ``deck`` (each
    CONTACT set with walls: its triangles and analytic walls) the material ``walls`` of the
    library x3dpd.materials (E and nu in the deck's units), with the particles' own friction
    coefficient (PCOF) so that only the compliance changes; ``"rigid"``: none (None)."""
    from x3dpd.api.decks import WallMat
    from x3dpd.errors import InputError
    from x3dpd.materials import MaterialError, in_units

    if walls == "rigid":
        return None
    try:
        mat = in_units(walls, deck.units)
    except MaterialError as exc:
        raise InputError(f"--walls: {exc}") from None
    mus = {p.pcof for p in deck.pdmp}
    if len(mus) != 1:
        raise InputError(
            f"--walls {walls}: the particle groups have different friction "
            f"coefficients ({', '.join(map(str, sorted(mus)))}); a study's wall "
            f"material keeps one PCOF (write the deck's WALLMAT card instead)"
        )
    sets = sorted(
        {t.set_id for c in deck.contacts for t in c.triangles}
        | {w.set_id for w in deck.analytic_walls or ()}
    )
    mu = mus.pop()
    return tuple(WallMat(k, mat.E, mat.nu, mu) for k in sets) or None
