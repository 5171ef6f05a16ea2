"""Model builder step for the MODAL card: the modes as given, then coupled with the deck's mass.

From the card's records (x3dpd.deck.modal_card) or its mode file (x3dpd.deck.mode_files):

1. the modes kept (FILE ``modes=``, ``band=``), their damping (the file's, or ``zeta=``), the
   file's node ids mapped to deck nodes (the same ids, or ``map=``; file nodes that are not in
   the deck are left out -- a file may hold a whole FE model), its units converted to the deck's
   (UNITS card), shapes checked for mass normalisation (a generalized mass that is not 1 is an
   error unless ``normalize=mass``);
2. the DOFs held: a DOF with no shape value (a file with translations only, a SHAPE record
   missing) or fixed by BOUNDARY CONDITIONS does not move, and what acts on it goes to ground;
3. the deck's mass on modal nodes coupled in (``HOUSING added``, the default: the modes are of
   the structure without the damper housing): the node's 6 x 6 mass matrix (a rigid body's about
   its master: m, first moment, inertia tensor; a plain node's MASS and element masses) gives
   :math:`\\mathsf M = \\mathsf I + \\Phi^{\\mathsf T}\\mathsf M_a\\Phi`, and the reduced
   eigenproblem :math:`\\mathrm{diag}(\\omega^2)\\psi = \\lambda\\mathsf M\\psi`
   (:math:`\\psi^{\\mathsf T}\\mathsf M\\psi = \\mathsf I`) is solved once: the coupled modes
   :math:`\\Phi\\psi` with frequencies :math:`\\sqrt\\lambda` are again independent oscillators,
   each integrated exactly. Their damping :math:`\\psi^{\\mathsf T}\\mathrm{diag}(2\\zeta\\omega)
   \\psi` keeps its diagonal as modal damping; what it has off the diagonal couples the modes and
   is applied as a force (x3dpd.physics.modal). ``HOUSING included``: the modes already contain
   the housing; the deck's mass on modal nodes is neither added nor weighed.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.errors import Pos
from x3dpd.model.build_base import BuilderBase
from x3dpd.model.modal_structure import ModalStructure, unit_factors

CARD = "MODAL"
#: Relative tolerance of a generalized mass of 1 (mass-normalised shapes).
UNIT_MASS_TOLERANCE = 1e-3
#: Highest natural frequency a mode may have [cycles per time unit]: far above any structural
#: mode, and low enough that omega^2 and the step coefficients stay far from overflow.
MAX_FREQUENCY = 1e12
#: Largest ratio of two nonzero natural frequencies whose modes the deck's mass couples: the
#: coupled eigenproblem (scipy.linalg.eigh) resolves its lowest eigenvalue to about
#: eps (f_max / f_min)^2 of itself, 2e-6 at this ratio; at 1e15 Hz beside 38 Hz it found 0 Hz.
MAX_FREQUENCY_RATIO = 1e5


class ModalSteps(BuilderBase):
    """The modal structure of a deck with a MODAL card (``self.modal``; None without)."""

    def _modal(self) -> None:
        self.modal = None
        self.modal_nodes: set[int] = set()
        card = self.deck.modal
        if card is None:
            return
        if card.files:
            numbers, freq, zeta, shapes, source = self._modes_from_file(card.files[0])
            where = {i: card.files[0].pos for i in shapes}
        else:
            numbers, freq, zeta, shapes, source = self._modes_inline(card)
            where = {}
            for s in card.shapes:
                where.setdefault(self.index[s.node], s.node_pos if s.node_pos.line else s.pos)
        nodes = sorted(shapes)
        phi = np.stack([shapes[i] for i in nodes]) if nodes else np.zeros((0, 6, len(freq)))
        held = np.isnan(phi).all(axis=2)
        phi = np.nan_to_num(phi, nan=0.0)
        for j, i in enumerate(nodes):
            fixed = self.fixed[i]
            held[j] |= fixed
            phi[j, fixed, :] = 0.0
            if i in self.slave_of:
                master = int(self.ids[self.rigid_master[self.slave_of[i]]])
                raise self.error(
                    f"node {int(self.ids[i])} has shape values but is a slave of the "
                    f"rigid body of master {master}; give the shape values at the "
                    "master"
                    + (" (with map=, only the mapped file nodes are used)" if card.files else ""),
                    where[i],
                    CARD,
                )
        node_idx = np.array(nodes, dtype=np.int64)
        added = (
            self._added_mass(node_idx) if card.housing == "added" else np.zeros((len(nodes), 6, 6))
        )
        self._check_frequencies(card, numbers, freq, coupled=bool(np.any(added)))
        omega0 = 2.0 * math.pi * np.asarray(freq, dtype=np.float64)
        omega, zeta_c, shape_c, coupling = couple_added_mass(omega0, np.asarray(zeta), phi, added)
        body = np.array([self.body_of_master.get(int(i), -1) for i in node_idx], dtype=np.int64)
        self.modal = ModalStructure(
            nodes=node_idx,
            shape=shape_c,
            omega=omega,
            zeta=zeta_c,
            coupling=coupling,
            body=body,
            held=held,
            added_mass=added,
            given_numbers=np.asarray(numbers, np.int64),
            given_freq=np.asarray(freq, dtype=np.float64),
            given_zeta=np.asarray(zeta, float),
            given_shape=phi,
            housing=card.housing,
            source=source,
        )
        self.modal_nodes = {int(i) for i in node_idx}

    def _check_frequencies(self, card, numbers, freq, coupled: bool) -> None:
        """Each mode's frequency within [0, MAX_FREQUENCY]; with the deck's mass coupled in,
        the nonzero ones within MAX_FREQUENCY_RATIO of each other. The error stands at the
        mode's MODE record (at the FILE record for a mode file)."""
        f = np.asarray(freq, dtype=np.float64)

        def where(k: int) -> Pos:
            if card.files:
                return card.files[0].pos
            return next(m.pos for m in card.modes if m.number == numbers[k])

        def prefix() -> str:
            return f"mode file {card.files[0].path}: " if card.files else ""

        high = np.flatnonzero(~(f <= MAX_FREQUENCY))
        if high.size:
            k = int(high[0])
            raise self.error(
                f"{prefix()}mode {numbers[k]} has frequency {f[k]:.6g} (cycles per time unit): "
                f"out of range, expected 0 <= FREQ <= {MAX_FREQUENCY:g} (no structural mode "
                "comes near it: a typing slip?)",
                where(k),
                CARD,
            )
        nonzero = np.flatnonzero(f > 0.0)
        if coupled and nonzero.size > 1:
            lo = int(nonzero[np.argmin(f[nonzero])])
            hi = int(nonzero[np.argmax(f[nonzero])])
            if f[hi] > MAX_FREQUENCY_RATIO * f[lo]:
                raise self.error(
                    f"{prefix()}mode {numbers[hi]} has frequency {f[hi]:.6g}, "
                    f"{f[hi] / f[lo]:.3g} x above mode {numbers[lo]}'s {f[lo]:.6g}: with the "
                    f"deck's mass coupled in (HOUSING added) modes more than "
                    f"{MAX_FREQUENCY_RATIO:g} x apart cannot be solved together in double "
                    "precision; leave the high mode out (modes=, band=) or give HOUSING included",
                    where(hi),
                    CARD,
                )

    # -- inline records -------------------------------------------------------------------------
    def _modes_inline(self, card):
        modes = sorted(card.modes, key=lambda m: m.number)
        order = [card.modes.index(m) for m in modes]
        for m in modes:
            if m.mass is not None and abs(m.mass - 1.0) > UNIT_MASS_TOLERANCE:
                raise self.error(
                    f"mode {m.number} has generalized mass {m.mass:g}: the shapes are "
                    f"not mass-normalised (divide them by sqrt({m.mass:g}) and give "
                    f"MASS 1, or leave MASS off)",
                    m.pos,
                    CARD,
                )
        shapes: dict[int, np.ndarray] = {}
        for s in card.shapes:
            pos = s.node_pos if s.node_pos.line else s.pos
            i = self.structural(s.node, pos, CARD, "SHAPE node")
            row = shapes.setdefault(i, np.full((6, len(modes)), np.nan))
            row[s.dof - 1] = [s.values[k] for k in order]
        return (
            [m.number for m in modes],
            [m.freq for m in modes],
            [m.zeta for m in modes],
            shapes,
            "MODE/SHAPE records",
        )

    # -- a mode file ----------------------------------------------------------------------------
    # Over 80 lines: a mode file read, selected, mapped and coupled.
    def _modes_from_file(self, rec):
        ms = rec.mode_set
        if ms is None:
            raise self.error(
                f"mode file {rec.path} was not read (parse the deck with x3dpd.deck.read_deck)",
                rec.pos,
                CARD,
            )
        opt = rec.option
        numbers = np.asarray(ms.mode_numbers, dtype=np.int64)
        keep = np.ones(numbers.shape[0], dtype=bool)
        if opt("modes"):
            want, pos = opt("modes")
            missing = sorted(set(want) - set(numbers.tolist()))
            if missing:
                raise self.error(
                    f"mode file {rec.path} has no mode {missing[0]} (it holds modes "
                    f"{_ranges(numbers)})",
                    pos,
                    CARD,
                )
            keep &= np.isin(numbers, want)
        # units: the file's own, or the record's units=, converted to the deck's
        deck_units = self._deck_units()
        file_units = tuple(ms.units) if ms.units is not None else None
        if opt("units"):
            stated, pos = opt("units")
            stated = tuple(stated)
            if file_units is not None and stated != file_units:
                raise self.error(
                    f"FILE units={','.join(stated)} contradicts mode file "
                    f"{rec.path}, which says it is in {' '.join(file_units)}",
                    pos,
                    CARD,
                )
            file_units = stated
        f_time, f_shape_t, f_shape_r = unit_factors(file_units or deck_units, deck_units)
        freq = np.asarray(ms.freq_hz, dtype=np.float64) * f_time
        if opt("band"):
            (lo, hi), pos = opt("band")
            keep &= (freq >= lo) & (freq <= hi)
        if not keep.any():
            raise self.error(
                f"no mode of mode file {rec.path} is kept (it holds modes "
                f"{_ranges(numbers)} at {_freqs(freq)})",
                rec.pos,
                CARD,
            )
        if np.any(freq[keep] < 0.0) or not np.all(np.isfinite(freq[keep])):
            raise self.error(
                f"mode file {rec.path} has a negative or non-finite frequency", rec.pos, CARD
            )
        shapes_all = np.asarray(ms.shapes, dtype=np.float64)[keep]  # (M, N, 6)
        shapes_all = shapes_all.copy()
        shapes_all[..., :3] *= f_shape_t
        shapes_all[..., 3:] *= f_shape_r
        mass = None if ms.modal_mass is None else np.asarray(ms.modal_mass, float)[keep]
        if mass is not None:
            bad = np.abs(mass - 1.0) > UNIT_MASS_TOLERANCE
            if opt("normalize"):
                shapes_all /= np.sqrt(mass)[:, None, None]
            elif bad.any():
                k = int(np.argmax(bad))
                raise self.error(
                    f"mode file {rec.path}: mode {int(numbers[keep][k])} has "
                    f"generalized mass {mass[k]:g}: the shapes are not "
                    f"mass-normalised (add normalize=mass to rescale them)",
                    rec.pos,
                    CARD,
                )
        # damping
        if opt("zeta"):
            parts, pos = opt("zeta")
            if len(parts) not in (1, int(keep.sum())):
                raise self.error(
                    f"FILE zeta gives {len(parts)} values for {int(keep.sum())} "
                    f"kept modes; give one for all or one per mode",
                    pos,
                    CARD,
                )
            zeta = np.broadcast_to(np.asarray(parts), (int(keep.sum()),)).copy()
        elif ms.damping is not None:
            zeta = np.asarray(ms.damping, dtype=np.float64)[keep]
        else:
            raise self.error(
                f"mode file {rec.path} gives no damping: add zeta=RATIO (one for "
                "all modes, or one per kept mode)",
                rec.pos,
                CARD,
            )
        # nodes
        mapping = opt("map")[0] if opt("map") else {}
        shapes: dict[int, np.ndarray] = {}
        for n, fid in enumerate(np.asarray(ms.node_ids, dtype=np.int64)):
            if mapping and int(fid) not in mapping:
                continue  # with map=, the mapped nodes only
            did = mapping.get(int(fid), int(fid))
            i = self.index.get(did)
            if i is None:
                if int(fid) in mapping:
                    pos = opt("map")[1]
                    raise self.error(
                        f"FILE map sends file node {int(fid)} to node {did}, which "
                        "is not defined in NODE COORDINATES",
                        pos,
                        CARD,
                    )
                continue  # a node of the FE model the deck does not use
            if i >= self.pstart:
                raise self.error(
                    f"mode file node {int(fid)} is deck node {did}, a particle node "
                    f"(PDMP NODLIM {self.nodlim})",
                    rec.pos,
                    CARD,
                )
            shapes[i] = shapes_all[:, n, :].T.copy()  # (6, M)
        for fid in mapping:
            if fid not in set(np.asarray(ms.node_ids).tolist()):
                pos = opt("map")[1]
                raise self.error(
                    f"FILE map names file node {fid}, which mode file {rec.path} does not hold",
                    pos,
                    CARD,
                )
        if not shapes:
            raise self.error(
                f"no node of mode file {rec.path} is a node of the deck (give map=FILE:DECK pairs)",
                rec.pos,
                CARD,
            )
        return numbers[keep].tolist(), freq[keep].tolist(), zeta.tolist(), shapes, rec.path

    def _deck_units(self) -> tuple[str, str, str]:
        u = getattr(self.deck, "units", None)
        return u.system if u is not None else ("in", "lbf", "s")

    # -- the deck's mass on modal nodes ---------------------------------------------------------
    def _added_mass(self, nodes: np.ndarray) -> np.ndarray:
        """(N, 6, 6) mass matrix of what the deck puts on each modal node: a rigid body's about
        its master (mass, first moment S = sum m_s r_s, inertia tensor J), else the node's
        MASS and element masses on the diagonal [mass, mass length, mass length^2]."""
        out = np.zeros((nodes.shape[0], 6, 6))
        for j, i in enumerate(nodes):
            b = self.body_of_master.get(int(i))
            if b is None:
                out[j] = np.diag([self.mass[i]] * 3 + list(self.inertia[i]))
                continue
            sl = self.rigid_slaves[self.rigid_ptr[b] : self.rigid_ptr[b + 1]]
            first = (self.mass[sl, None] * (self.x0[sl] - self.x0[i])).sum(axis=0)
            out[j, :3, :3] = self.rigid_mass[b] * np.eye(3)
            out[j, :3, 3:] = -_cross_matrix(first)
            out[j, 3:, :3] = _cross_matrix(first)
            out[j, 3:, 3:] = self.rigid_inertia[b]
        return out


