"""The checks a :class:`~x3dpd.solver.simulation.Simulation` runs as it steps.

They turn the compiled loop's status bits into :class:`~x3dpd.errors.UnstableRunError` with a
diagnosis (penetration, a full or overflowing list, non-finite state), audit the energy ledger
(residual, negative dissipation, step instability: :mod:`x3dpd.solver.ledger_checks`, report
Section 7.4's energy balance) and check that every particle is still inside its cavity or
cylinder. A mixin: the methods read the simulation's ``state``, ``setup``, ``model`` and ``dt``.

Every decision depends on the run's state at fixed step counts only, never on how the steps
were chunked (through the API or the CLI, on an idle or a loaded machine): the ledger rows
(every ITRAC steps) are judged each against the energy scale of the rows up to it
(:meth:`RunChecks.row_scales`), and the simulation checks containment when its step count is a
multiple of its ``audit_steps``.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.errors import UnstableRunError
from x3dpd.geometry.shapes import SHAPES, analytic_wall
from x3dpd.physics.motion import motion_rows
from x3dpd.solver.diagnosis import energy_source_advice
from x3dpd.solver.ledger_checks import (
    SAFE_FRACTION,
    SHADOW_LIMIT,
    negative_dissipation,
    step_instability,
    unbalanced_row,
)


#: The checks that read the whole state -- every particle inside its cavity -- run when the step
#: count is a multiple of a simulation's ``audit_steps``: the smallest multiple of ITRAC of at
#: least this many steps. A fixed count, so that where a run stops does not depend on how it was
#: chunked; the compiled loop is called up to each, and a call with the check costs 60-140 us
#: (decks/hooke_wall.inp, beam_64.inp), 1.2 % and 0.5 % of their 10 000 steps.
AUDIT_STEPS = 10000


class RunChecks:
    """Energy-ledger audit, containment and status diagnosis of a running simulation."""

    def energy_scale(self, energy: np.ndarray) -> float:
        """Energy against which the residual is judged: the largest of the ledger's terms."""
        cols = np.abs(energy[:, 1:11])
        scale = float(cols.max()) if cols.size else 0.0
        return max(scale, abs(self.state.e_ref), 1e-300)

    def row_scales(self, energy: np.ndarray) -> np.ndarray:
        """The energy scale at each ledger row: the largest of the ledger's terms over every
        row up to and including it (the run's earlier rows through ``state.scale``).

        A row is judged by the rows before it only, never by later rows that happened to be
        computed in the same chunk: the audit then decides the same at every row whatever the
        chunking, i.e. through the API or the CLI and however loaded the machine."""
        if not energy.shape[0]:
            return np.zeros(0)
        per_row = np.max(np.abs(energy[:, 1:11]), axis=1)
        floor = max(self.state.scale, abs(self.state.e_ref), 1e-300)
        return np.maximum.accumulate(np.maximum(per_row, floor))

    def _audit_energy(self, energy: np.ndarray) -> None:
        """Check every ledger row: step stability, then the balance, then that no dissipative
        mechanism gave energy back (x3dpd.solver.ledger_checks). Each row against the energy
        scale up to it (:meth:`row_scales`)."""
        if not energy.shape[0]:
            return
        for row in energy:
            self._check_step_stability(row)
        st = self.state
        scales = self.row_scales(energy)
        tol = self.energy_tolerance
        bad = unbalanced_row(energy, scales, tol)
        neg = negative_dissipation(energy, scales, tol)
        if bad is not None and (neg is None or bad <= neg[0]):
            row = energy[bad]
            res = row[11]
            t = row[0]
            st.scale = scale = float(scales[bad])
            grew = "grew" if res > 0 else "was lost"
            raise UnstableRunError(
                f"unstable run at t = {t:.6g} s: total energy {grew} by {abs(res):.4g} without a "
                f"source ({abs(res) / scale:.1%} of the energy scale {scale:.4g}; "
                f"tolerance {_percent(tol)}). "
                + energy_source_advice(self.model, self.setup, st.vel, self.dt,
                                       self._energy_sources()),
                time=t, step=self._step_at(t))
        if neg is not None:
            k, what, amount = neg
            t = energy[k, 0]
            st.scale = scale = float(scales[k])
            raise UnstableRunError(
                f"unstable run at t = {t:.6g} s: the {what} dissipated {amount:.4g}, less than "
                f"zero ({abs(amount) / scale:.1%} of the energy scale {scale:.4g}; "
                f"tolerance {_percent(tol)}): energy was created, e.g. a particle rebounding "
                f"faster than it came in. Likely cause: the time step {self.dt:.3g} s resolves "
                f"a contact in too few steps; run `x3dpd check` for a recommended step.",
                time=t, step=self._step_at(t))
        st.scale = float(scales[-1])

    def _step_at(self, t: float) -> int:
        return int(round((t - self.model.t0) / self.dt))

    def _energy_sources(self) -> list[str]:
        out = [f"force {spec}" for spec in self._force_specs]
        out += [f"prescribed motion of node {int(self.model.node_ids[int(r[0])])} dof "
                f"{int(r[1]) + 1}" for r in motion_rows(self.motion)]
        return out

    def _check_step_stability(self, row: np.ndarray) -> None:
        """Stop when the step exceeds the stability limit of the stiffest oscillator.

        Velocity Verlet conserves KE - S + U even when unstable, so the residual cannot see a
        step beyond the limit; the Verlet correction S then outgrows the energy the run ever
        received (x3dpd.solver.ledger_checks.step_instability). ``row`` is one ledger row.
        """
        found = step_instability(row, self.state.e_ref, self.dt)
        # two rows in a row: one step after a start from rest under a force the trapezoidal
        # work is still zero while S is not (S equals the kinetic energy then), so one row alone
        # does not decide
        self._unstable_rows = self._unstable_rows + 1 if found is not None else 0
        if self._unstable_rows < 2:
            return
        t = found.time
        step = self._step_at(t)
        if math.isfinite(found.omega):
            crit = found.critical_step()
            limit = (f"the stability limit 2/omega = {crit:.3g} s of the stiffest spring or "
                     f"contact (omega ~ {found.omega:.4g} rad/s, estimated from the growing "
                     f"mode: S/U = (omega dt)^2/4); a safe step is <= "
                     f"{SAFE_FRACTION * crit:.3g} s ({SAFE_FRACTION:g} of the limit, as "
                     f"`x3dpd check` recommends)")
        else:
            limit = ("the stability limit 2/omega of the stiffest spring or contact; run "
                     "`x3dpd check` for the recommended step")
        raise UnstableRunError(
            f"unstable run at t = {t:.6g} s (step {step}): the time step {self.dt:.3g} s "
            f"exceeds {limit}. The integrator's correction energy {found.correction:.4g} "
            f"outgrew {SHADOW_LIMIT:g} times the energy the run received ({found.budget:.4g}). "
            f"Likely cause: a stiff element (e.g. a 1e12 spring on a DOF that BOUNDARY "
            f"CONDITIONS leave free).", time=t, step=step)

    def _check_containment(self) -> None:
        """Every node's position and velocity finite; every particle inside its closed cavity."""
        m, k, s = self.model, self.setup, self.state
        finite = np.all(np.isfinite(s.x), axis=1) & np.all(np.isfinite(s.vel), axis=1)
        if not finite.all():
            bad = int(np.argmax(~finite))
            what = "particle node" if bad >= k.p0 else "node"
            raise UnstableRunError(
                f"unstable run at t = {self.time:.6g} s: {what} {m.node_ids[bad]} has a "
                f"non-finite position or velocity. Likely cause: the time step {self.dt:.3g} s "
                f"is too large; run `x3dpd check` for a recommended step.",
                time=self.time, step=s.step, node=int(m.node_ids[bad]))
        self._check_shape_containment()
        if m.n_particles == 0 or k.tri_nodes.shape[0] == 0:
            return
        xp = s.x[k.p0:]
        for c, nodes in enumerate(self._cavity_nodes()):
            members = np.nonzero(k.pcav == c)[0]
            if members.size == 0 or nodes.size == 0:
                continue
            lo = s.x[nodes].min(axis=0)
            hi = s.x[nodes].max(axis=0)
            pos = xp[members]
            r = k.radius[members][:, None]
            out = np.any((pos < lo - r) | (pos > hi + r), axis=1)
            if out.any():
                self._escaped(int(members[np.argmax(out)]),
                              f"cavity (CONTACT set {int(m.cavity_set_ids[c])})", "a wall")

    def _check_shape_containment(self) -> None:
        """Every particle of an analytic wall's cavity with its centre inside the wall."""
        k, s = self.setup, self.state
        table = k.shapes
        for w in range(table.kind.shape[0]):
            members = table.particle[table.wall == w]
            if members.size == 0:
                continue
            shape, ends, lengths = analytic_wall(table.kind[w], table.nodes[w], table.params[w],
                                                 s.x)
            _, inside = shape.clearance(s.x[k.p0 + members], k.radius[members], ends, lengths)
            if not inside.all():
                self._escaped(int(members[np.argmin(inside)]),
                              f"{shape.name} ({self._shape_nodes(w)})", "the wall")

    def _shape_nodes(self, w: int) -> str:
        """'axis nodes 2, 3' of analytic wall ``w``."""
        table = self.setup.shapes
        shape = SHAPES[int(table.kind[w])]
        ids = table.nodes[w][:len(shape.node_fields)]
        return f"{shape.nodes_word} {', '.join(str(int(self.model.node_ids[q])) for q in ids)}"

    def _escaped(self, p: int, home: str, wall: str) -> None:
        """Stop: particle ``p`` left its ``home`` (it tunnelled through ``wall``)."""
        nid = int(self.model.node_ids[self.setup.p0 + p])
        where = np.round(self.state.x[self.setup.p0 + p], 6).tolist()
        raise UnstableRunError(
            f"unstable run at t = {self.time:.6g} s: particle node {nid} left its {home} at "
            f"{where}. Likely cause: the time step {self.dt:.3g} s is too large for the wall "
            f"contact stiffness, so the particle tunnelled through {wall}.",
            time=self.time, step=self.state.step, node=nid)

    def _cavity_nodes(self) -> list:
        """Node indices of each *closed* cavity (an empty array for an open one: a particle
        may legitimately leave the box of a lone floor's nodes)."""
        if not hasattr(self, "_cav_nodes"):
            from x3dpd.geometry.cavity import merge_vertices, surface_edges

            m, k = self.model, self.setup
            out = []
            size = float(np.ptp(k.x0, axis=0).max()) or 1.0
            labels = merge_vertices(k.x0, size)
            for c in range(k.cav_ptr.shape[0] - 1):
                faces = k.cav_faces[k.cav_ptr[c]:k.cav_ptr[c + 1]]
                tris = np.isin(m.tri_face, faces)
                closed, _ = surface_edges(labels[k.tri_nodes[tris]], k.tri_sign[tris])
                out.append(np.unique(k.tri_nodes[tris]) if closed else np.zeros(0, np.int64))
            self._cav_nodes = out
        return self._cav_nodes

    def _check_status(self, status: int, t: float, step: int) -> None:
        if status == 0:
            return
        m, k = self.model, self.setup
        if status & 2:
            raise UnstableRunError(
                f"unstable run at t = {t:.6g} s (step {step}): a traced value became non-finite "
                f"(inf or NaN). Likely cause: the time step {self.dt:.3g} s is too large.",
                time=t, step=step)
        if status & 1:
            p = int(self.diag[0])
            other = int(self.diag[1])
            depth = self.diag[2]
            r = self.diag[3]
            nid = int(m.node_ids[k.p0 + p])
            nf = k.face_first_tri.shape[0]
            if other >= nf:   # an analytic wall's part: n_faces + its entity number
                table = k.shapes
                w = int(np.searchsorted(table.entity, other - nf, side="right") - 1)
                shape = SHAPES[int(table.kind[w])]
                part = other - nf - int(table.entity[w])
                what = (f"the {shape.part_names[part]} of the {shape.name} on "
                        f"{self._shape_nodes(w)}")
            elif other >= 0:
                tri = int(k.face_tris[k.face_ptr[other]])
                what = (f"wall triangle {tri + 1} (nodes "
                        f"{', '.join(str(int(m.node_ids[q])) for q in k.tri_nodes[tri])})")
            else:
                what = f"particle node {int(m.node_ids[k.p0 - 1 - other])}"
            if step == 0:
                raise UnstableRunError(
                    f"particle node {nid} starts {depth:.4g} deep inside {what}, more than "
                    f"{self.penetration_limit:.0%} of its radius {r:.4g}: the deck's geometry is "
                    f"wrong (run `x3dpd check` on it).", time=t, step=step, node=nid)
            raise UnstableRunError(
                f"unstable run at t = {t:.6g} s (step {step}): particle node {nid} penetrated "
                f"{what} by {depth:.4g} ({depth / r:.1%} of its radius; limit "
                f"{self.penetration_limit:.0%}). Likely cause: the time step {self.dt:.3g} s is "
                f"too large for the contact stiffness at this impact speed; run `x3dpd check`.",
                time=t, step=step, node=nid)

    # ------------------------------------------------------------------ internals


def _percent(fraction: float) -> str:
    """A tolerance as a percentage with the digits it needs (5 %, 0.1 %, 1e-06 %)."""
    return f"{fraction:.0%}" if fraction >= 0.01 else f"{fraction * 100:.2g} %"
