"""Deck -> Model: cross-reference checks, then the arrays the solver needs.

:func:`build_model` is the only entry point. Every problem it finds is a :class:`DeckError`
pointing at the offending record (``FILE:LINE:COL: CARD: message``). Physics stays out: the
builder only sums masses, applies material scale factors and reads geometry.

Wall orientation comes from geometry, never from the winding of the triangles: each triangle's
inward side is the side facing the centroid of its cavity's triangle nodes (the "master nodes").
The report's Appendix A winds some cavity triangles one way and some the other.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from x3dpd.errors import NOWHERE, DeckError, Pos, UsrfrcError
from x3dpd.geometry.cavity import geometry_size, group_faces
from x3dpd.geometry.triangle import PLANE_TOL, inward_signs, triangle_areas, unit_normals
from x3dpd.model.model import Model
from x3dpd.physics.motion import motion_table, prescribed_mask
from x3dpd.physics.usrfrc import force_table, is_user_file, split_specs

if TYPE_CHECKING:  # the builder reads cards by attribute; it needs no runtime import of them
    from x3dpd.deck.cards import Deck

_AXES = "xyz"
_ALL_DOFS = (1, 2, 3, 4, 5, 6)


def build_model(deck: Deck, *, usrfrc: Sequence[str] = (), motion: Sequence[str] = ()) -> Model:
    """Check a parsed deck's cross references and turn it into a :class:`Model`.

    Parameters
    ----------
    deck : Deck
        The parsed deck (``x3dpd.deck.read_deck``).
    usrfrc : sequence of str
        Extra force specs (``--usrfrc``), added to the deck's USRFRC card for the
        ``external_force`` effect and the zero-mass check.
    motion : sequence of str
        Prescribed-motion specs (``--motion``): the ``prescribed_motion`` effect, and the DOFs
        they drive need no mass.

    Raises
    ------
    DeckError
        At the first record that is inconsistent with the rest of the deck.
    """
    return _Builder(deck, tuple(usrfrc), tuple(motion)).build()


class _Builder:
    """One build: holds the deck and the lookup tables the checks share."""

    def __init__(self, deck: Deck, usrfrc: tuple[str, ...], motion: tuple[str, ...]):
        self.deck = deck
        self.usrfrc = usrfrc
        self.motion = motion

    # -- errors -------------------------------------------------------------------------------

    def error(self, message: str, pos: Pos, card: str) -> DeckError:
        return DeckError(message, self.deck.path, pos.line, pos.column, card)

    def node(self, nid: int, pos: Pos, card: str, what: str = "node") -> int:
        """Index of node ``nid``; DeckError when it is not defined."""
        i = self.index.get(nid)
        if i is None:
            raise self.error(f"{what} {nid} is not defined in NODE COORDINATES", pos, card)
        return i

    def structural(self, nid: int, pos: Pos, card: str, what: str) -> int:
        """Index of a node that must not be a particle (report Appendix B, PDMP note 1)."""
        i = self.node(nid, pos, card, what)
        if i >= self.pstart:
            raise self.error(
                f"{what} {nid} is a particle node (PDMP NODLIM {self.nodlim}: nodes above it are "
                f"particles, which must not be connected to elements, masses or rigid links)",
                pos, card)
        return i

    # -- build --------------------------------------------------------------------------------

    def build(self) -> Model:
        deck = self.deck
        par = self._parameters()
        self._nodes()
        self._particles()
        n = self.ids.shape[0]
        self.mass = np.zeros(n)
        self.inertia = np.zeros((n, 3))
        self.mass[self.pstart:] = self.p_mass
        self.inertia[self.pstart:] = (0.4 * self.p_mass * self.radius**2)[:, None]
        self._masses()
        self._springs()
        self.fixed = self._boundaries()
        self._rigid_bodies()
        self._walls()
        v0 = self._initial_velocities()
        trace = self._trace()
        self._zero_mass_check()
        body = np.zeros(3) if deck.body is None else np.array(
            [deck.body.ax, deck.body.ay, deck.body.az], dtype=np.float64)
        return Model(
            node_ids=_ro(self.ids, np.int64), x0=_ro(self.x0), mass=_ro(self.mass),
            inertia=_ro(self.inertia), fixed=_ro(self.fixed, bool), v0=_ro(v0),
            body_accel=_ro(body),
            particle_start=int(self.pstart), radius=_ro(self.radius),
            density=_ro(self.density), poisson=_ro(self.poisson), mu=_ro(self.mu),
            moduli=_ro(self.moduli), taus=_ro(self.taus),
            particle_group=_ro(self.group, np.int64),
            particle_cavity=_ro(self.particle_cavity, np.int64),
            spring_nodes=_ro(self.spring_nodes.reshape(-1, 2), np.int64),
            spring_k=_ro(self.spring_k.reshape(-1, 3)),
            spring_c=_ro(self.spring_c.reshape(-1, 3)),
            rigid_master=_ro(self.rigid_master, np.int64), rigid_ptr=_ro(self.rigid_ptr, np.int64),
            rigid_slaves=_ro(self.rigid_slaves, np.int64), rigid_mass=_ro(self.rigid_mass),
            rigid_inertia=_ro(self.rigid_inertia.reshape(-1, 3, 3)),
            tri_nodes=_ro(self.tri_nodes.reshape(-1, 3), np.int64), tri_sign=_ro(self.tri_sign),
            tri_face=_ro(self.tri_face, np.int64), face_cavity=_ro(self.face_cavity, np.int64),
            cavity_set_ids=_ro(self.cavity_set_ids, np.int64),
            cylinder_nodes=_ro(self.cylinder_nodes.reshape(-1, 2), np.int64),
            cylinder_radius=_ro(self.cylinder_radius),
            cylinder_cavity=_ro(self.cylinder_cavity, np.int64),
            trace_nodes=_ro(trace, np.int64),
            t0=float(par.time), tmax=float(par.tmax), dt=float(par.dtmax), trest=float(par.trest),
            itrac=int(par.itrac), irest=int(par.irest), incmax=float(par.incmax),
            effects=self._effects(body),
            usrfrc=self._deck_usrfrc(),
            title=deck.title.text if deck.title is not None else "",
            units=(deck.units.system if getattr(deck, "units", None) is not None
                   else ("in", "lbf", "s")),
            path=deck.path,
            **self._normal_law(),
        )

    def _parameters(self):
        par = self.deck.parameters
        if par is None:
            raise self.error("no PARAMETERS card: the deck must give TIME TMAX TREST DTMIN DTMAX "
                             "INCR INCMAX IREST NINTPL ISTAT ITRAC", NOWHERE, "PARAMETERS")
        if not par.dtmax > 0.0:
            raise self.error(f"DTMAX must be > 0 (it is the time step), got {par.dtmax:g}",
                             par.pos, "PARAMETERS")
        if par.dtmin > par.dtmax:
            raise self.error(f"DTMIN {par.dtmin:g} is larger than DTMAX {par.dtmax:g}",
                             par.pos, "PARAMETERS")
        if par.tmax < par.time:
            raise self.error(f"TMAX {par.tmax:g} is before the start time TIME {par.time:g}",
                             par.pos, "PARAMETERS")
        return par

    def _nodes(self) -> None:
        first: dict[int, Pos] = {}
        for nd in self.deck.nodes:
            if nd.nid in first:
                raise self.error(f"node {nd.nid} is defined twice (first at line "
                                 f"{first[nd.nid].line})", nd.pos, "NODE COORDINATES")
            first[nd.nid] = nd.pos
        nodes = sorted(self.deck.nodes, key=lambda nd: nd.nid)
        self.node_pos = first
        self.ids = np.array([nd.nid for nd in nodes], dtype=np.int64)
        self.x0 = np.array([(nd.x, nd.y, nd.z) for nd in nodes], dtype=np.float64).reshape(-1, 3)
        self.index = {int(nid): i for i, nid in enumerate(self.ids)}

    def _particles(self) -> None:
        """Particle groups from the PDMP cards (report Appendix B)."""
        cards = self.deck.pdmp
        for prev, card in zip(cards, cards[1:]):
            if card.nodlim <= prev.nodlim:
                raise self.error(f"NODLIM {card.nodlim} must be larger than the previous PDMP "
                                 f"card's NODLIM {prev.nodlim} (line {prev.pos.line}): each card "
                                 f"starts a new group of particles", card.pos, "PDMP")
        for card in cards:
            self._check_pdmp(card)
        if cards:
            self.nodlim = cards[0].nodlim
            self.pstart = int(np.searchsorted(self.ids, self.nodlim, side="right"))
        else:
            self.nodlim = None
            self.pstart = self.ids.shape[0]
        pid = self.ids[self.pstart:]
        limits = np.array([c.nodlim for c in cards], dtype=np.int64)
        self.group = (np.searchsorted(limits, pid, side="left") - 1).astype(np.int64)
        g = [cards[k] for k in self.group]
        self.radius = np.array([c.rzero for c in g], dtype=np.float64)
        self.density = np.array([c.prho for c in g], dtype=np.float64)
        self.poisson = np.array([c.ppoi for c in g], dtype=np.float64)
        self.mu = np.array([c.pcof for c in g], dtype=np.float64)
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

    def _normal_law(self) -> dict:
        """The HOOKE card (our extension): the linear spring-dashpot law for the PDMP groups it
        names. A scene runs one normal law, so it must name every group."""
        records = self.deck.hooke
        if not records:
            return {}
        cards = self.deck.pdmp
        by_nodlim = {c.nodlim: k for k, c in enumerate(cards)}
        params = np.full((len(cards), 2), np.nan)
        for r in records:
            if r.nodlim not in by_nodlim:
                raise self.error(f"NODLIM {r.nodlim} names no PDMP group (PDMP NODLIMs: "
                                 f"{', '.join(str(c.nodlim) for c in cards) or 'none'})",
                                 r.pos, "HOOKE")
            k = by_nodlim[r.nodlim]
            if not np.isnan(params[k, 0]):
                raise self.error(f"PDMP group NODLIM {r.nodlim} is given twice", r.pos, "HOOKE")
            if cards[k].e1 != 0.0 or cards[k].extra_terms:
                raise self.error(f"PDMP group NODLIM {r.nodlim} has Maxwell terms (E1 = "
                                 f"{cards[k].e1:g}): the HOOKE law replaces the viscoelastic "
                                 f"law; set E1 to 0", r.pos, "HOOKE")
            params[k] = r.kn, r.e
        missing = [c.nodlim for c, p in zip(cards, params) if np.isnan(p[0])]
        if missing:
            raise self.error(f"a scene runs one normal law: give every PDMP group a HOOKE record "
                             f"(missing NODLIM {', '.join(map(str, missing))})", records[0].pos,
                             "HOOKE")
        return {"normal_law": "hooke", "hooke": _ro(params[self.group].reshape(-1, 2))}

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

    def _masses(self) -> None:
        for rec in self.deck.masses:
            i = self.structural(rec.nid, rec.pos, "MASS", "node")
            for name, value in (("mass", rec.mass), ("Ixx", rec.ixx), ("Iyy", rec.iyy),
                                ("Izz", rec.izz)):
                if value < 0.0:
                    raise self.error(f"negative {name} {value:g} for node {rec.nid}", rec.pos,
                                     "MASS")
            self.mass[i] += rec.mass
            self.inertia[i] += (rec.ixx, rec.iyy, rec.izz)

    def _springs(self) -> None:
        materials: dict[int, object] = {}
        for mat in self.deck.materials:
            if mat.mid in materials:
                raise self.error(f"material {mat.mid} is defined twice (first at line "
                                 f"{materials[mat.mid].pos.line})", mat.pos, "MATID")
            if mat.mtype != 1:
                raise self.error(f"material {mat.mid} has type {mat.mtype}; only type 1 "
                                 f"(discrete spring-damper) is supported", mat.pos, "MATID")
            if mat.mass < 0.0:
                raise self.error(f"negative element mass {mat.mass:g} in material {mat.mid}",
                                 mat.pos, "MATID")
            materials[mat.mid] = mat
        seen: dict[int, Pos] = {}
        nodes, ks, cs = [], [], []
        for el in self.deck.elements:
            if el.eid in seen:
                raise self.error(f"element {el.eid} is defined twice (first at line "
                                 f"{seen[el.eid].line})", el.pos, "ELEMENTS")
            seen[el.eid] = el.pos
            mat = materials.get(el.mid)
            if mat is None:
                raise self.error(f"element {el.eid} uses material {el.mid}, which no MATID "
                                 f"record defines", el.pos, "ELEMENTS")
            if len(el.nodes) not in (1, 2) or len(set(el.nodes)) != len(el.nodes):
                raise self.error(f"element {el.eid} must join one node to ground or two "
                                 f"distinct nodes, got {list(el.nodes)}", el.pos, "ELEMENTS")
            idx = [self.structural(nid, el.pos, "ELEMENTS", f"element {el.eid} node")
                   for nid in el.nodes]
            for i in idx:  # lumped equally on both ends; a ground end's share is dropped
                self.mass[i] += 0.5 * mat.mass
            nodes.append(idx + [-1] * (2 - len(idx)))
            ks.append([mat.scale * mat.kx, mat.scale * mat.ky, mat.scale * mat.kz])
            cs.append([mat.scale * mat.c] * 3)
        self.spring_elements = self.deck.elements
        self.spring_nodes = np.array(nodes, dtype=np.int64).reshape(-1, 2)
        self.spring_k = np.array(ks, dtype=np.float64).reshape(-1, 3)
        self.spring_c = np.array(cs, dtype=np.float64).reshape(-1, 3)

    def _boundaries(self) -> np.ndarray:
        fixed = np.zeros((self.ids.shape[0], 6), dtype=bool)
        for rec in self.deck.boundaries:
            card = "BOUNDARY CONDITIONS"
            self.node(rec.first, rec.pos, card, "first node")
            self.node(rec.last, rec.pos, card, "last node")
            if rec.inc <= 0 or rec.last < rec.first:
                raise self.error(f"node range {rec.first}..{rec.last} step {rec.inc} is empty; "
                                 f"the increment must be > 0 and the last node >= the first",
                                 rec.pos, card)
            bad = [d for d in rec.dofs if d not in _ALL_DOFS]
            if bad:
                raise self.error(f"DOF {bad[0]} is not one of 1..6 (x, y, z, rx, ry, rz)",
                                 rec.pos, card)
            cols = [d - 1 for d in rec.dofs]
            for nid in range(rec.first, rec.last + 1, rec.inc):
                i = self.index.get(nid)
                if i is not None:
                    fixed[i, cols] = True
        return fixed

    def _rigid_bodies(self) -> None:
        owner: dict[int, tuple[int, Pos]] = {}  # node index -> (master id, line of its RBEL)
        masters, ptr, slaves = [], [0], []
        for rb in self.deck.rbels:
            if sorted(rb.dofs) != list(_ALL_DOFS):
                code = "".join(str(d) for d in rb.dofs)
                raise self.error(f"DOF code {code}: only 123456 (all six DOFs rigidly linked) is "
                                 f"supported", rb.pos, "RBEL")
            m = self.structural(rb.master, rb.pos, "RBEL", "master node")
            if m in owner:
                raise self.error(f"master node {rb.master} already belongs to the rigid body of "
                                 f"master {owner[m][0]} (line {owner[m][1].line}); a node may "
                                 f"be in one rigid body only", rb.pos, "RBEL")
            owner[m] = (rb.master, rb.pos)
            body = []
            for k, nid in enumerate(rb.slaves):
                pos = _pos_at(rb.slave_positions, k, rb.pos)
                s = self.structural(nid, pos, "RBEL", "slave node")
                if s in owner:
                    raise self.error(f"slave node {nid} already belongs to the rigid body of "
                                     f"master {owner[s][0]} (line {owner[s][1].line}); a node "
                                     f"may be in one rigid body only", pos, "RBEL")
                owner[s] = (rb.master, rb.pos)
                body.append(s)
            masters.append(m)
            slaves.extend(body)
            ptr.append(len(slaves))
        self.rigid_master = np.array(masters, dtype=np.int64)
        self.rigid_ptr = np.array(ptr, dtype=np.int64)
        self.rigid_slaves = np.array(slaves, dtype=np.int64)
        b = len(masters)
        self.rigid_mass = np.zeros(b)
        self.rigid_inertia = np.zeros((b, 3, 3))
        for k, m in enumerate(masters):
            sl = self.rigid_slaves[ptr[k]:ptr[k + 1]]
            r = self.x0[sl] - self.x0[m]
            ms = self.mass[sl]
            self.rigid_mass[k] = self.mass[m] + ms.sum()
            # Parallel-axis theorem about the master's initial position:
            # J = diag(I_m) + sum_s [diag(I_s) + m_s (|r_s|^2 1 - r_s r_s^T)].
            j = np.diag(self.inertia[m] + self.inertia[sl].sum(axis=0))
            j += np.einsum("s,s->", ms, np.einsum("sk,sk->s", r, r)) * np.eye(3)
            j -= np.einsum("s,si,sj->ij", ms, r, r)
            self.rigid_inertia[k] = j
        self.slave_of = {int(s): k for k in range(b) for s in slaves[ptr[k]:ptr[k + 1]]}
        self.body_of_master = {int(m): k for k, m in enumerate(masters)}

    def _walls(self) -> None:
        tris = [t for c in self.deck.contacts for t in c.triangles]
        sets = [s for c in self.deck.contacts for s in c.slaves]
        idx = np.array([[self.structural(nid, t.pos, "CONTACT", "triangle node")
                         for nid in t.nodes] for t in tris], dtype=np.int64).reshape(-1, 3)
        p0, p1, p2 = (self.x0[idx[:, k]] for k in range(3))
        area = triangle_areas(p0, p1, p2)
        longest = np.max(np.stack([np.linalg.norm(p1 - p0, axis=1),
                                   np.linalg.norm(p2 - p1, axis=1),
                                   np.linalg.norm(p0 - p2, axis=1)]), axis=0, initial=0.0)
        for k, t in enumerate(tris):
            if not area[k] > PLANE_TOL * longest[k] ** 2:
                raise self.error(f"triangle {k + 1} (nodes {' '.join(map(str, t.nodes))}) is "
                                 f"degenerate: area {area[k]:.6g}", t.pos, "CONTACT")
        set_ids = sorted({t.set_id for t in tris} | {c.set_id for c in self.deck.cylinders or ()})
        cav_of_set = {s: c for c, s in enumerate(set_ids)}
        pcav = np.full(self.ids.shape[0] - self.pstart, -1, dtype=np.int64)
        where: dict[int, Pos] = {}
        for ss in sets:
            if ss.set_id not in cav_of_set:
                raise self.error(f"slave set {ss.set_id} has no master triangles and no "
                                 f"CYLINDER (the CONTACT triangles and cylinders use set ids "
                                 f"{', '.join(map(str, set_ids)) or 'none'})", ss.pos, "CONTACT")
            for k, nid in enumerate(ss.nodes):
                pos = _pos_at(ss.positions, k, ss.pos)
                i = self.node(nid, pos, "CONTACT", "slave node")
                if i < self.pstart:
                    raise self.error(f"slave node {nid} is not a particle (particles are the "
                                     f"nodes above PDMP NODLIM {self.nodlim})", pos, "CONTACT")
                if i in where:
                    raise self.error(f"particle {nid} is already a slave of another set (line "
                                     f"{where[i].line}); a particle belongs to one cavity",
                                     pos, "CONTACT")
                where[i] = pos
                pcav[i - self.pstart] = cav_of_set[ss.set_id]
        sign = np.zeros(len(tris))
        face = np.zeros(len(tris), dtype=np.int64)
        face_cavity: list[int] = []
        n_hat = unit_normals(p0, p1, p2)
        for c, sid in enumerate(set_ids):
            mine = np.array([k for k, t in enumerate(tris) if t.set_id == sid], dtype=np.int64)
            if mine.size == 0:   # a cavity of cylinders only
                continue
            corners = np.unique(idx[mine].reshape(-1))
            s = inward_signs(p0[mine], p1[mine], p2[mine], self.x0[corners].mean(axis=0))
            if np.any(s == 0.0):  # e.g. a flat floor: the master nodes' centroid is in its plane
                own = self.pstart + np.flatnonzero(pcav == c)
                if own.size:
                    ref = self.x0[own].mean(axis=0)
                    s = np.where(s == 0.0, inward_signs(p0[mine], p1[mine], p2[mine], ref), s)
            if np.any(s == 0.0):
                k = int(mine[np.flatnonzero(s == 0.0)[0]])
                raise self.error(
                    f"cannot tell the inside of triangle {k + 1} (nodes "
                    f"{' '.join(map(str, tris[k].nodes))}): the centroid of cavity {sid}'s "
                    f"triangle nodes and of its particles lie in the triangle's plane",
                    tris[k].pos, "CONTACT")
            sign[mine] = s
            local = group_faces(s[:, None] * n_hat[mine], p0[mine],
                                geometry_size(self.x0[corners]))
            face[mine] = len(face_cavity) + local
            face_cavity.extend([c] * (int(local.max()) + 1))
        self.triangles = tris
        self.tri_nodes = idx
        self.tri_sign = sign
        self.tri_face = face
        self.face_cavity = np.array(face_cavity, dtype=np.int64)
        self.cavity_set_ids = np.array(set_ids, dtype=np.int64)
        self.particle_cavity = pcav
        self._cylinders(cav_of_set)

    def _cylinders(self, cav_of_set: dict[int, int]) -> None:
        """The CYLINDER card (our extension): analytic cylindrical cavities. Their axis nodes
        must move rigidly together (one rigid body, or both fixed), so that the reaction and
        the wall's velocity formed from them are exact (x3dpd.geometry.cylinder)."""
        nodes, radius, cavity = [], [], []
        for cy in self.deck.cylinders or ():
            ends = [self.structural(nid, cy.pos, "CYLINDER", what)
                    for nid, what in ((cy.node_a, "axis node A"), (cy.node_b, "axis node B"))]
            bodies = [self.slave_of.get(i, self.body_of_master.get(i)) for i in ends]
            fixed = all(self.fixed[i].all() for i in ends)
            if not fixed and (bodies[0] is None or bodies[0] != bodies[1]):
                raise self.error(f"axis nodes {cy.node_a} and {cy.node_b} must move as one "
                                 f"rigid cavity: make both RBEL slaves (or the master) of one "
                                 f"rigid body, or fix all their DOFs", cy.pos, "CYLINDER")
            length = float(np.linalg.norm(self.x0[ends[1]] - self.x0[ends[0]]))
            if not length > 0.0:
                raise self.error(f"axis nodes {cy.node_a} and {cy.node_b} coincide: the "
                                 f"cylinder has no length", cy.pos, "CYLINDER")
            nodes.append(ends)
            radius.append(cy.radius)
            cavity.append(cav_of_set[cy.set_id])
        self.cylinder_nodes = np.array(nodes, dtype=np.int64).reshape(-1, 2)
        self.cylinder_radius = np.array(radius, dtype=np.float64)
        self.cylinder_cavity = np.array(cavity, dtype=np.int64)

    def _initial_velocities(self) -> np.ndarray:
        v0 = np.zeros((self.ids.shape[0], 6))
        for k, card in enumerate(self.deck.pdmp):
            v0[self.pstart + np.flatnonzero(self.group == k), :3] = (card.vx0, card.vy0, card.vz0)
        for rec in self.deck.initials:
            i = self.node(rec.nid, rec.pos, "INITIAL", "node")
            if len(rec.velocity) not in (3, 6):
                raise self.error(f"node {rec.nid}: give 3 (vx vy vz) or 6 (and wx wy wz) "
                                 f"velocity components, got {len(rec.velocity)}", rec.pos,
                                 "INITIAL")
            v0[i, :len(rec.velocity)] = rec.velocity
        v0[self.fixed] = 0.0  # report Appendix B note 5: initial velocities obey BOUNDARY
        return v0

    def _trace(self) -> np.ndarray:
        tr = self.deck.trace
        if tr is None:
            return np.arange(self.ids.shape[0], dtype=np.int64)
        return np.array([self.node(nid, _pos_at(tr.positions, k, tr.pos), "TRACE", "node")
                         for k, nid in enumerate(tr.nodes)], dtype=np.int64)

    def _zero_mass_check(self) -> None:
        """A free, loaded translational DOF needs mass (explicit time integration divides by it)."""
        loads: dict[tuple[int, int], str] = {}
        for el, nodes, k, c in zip(self.spring_elements, self.spring_nodes, self.spring_k,
                                   self.spring_c):
            for i in nodes[nodes >= 0]:
                for a in range(3):
                    if k[a] != 0.0 or c[a] != 0.0:
                        loads.setdefault((int(i), a), f"element {el.eid} (line {el.pos.line})")
        for t, nodes in zip(self.triangles, self.tri_nodes):
            for i in nodes:
                for a in range(3):
                    loads.setdefault((int(i), a), f"the wall contact of the CONTACT triangle at "
                                                  f"line {t.pos.line}")
        for spec, (i, a) in self._external_loads():
            if a < 3:
                loads.setdefault((i, a), f"the USRFRC force {spec!r}")
        prescribed = np.zeros((len(self.ids), 6), dtype=bool)
        if self.motion:
            prescribed = prescribed_mask(motion_table(self.motion, self.ids, self.x0),
                                         len(self.ids))
        for (i, a), what in sorted(loads.items()):
            if i >= self.pstart or prescribed[i, a]:
                continue
            body = self.slave_of.get(i, self.body_of_master.get(i))
            if body is None:
                if self.fixed[i, a] or self.mass[i] > 0.0:
                    continue
                nid = int(self.ids[i])
                raise self.error(
                    f"node {nid} has no mass but its free {_AXES[a]} DOF is loaded by {what}; add "
                    f"a MASS record for node {nid}, fix DOF {a + 1} in BOUNDARY CONDITIONS, or "
                    f"make the node a slave of a rigid body (RBEL)", self.node_pos[nid],
                    "NODE COORDINATES")
            m = int(self.rigid_master[body])
            if self.fixed[m, a] or self.rigid_mass[body] > 0.0:
                continue
            nid, mid = int(self.ids[i]), int(self.ids[m])
            raise self.error(
                f"the rigid body of master {mid} has no mass but its free {_AXES[a]} DOF is "
                f"loaded by {what} (on node {nid}); add a MASS record for node {mid} or fix "
                f"DOF {a + 1} of node {mid} in BOUNDARY CONDITIONS", self.node_pos[mid],
                "NODE COORDINATES")

    def _all_usrfrc(self) -> tuple[str, ...]:
        return self._deck_usrfrc() + self.usrfrc

    def _deck_usrfrc(self) -> tuple[str, ...]:
        """The USRFRC card's specs, user force files resolved against the deck's folder.

        A deck and its force file travel together, so ``force.py`` on the card means the file
        beside the deck, whatever the working directory (``--usrfrc`` paths on the command line
        stay relative to the working directory, as shells expect). A missing file is an error at
        the card.
        """
        known = self.deck.path not in ("<deck>", "<string>", "-")
        folder = Path(self.deck.path).parent if known else None
        out = []
        for card in self.deck.usrfrc:
            for spec in card.specs:
                if is_user_file(spec):
                    path = Path(spec.strip())
                    if folder is not None and not path.is_absolute():
                        path = folder / path
                    if not path.is_file():
                        raise self.error(f"user force file {spec.strip()!r} not found "
                                         f"(looked for {path})", card.pos, "USRFRC")
                    spec = str(path)
                out.append(spec)
        return tuple(out)

    def _external_loads(self) -> list[tuple[str, tuple[int, int]]]:
        """(spec, (node index, DOF column)) of every built-in force law (user files: unknown).

        A bad spec on the deck's USRFRC card is a DeckError at the card; a bad ``--usrfrc`` spec
        raises :class:`UsrfrcError`.
        """
        out = []
        for card in self.deck.usrfrc:
            builtin, _ = split_specs(card.specs)
            if not builtin:
                continue
            try:
                table = force_table(builtin, self.ids)
            except UsrfrcError as exc:
                raise self.error(str(exc), card.pos, "USRFRC") from None
            out += [(s, (int(r[1]), int(r[2]))) for s, r in zip(builtin, table)]
        builtin, _ = split_specs(self.usrfrc)
        if builtin:
            table = force_table(builtin, self.ids)
            out += [(s, (int(r[1]), int(r[2]))) for s, r in zip(builtin, table)]
        return out

    def _effects(self, body: np.ndarray) -> frozenset:
        eff = set()
        pstart, n = self.pstart, self.ids.shape[0]
        if np.linalg.norm(body) > 0.0:
            eff.add("gravity")
        sn = self.spring_nodes
        if sn.shape[0]:
            free = ~self.fixed[sn[:, 0], :3]
            other = np.where(sn[:, 1:2] >= 0, ~self.fixed[sn[:, 1], :3], False)
            if np.any((self.spring_k > 0.0) & (free | other)):
                eff.add("springs")
        if np.any(self.spring_c > 0.0):
            eff.add("dampers")
        if self.rigid_master.shape[0]:
            eff.add("rigid_links")
            if np.any(~self.fixed[self.rigid_master, 3:]):
                eff.add("rigid_rotation")
        pc = self.particle_cavity
        if self.tri_nodes.shape[0] and np.any(pc >= 0):
            eff.add("wall_contact")
        if np.any(np.isin(pc, self.cylinder_cavity)):
            eff.add("cylinder_contact")
        counts = np.bincount(pc[pc >= 0], minlength=1)
        if np.any(counts >= 2) or (n - pstart >= 2 and np.any(pc < 0)):
            eff.add("pair_contact")
        if self.moduli.shape[1] > 1 and np.any(self.moduli[:, 1:] != 0.0):
            eff.add("viscoelastic")
        if np.any(self.mu > 0.0):
            eff.add("friction")
        if self._all_usrfrc():
            eff.add("external_force")
        if self.motion:
            eff.add("prescribed_motion")
        return frozenset(eff)


def _pos_at(positions: Sequence[Pos], k: int, fallback: Pos) -> Pos:
    return positions[k] if k < len(positions) else fallback


def _ro(a, dtype=np.float64) -> np.ndarray:
    """C-contiguous read-only copy (the model's arrays must not be modified)."""
    out = np.array(a, dtype=dtype, order="C", copy=True)
    out.flags.writeable = False
    return out