def couple_added_mass(omega: np.ndarray, zeta: np.ndarray, phi: np.ndarray, added: np.ndarray):
    """The modes of the structure with ``added`` (N, 6, 6) mass on its nodes: (omega, zeta,
    shape (N, 6, M), coupling (M, M) or (0, 0)); see the module docstring."""
    m_count = omega.shape[0]
    flat = phi.reshape(-1, m_count)  # (N*6, M)
    big = np.zeros((flat.shape[0], flat.shape[0]))
    for j in range(added.shape[0]):
        big[6 * j : 6 * j + 6, 6 * j : 6 * j + 6] = added[j]
    m_red = np.eye(m_count) + flat.T @ big @ flat
    if np.allclose(m_red, np.eye(m_count), rtol=0.0, atol=1e-14):
        return omega.copy(), zeta.copy(), phi.copy(), np.zeros((0, 0))
    from scipy.linalg import eigh  # here: scipy.linalg costs every run half a second of import

    lam, psi = eigh(np.diag(omega**2), 0.5 * (m_red + m_red.T))
    for k in range(m_count):  # a sign that does not depend on the solver: largest > 0
        if psi[np.argmax(np.abs(psi[:, k])), k] < 0.0:
            psi[:, k] = -psi[:, k]
    omega_c = np.sqrt(np.maximum(lam, 0.0))
    damping = psi.T @ np.diag(2.0 * zeta * omega) @ psi
    diag = np.diag(damping).copy()
    zeta_c = np.where(omega_c > 0.0, diag / np.where(omega_c > 0.0, 2.0 * omega_c, 1.0), 0.0)
    coupling = damping - np.diag(np.where(omega_c > 0.0, diag, 0.0))
    scale = max(float(np.max(np.abs(diag))), 1e-300)
    if np.max(np.abs(coupling)) <= 1e-12 * scale:
        coupling = np.zeros((0, 0))
    shape = (flat @ psi).reshape(phi.shape[0], 6, m_count)
    return omega_c, zeta_c, shape, coupling


def _cross_matrix(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _ranges(numbers) -> str:
    numbers = list(numbers)
    return ", ".join(str(n) for n in numbers[:12]) + (" ..." if len(numbers) > 12 else "")


def _freqs(freq) -> str:
    return ", ".join(f"{f:.4g}" for f in list(freq)[:8]) + (" ..." if len(freq) > 8 else "")


__all__ = ["ModalSteps", "couple_added_mass", "Pos"]
