"""Closed-form steady state of any particle-free linear structure a deck can hold: lumped nodes
and rigid bodies on MATID type 1 springs and dashpots (to ground, to each other, to a moving
base), and a modal structure (MODAL card) they may be attached to -- the baselines of a sweep or
an FRF where the simpler forms of x3dpd.design.baselines (one SDOF, the modes alone, an SDOF on a
base) do not apply.

Coordinates z: the M coupled modal coordinates q (x3dpd.model.modal_structure: mass-normalised,
M_q = I, K_q = diag(w_r^2), C_q = diag(2 zeta_r w_r) + the coupling) and one coordinate per free
translational DOF of every non-modal body (a node, or a rigid body's master with its mass). A
node's displacement along axis d is a row e(node, d) . [z; u]:

* a modal node: its shape values phi_d (0 where held); a rigid slave of a modal master:
  phi_d(master) + (phi_rot(master) x r0)_d, r0 its offset from the master (small rotations);
* a non-modal body's node: its body's coordinate along d, 0 where the body is fixed (BOUNDARY);
* the base (a base drive's node, and its rigid slaves) along the drive's DOF: u, the prescribed
  motion.

A spring or dashpot k_d, c_d along axis d between nodes a and b (b: ground, e = 0) adds
k_d r r^T and c_d r r^T with r = e(a, d) - e(b, d) (MATID type 1 acts along the global axes); a
body's mass m adds m on its coordinate. With D(w) = K - w^2 M + i w C partitioned into the free
part zz and the base column zu, the steady state of u = Im(U e^{i w t}) or of a force
F = Im(F e^{i w t}) on node n along d is

    D_zz Z = -D_zu U          (base drive),       D_zz Z = e(n, d) F      (force drive),

and a response X = e(out) . [Z; U]; the dashpots and the modal damping dissipate
pi w Re([Z; U]^H C [Z; U]) per cycle (Rayleigh: the time average of c xdot^2 over a cycle).

Not in this form (``None``: the baseline is simulated): particles, axial or rotational springs
(MATID types 2 and 3), a rotational DOF (a translation only is driven and measured), a base that
is a modal node, a spring on an off-master node of a non-modal body free to turn (its moment
would couple the body's rotation), and a singular D_zz (a free body with no mass).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from x3dpd.api.structures import Model


@dataclass(frozen=True)
class LinearSystem:
    """A particle-free linear structure in the frequency domain (module doc): matrices over the
    coordinates [z; u] (u the base's prescribed motion, a zero column under a force drive), the
    driving row and the measured row. ``base``: a base drive (``drive_row`` unused)."""

    stiffness: np.ndarray
    damping: np.ndarray
    mass: np.ndarray
    drive_row: np.ndarray
    out_row: np.ndarray
    base: bool

    def state(self, omega: float, drive: complex = 1.0) -> np.ndarray:
        """Complex amplitudes [Z; U] under a drive of complex amplitude ``drive`` (a force, or
        the base's displacement)."""
        dyn = self.stiffness - omega * omega * self.mass + 1j * omega * self.damping
        n = dyn.shape[0] - 1
        if self.base:
            rhs = -dyn[:n, n] * drive
        else:
            rhs = self.drive_row[:n].astype(complex) * drive
        z = np.linalg.solve(dyn[:n, :n], rhs)
        return np.append(z, drive if self.base else 0.0)

    def frf(self, omega: float) -> complex:
        """X / F (force drive, a receptance [length/force]) or X / U (base drive, the absolute
        motion's transmissibility) at the measured DOF."""
        return complex(self.out_row @ self.state(omega))

    def transmissibility(self, omega: float) -> complex:
        """X / U of a base drive (:meth:`frf`)."""
        return self.frf(omega)

    def receptance(self, omega: float) -> complex:
        """X / F of a force drive (:meth:`frf`)."""
        return self.frf(omega)

    def measured_at(self, out_row: np.ndarray) -> LinearSystem:
        """The same structure and drive measured at another row."""
        return LinearSystem(
            self.stiffness, self.damping, self.mass, self.drive_row, out_row, self.base
        )

    def response(self, drive: float, omega: float) -> tuple[float, float]:
        """Steady-state amplitude X [length] and phase [rad] against the drive's sin(omega t)
        under a drive of amplitude ``drive`` (force, or the base's displacement)."""
        h = self.frf(omega)
        return abs(drive * h), math.atan2(h.imag, h.real)

    def work_per_cycle(self, drive: float, omega: float) -> float:
        """Energy the dashpots and the modal damping take per cycle under a drive of amplitude
        ``drive``, pi w Re(v^H C v) (= the drive's work per cycle in the steady state)."""
        v = self.state(omega, drive)
        return float(math.pi * omega * np.real(np.conj(v) @ self.damping @ v))

    def dissipated_per_cycle(self, amplitude: float, omega: float) -> float:
        """A base drive: :meth:`work_per_cycle` of base amplitude ``amplitude``. A force drive:
        of the force that gives the driven DOF the displacement amplitude ``amplitude`` (as
        x3dpd.design.baselines.Sdof.dissipated_per_cycle takes it)."""
        if self.base:
            return self.work_per_cycle(amplitude, omega)
        at_drive = abs(complex(self.drive_row @ self.state(omega)))
        return self.work_per_cycle(amplitude / at_drive, omega) if at_drive > 0 else 0.0


def _bodies(model: Model) -> dict[int, int]:
    """Node index -> its rigid body's master index (every node of a rigid body)."""
    out = {}
    for b, master in enumerate(model.rigid_master):
        out[int(master)] = int(master)
        for s in model.rigid_slaves[model.rigid_ptr[b] : model.rigid_ptr[b + 1]]:
            out[int(s)] = int(master)
    return out


def _body_mass(model: Model, master: int) -> float:
    hit = np.flatnonzero(model.rigid_master == master)
    return float(model.rigid_mass[hit[0]]) if hit.size else float(model.mass[master])


class _Rows:
    """e(node, axis) over [q; physical coordinates; u] (module doc), coordinates made as met."""

    def __init__(self, model: Model, base: tuple[int, int] | None):
        self.model = model
        ms = model.modal
        self.modal_nodes = {} if ms is None else {int(n): k for k, n in enumerate(ms.nodes)}
        self.n_modes = 0 if ms is None else ms.n_modes
        self.master = _bodies(model)
        self.base = base
        self.coords: dict[tuple[int, int], int] = {}

    def row(self, i: int, d: int) -> dict | None:
        """The row of node index ``i`` along axis ``d`` (0-2), as {(kind, column): value}
        (kind "q" a mode, "x" a physical coordinate, "u" the base; :meth:`dense` once every
        coordinate is known); None when it is not in this form."""
        model, ms = self.model, self.model.modal
        if i >= model.particle_start:
            return None
        master = self.master.get(i, i)
        if master in self.modal_nodes:
            k = self.modal_nodes[master]
            out = {("q", r): float(v) for r, v in enumerate(ms.shape[k, d])}
            if i != master:
                offset = model.x0[i] - model.x0[master]
                rot = ms.shape[k, 3:6]  # (3, M)
                arm = np.cross(rot.T, offset).T  # (3, M): phi_rot x r0
                out = {key: v + float(arm[d, key[1]]) for key, v in out.items()}
            return out
        if self.base is not None and master == self.base[0] and d == self.base[1]:
            return {("u", 0): 1.0}
        if model.fixed[master, d]:
            return {}
        if i != master and not np.all(model.fixed[master, 3:6]):
            if np.any(model.x0[i] != model.x0[master]):
                return None
        key = (master, d)
        if key not in self.coords:
            self.coords[key] = len(self.coords)
        return {("x", self.coords[key]): 1.0}

    def dense(self, sparse: dict) -> np.ndarray:
        n = self.n_modes + len(self.coords)
        out = np.zeros(n + 1)
        for (kind, j), v in sparse.items():
            out[j if kind == "q" else self.n_modes + j if kind == "x" else n] += v
        return out


def linear_system(
    model: Model,
    node: int,
    dof: int,
    response: tuple[int, int] | None = None,
    *,
    base: bool = False,
) -> LinearSystem | None:
    """The :class:`LinearSystem` of a particle-free ``model`` driven at ``node`` along ``dof``
    (1-3) by a force, or with ``base`` by moving that node, measured at ``response`` (node, dof;
    default the driven DOF), or None when it is not in this form (module doc)."""
    if model.n_particles or dof not in (1, 2, 3):
        return None
    if model.axial_nodes.shape[0] or model.rotational_nodes.shape[0]:
        return None
    response = (node, dof) if response is None else tuple(response)
    if response[1] not in (1, 2, 3):
        return None
    try:
        i_drive, i_out = model.index_of(node), model.index_of(response[0])
    except KeyError:
        return None
    rows = _Rows(model, (i_drive, dof - 1) if base else None)
    if base and rows.master.get(i_drive, i_drive) in rows.modal_nodes:
        return None
    drive, out = rows.row(i_drive, dof - 1), rows.row(i_out, response[1] - 1)
    springs = []
    for (a, b), ks, cs in zip(model.spring_nodes, model.spring_k, model.spring_c):
        for d in range(3):
            if ks[d] == 0.0 and cs[d] == 0.0:
                continue
            ea = rows.row(int(a), d)
            eb = rows.row(int(b), d) if b >= 0 else {}
            if ea is None or eb is None:
                return None
            springs.append((ea, eb, float(ks[d]), float(cs[d])))
    if drive is None or out is None:
        return None
    n = rows.n_modes + len(rows.coords)
    stiffness, damping, mass = (np.zeros((n + 1, n + 1)) for _ in range(3))
    ms = model.modal
    if ms is not None:
        m = rows.n_modes
        stiffness[:m, :m] = np.diag(ms.omega**2)
        damping[:m, :m] = np.diag(2.0 * ms.zeta * ms.omega)
        if ms.coupling.size:
            damping[:m, :m] += ms.coupling
        mass[:m, :m] = np.eye(m)
    for (master, _dof), j in rows.coords.items():
        mass[rows.n_modes + j, rows.n_modes + j] = _body_mass(model, master)
    for ea, eb, k, c in springs:
        r = rows.dense(ea) - rows.dense(eb)
        stiffness += k * np.outer(r, r)
        damping += c * np.outer(r, r)
    system = LinearSystem(stiffness, damping, mass, rows.dense(drive), rows.dense(out), base)
    dyn = stiffness[:n, :n] + 1j * damping[:n, :n] - mass[:n, :n]
    if n == 0 or np.linalg.cond(dyn) > 1e14:
        return None
    if not base and not np.any(system.drive_row[:n]):
        return None
    return system
