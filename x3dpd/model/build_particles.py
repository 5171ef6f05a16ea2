"""Model builder steps for the particles: PDMP groups (report Appendix B), the HOOKE law,
initial velocities."""

from __future__ import annotations

import math

import numpy as np

from x3dpd.errors import DeckError
from x3dpd.model.build_base import BuilderBase, _ro
from x3dpd.physics.normal_laws import NORMAL_LAWS


class ParticleSteps(BuilderBase):
    """The particle arrays: radius, density, moduli, groups and their initial velocities."""

    def _particles(self) -> None:
        """Particle groups from the PDMP cards (report Appendix B)."""
        cards = self.deck.pdmp
        for prev, card in zip(cards, cards[1:]):
            if card.nodlim <= prev.nodlim:
                raise self.error(
                    f"NODLIM {card.nodlim} must be larger than the previous PDMP "
                    f"card's NODLIM {prev.nodlim} (line {prev.pos.line}): each card "
                    f"starts a new group of particles",
                    card.pos,
                    "PDMP",
                )
        for card in cards:
            self._check_pdmp(card)
        if cards:
            self.nodlim = cards[0].nodlim
            self.pstart = int(np.searchsorted(self.ids, self.nodlim, side="right"))
        else:
            self.nodlim = None
            self.pstart = self.ids.shape[0]
        pid = self.ids[self.pstart :]
        limits = np.array([c.nodlim for c in cards], dtype=np.int64)
        self.group = (np.searchsorted(limits, pid, side="left") - 1).astype(np.int64)
        g = [cards[k] for k in self.group]
        self.radius = np.array([c.rzero for c in g], dtype=np.float64)
        self.density = np.array([c.prho for c in g], dtype=np.float64)
        self.poisson = np.array([c.ppoi for c in g], dtype=np.float64)
        self.mu = np.array([c.pcof for c in g], dtype=np.float64)
        self._friction_card()
        # Report Appendix B note 2: M = PRHO * 4/3 * pi * RZERO^3.
        self.p_mass = self.density * (4.0 / 3.0) * math.pi * self.radius**3
        terms = [[(c.e1, c.t1), *c.extra_terms] for c in cards]
        viscous = any(e != 0.0 for t in terms for e, _ in t)
        k = 1 + (max(len(t) for t in terms) if viscous else 0)
        moduli = np.zeros((len(cards), k))
        taus = np.ones((len(cards), k))
        taus[:, 0] = np.inf
        for j, (c, t) in enumerate(zip(cards, terms)):
            moduli[j, 0] = c.e0
            for m, (e, tau) in enumerate(t[: k - 1], start=1):
                moduli[j, m] = e
                taus[j, m] = tau if e != 0.0 else 1.0
        self.moduli = moduli[self.group].reshape(-1, k)
        self.taus = taus[self.group].reshape(-1, k)

    def _card_law(self):
        """``(name, law module, records)`` of the normal law a card of the deck selects (the
        HOOKE card: x3dpd.physics.normal_laws, a law's ``CARD``), or None: the report's law."""
        for name, law in NORMAL_LAWS.items():
            records = getattr(self.deck, law.CARD.lower()) if law.CARD else None
            if records:
                return name, law, records
        return None

    def _normal_law(self) -> dict:
        """The normal law a card selects (the HOOKE card, our extension: the linear
        spring-dashpot law) for the PDMP groups it names, with the law's constants (its
        ``PARAMS``) per particle. A scene runs one normal law, so it must name every group."""
        selected = self._card_law()
        if selected is None:
            return {}
        name, law, records = selected
        card = law.CARD
        cards = self.deck.pdmp
        by_nodlim = {c.nodlim: k for k, c in enumerate(cards)}
        params = np.full((len(cards), len(law.PARAMS)), np.nan)
        for r in records:
            if r.nodlim not in by_nodlim:
                raise self.error(
                    f"NODLIM {r.nodlim} names no PDMP group (PDMP NODLIMs: "
                    f"{', '.join(str(c.nodlim) for c in cards) or 'none'})",
                    r.pos,
                    card,
                )
            k = by_nodlim[r.nodlim]
            if not np.isnan(params[k, 0]):
                raise self.error(f"PDMP group NODLIM {r.nodlim} is given twice", r.pos, card)
            if cards[k].e1 != 0.0 or cards[k].extra_terms:
                raise self.error(
                    f"PDMP group NODLIM {r.nodlim} has Maxwell terms (E1 = "
                    f"{cards[k].e1:g}): the {card} law replaces the viscoelastic "
                    f"law; set E1 to 0",
                    r.pos,
                    card,
                )
            params[k] = [getattr(r, field.lower()) for field in law.PARAMS]
        missing = [c.nodlim for c, p in zip(cards, params) if np.isnan(p[0])]
        if missing:
            raise self.error(
                f"a scene runs one normal law: give every PDMP group a {card} record "
                f"(missing NODLIM {', '.join(map(str, missing))})",
                records[0].pos,
                card,
            )
        return {
            "normal_law": name,
            "law_params": _ro(params[self.group].reshape(-1, len(law.PARAMS))),
        }

    def _friction_card(self) -> None:
        """The FRICTION card (our extension): per PDMP group its static and kinetic mu (they
        replace PCOF) and rolling coefficient. A scene runs one tangential law and one rolling
        law (the step loop is compiled for them): every record must name the same LAW, and
        every record with a rolling law the same ROLL; a group without a record keeps its PCOF
        as mu_s = mu_k and no rolling resistance."""
        self.friction_law = None
        self.rolling_law = "none"
        self.mu_kinetic = None
        self.mu_roll = None
        records = self.deck.friction
        if not records:
            return
        cards = self.deck.pdmp
        by_nodlim = {c.nodlim: k for k, c in enumerate(cards)}
        mu_s = np.array([c.pcof for c in cards], dtype=np.float64)
        mu_k = mu_s.copy()
        mu_r = np.zeros(len(cards))
        seen = set()
        for r in records:
            if r.nodlim not in by_nodlim:
                raise self.error(
                    f"NODLIM {r.nodlim} names no PDMP group (PDMP NODLIMs: "
                    f"{', '.join(str(c.nodlim) for c in cards) or 'none'})",
                    r.pos,
                    "FRICTION",
                )
            if r.nodlim in seen:
                raise self.error(f"PDMP group NODLIM {r.nodlim} is given twice", r.pos, "FRICTION")
            seen.add(r.nodlim)
            if r.law != records[0].law:
                raise self.error(
                    f"a scene runs one tangential law: LAW {r.law} here, "
                    f"{records[0].law} on line {records[0].pos.line}",
                    r.pos,
                    "FRICTION",
                )
            if r.roll != "none":
                if self.rolling_law not in ("none", r.roll):
                    raise self.error(
                        f"a scene runs one rolling law: ROLL {r.roll} here, "
                        f"{self.rolling_law} above",
                        r.pos,
                        "FRICTION",
                    )
                self.rolling_law = r.roll
            k = by_nodlim[r.nodlim]
            mu_s[k], mu_k[k], mu_r[k] = r.mu_s, r.mu_k, r.mu_r
        self.friction_law = records[0].law
        self.mu = mu_s[self.group].astype(np.float64)
        self.mu_kinetic = mu_k[self.group].astype(np.float64)
        self.mu_roll = mu_r[self.group].astype(np.float64)

    def _friction_fields(self) -> dict:
        """The Model fields of the FRICTION card (none without one)."""
        if self.friction_law is None:
            return {}
        return {
            "friction_law": self.friction_law,
            "mu_kinetic": _ro(self.mu_kinetic),
            "rolling_law": self.rolling_law,
            "mu_roll": _ro(self.mu_roll),
        }

    def _check_pdmp(self, c) -> None:
        def bad(message: str) -> DeckError:
            return self.error(message, c.pos, "PDMP")

        if not c.rzero > 0.0:
            raise bad(f"particle radius RZERO must be > 0, got {c.rzero:g}")
        if not c.prho > 0.0:
            raise bad(f"particle density PRHO must be > 0, got {c.prho:g}")
        if not c.e0 > 0.0:
            raise bad(f"particle modulus E0 must be > 0, got {c.e0:g}")
        if not -1.0 < c.ppoi < 0.5:
            raise bad(f"Poisson's ratio PPOI must lie in (-1, 0.5), got {c.ppoi:g}")
        if c.pcof < 0.0:
            raise bad(f"friction coefficient PCOF must be >= 0, got {c.pcof:g}")
        for m, (e, tau) in enumerate([(c.e1, c.t1), *c.extra_terms], start=1):
            if e < 0.0:
                raise bad(f"Maxwell modulus E{m} must be >= 0, got {e:g}")
            if e != 0.0 and not tau > 0.0:
                raise bad(f"relaxation time T{m} must be > 0 when E{m} is not zero, got {tau:g}")

    def _initial_velocities(self) -> np.ndarray:
        v0 = np.zeros((self.ids.shape[0], 6))
        for k, card in enumerate(self.deck.pdmp):
            v0[self.pstart + np.flatnonzero(self.group == k), :3] = (card.vx0, card.vy0, card.vz0)
        for rec in self.deck.initials:
            i = self.node(rec.nid, rec.pos, "INITIAL", "node")
            if len(rec.velocity) not in (3, 6):
                raise self.error(
                    f"node {rec.nid}: give 3 (vx vy vz) or 6 (and wx wy wz) "
                    f"velocity components, got {len(rec.velocity)}",
                    rec.pos,
                    "INITIAL",
                )
            v0[i, : len(rec.velocity)] = rec.velocity
        v0[self.fixed] = 0.0  # report Appendix B note 5: initial velocities obey BOUNDARY
        return v0
