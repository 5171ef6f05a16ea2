"""Deck -> Model: cross-reference checks, then the arrays the solver needs.

:func:`build_model` is the only entry point. Every problem it finds is a :class:`DeckError`
pointing at the offending record (``FILE:LINE:COL: CARD: message``). Physics stays out: the
builder only sums masses, applies material scale factors and reads geometry.

The steps live beside this module: errors and node lookups in ``build_base``, particles in
``build_particles``, masses, springs (MATID types 1-3), boundaries and rigid bodies in
``build_structure``, cavity walls and analytic walls in ``build_walls`` (wall orientation),
USRFRC loads and the zero-mass check in ``build_loads``. This module runs them in order and
assembles the :class:`Model`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from x3dpd.errors import NOWHERE, Pos
from x3dpd.geometry.shapes import SHAPES
from x3dpd.model.build_base import _pos_at, _ro
from x3dpd.model.build_loads import LoadSteps
from x3dpd.model.build_modal import ModalSteps
from x3dpd.model.build_particles import ParticleSteps
from x3dpd.model.build_structure import StructureSteps
from x3dpd.model.build_units import UnitSteps
from x3dpd.model.build_walls import WallSteps
from x3dpd.model.model import Model
from x3dpd.model.temperature import warmed

if TYPE_CHECKING:  # the builder reads cards by attribute; it needs no runtime import of them
    from x3dpd.deck.cards import Deck


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
    model = _Builder(deck, tuple(usrfrc), tuple(motion)).build()
    if getattr(deck, "temperature", None) is None:
        return model
    # TEMPERATURE (x3dpd.model.temperature): the cards carried to the operating temperature,
    # built again; ``model`` (the deck as written: the assembly temperature) tells how
    return warmed(deck, model, lambda cards: _Builder(cards, tuple(usrfrc), tuple(motion)).build())


class _Builder(ParticleSteps, StructureSteps, WallSteps, LoadSteps, ModalSteps, UnitSteps):
    """One build: the steps in order, then the :class:`Model` (steps: ``build_*`` modules)."""

    # -- build --------------------------------------------------------------------------------

    # Over 80 lines: the model's builders called in the order their inputs need, a line or two each.
    def build(self) -> Model:
        deck = self.deck
        if deck.plates:  # the reader builds them (x3dpd.deck.read_deck); a deck made in code
            raise self.error(  # must too (x3dpd.deck.plates.expand_plates)
                "the PLATES card is not built into the deck's cards: read the deck with "
                "x3dpd.deck.read_deck, or call x3dpd.deck.plates.expand_plates",
                deck.plates[0].pos,
                "PLATES",
            )
        par = self._parameters()
        self._nodes()
        self._particles()
        n = self.ids.shape[0]
        self.mass = np.zeros(n)
        self.inertia = np.zeros((n, 3))
        self.mass[self.pstart :] = self.p_mass
        self.inertia[self.pstart :] = (0.4 * self.p_mass * self.radius**2)[:, None]
        self._masses()
        self._springs()
        self.fixed = self._boundaries()
        self._rigid_bodies()
        self._modal()
        self._walls()
        unit_data = self._unit_data()
        v0 = self._initial_velocities()
        trace = self._trace()
        self._zero_mass_check()
        body = (
            np.zeros(3)
            if deck.body is None
            else np.array([deck.body.ax, deck.body.ay, deck.body.az], dtype=np.float64)
        )
        return Model(
            node_ids=_ro(self.ids, np.int64),
            x0=_ro(self.x0),
            mass=_ro(self.mass),
            inertia=_ro(self.inertia),
            fixed=_ro(self.fixed, bool),
            v0=_ro(v0),
            body_accel=_ro(body),
            particle_start=int(self.pstart),
            radius=_ro(self.radius),
            density=_ro(self.density),
            poisson=_ro(self.poisson),
            mu=_ro(self.mu),
            moduli=_ro(self.moduli),
            taus=_ro(self.taus),
            particle_group=_ro(self.group, np.int64),
            particle_cavity=_ro(self.particle_cavity, np.int64),
            spring_nodes=_ro(self.spring_nodes.reshape(-1, 2), np.int64),
            spring_k=_ro(self.spring_k.reshape(-1, 3)),
            spring_c=_ro(self.spring_c.reshape(-1, 3)),
            axial_nodes=_ro(self.axial_nodes, np.int64),
            axial_k=_ro(self.axial_k),
            axial_c=_ro(self.axial_c),
            axial_length=_ro(self.axial_length),
            rotational_nodes=_ro(self.rotational_nodes, np.int64),
            rotational_k=_ro(self.rotational_k),
            rotational_c=_ro(self.rotational_c),
            rigid_master=_ro(self.rigid_master, np.int64),
            rigid_ptr=_ro(self.rigid_ptr, np.int64),
            rigid_slaves=_ro(self.rigid_slaves, np.int64),
            rigid_mass=_ro(self.rigid_mass),
            rigid_inertia=_ro(self.rigid_inertia.reshape(-1, 3, 3)),
            tri_nodes=_ro(self.tri_nodes.reshape(-1, 3), np.int64),
            tri_sign=_ro(self.tri_sign),
            tri_face=_ro(self.tri_face, np.int64),
            face_cavity=_ro(self.face_cavity, np.int64),
            cavity_set_ids=_ro(self.cavity_set_ids, np.int64),
            shape_kind=_ro(self.shape_kind, np.int64),
            shape_nodes=_ro(self.shape_nodes.reshape(-1, 2), np.int64),
            shape_params=_ro(self.shape_params),
            shape_cavity=_ro(self.shape_cavity, np.int64),
            trace_nodes=_ro(trace, np.int64),
            t0=float(par.time),
            tmax=float(par.tmax),
            dt=float(par.dtmax),
            trest=float(par.trest),
            itrac=int(par.itrac),
            irest=int(par.irest),
            incmax=float(par.incmax),
            effects=self._effects(body),
            usrfrc=self._deck_usrfrc(),
            title=deck.title.text if deck.title is not None else "",
            units=(
                deck.units.system
                if getattr(deck, "units", None) is not None
                else ("in", "lbf", "s")
            ),
            path=deck.path,
            modal=self.modal,
            unit_data=unit_data,
            **self._normal_law(),
            wall_material=self._wall_materials(),
            **self._friction_fields(),
        )

    def _parameters(self):
        par = self.deck.parameters
        if par is None:
            raise self.error(
                "no PARAMETERS card: the deck must give TIME TMAX TREST DTMIN DTMAX "
                "INCR INCMAX IREST NINTPL ISTAT ITRAC",
                NOWHERE,
                "PARAMETERS",
            )
        if not par.dtmax > 0.0:
            raise self.error(
                f"DTMAX must be > 0 (it is the time step), got {par.dtmax:g}", par.pos, "PARAMETERS"
            )
        if par.dtmin > par.dtmax:
            raise self.error(
                f"DTMIN {par.dtmin:g} is larger than DTMAX {par.dtmax:g}", par.pos, "PARAMETERS"
            )
        if par.tmax < par.time:
            raise self.error(
                f"TMAX {par.tmax:g} is before the start time TIME {par.time:g}",
                par.pos,
                "PARAMETERS",
            )
        return par

    def _nodes(self) -> None:
        first: dict[int, Pos] = {}
        for nd in self.deck.nodes:
            if nd.nid in first:
                raise self.error(
                    f"node {nd.nid} is defined twice (first at line {first[nd.nid].line})",
                    nd.pos,
                    "NODE COORDINATES",
                )
            first[nd.nid] = nd.pos
        nodes = sorted(self.deck.nodes, key=lambda nd: nd.nid)
        self.node_pos = first
        self.ids = np.array([nd.nid for nd in nodes], dtype=np.int64)
        self.x0 = np.array([(nd.x, nd.y, nd.z) for nd in nodes], dtype=np.float64).reshape(-1, 3)
        self.index = {int(nid): i for i, nid in enumerate(self.ids)}

    def _trace(self) -> np.ndarray:
        tr = self.deck.trace
        if tr is None:
            return np.arange(self.ids.shape[0], dtype=np.int64)
        return np.array(
            [
                self.node(nid, _pos_at(tr.positions, k, tr.pos), "TRACE", "node")
                for k, nid in enumerate(tr.nodes)
            ],
            dtype=np.int64,
        )

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
        if np.any(self.axial_k != 0.0) or np.any(self.axial_c != 0.0):
            eff.add("axial_springs")
        if np.any(self.rotational_k != 0.0) or np.any(self.rotational_c != 0.0):
            eff.add("rotational_springs")
        if self.rigid_master.shape[0]:
            eff.add("rigid_links")
            plain = [m for m in self.rigid_master if int(m) not in self.modal_nodes]
            if plain and np.any(~self.fixed[plain, 3:]):
                eff.add("rigid_rotation")
        if self.modal is not None:
            eff.add("modal_structure")
            turning = self.modal.body >= 0
            if np.any(self.modal.shape[turning, 3:] != 0.0):
                eff.add("rigid_rotation")
        pc = self.particle_cavity
        if self.tri_nodes.shape[0] and np.any(pc >= 0):
            eff.add("wall_contact")
        for kind, shape in enumerate(SHAPES):  # analytic walls: "cylinder_contact" ...
            if np.any(np.isin(pc, self.shape_cavity[self.shape_kind == kind])):
                eff.add(shape.effect)
        # particles alone in cells (a drilled plate's holes, Shape.cells) never meet
        alone = np.isin(
            pc, self.shape_cavity[[SHAPES[k].cells is not None for k in self.shape_kind]]
        )
        counts = np.bincount(pc[(pc >= 0) & ~alone], minlength=1)
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
        return frozenset(eff | self.unit_effects)
