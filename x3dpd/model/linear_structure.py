"""Linear structures in closed form: a spring-mounted body (SDOF) or a modal structure.

Any vibration textbook (report Section 8.2's model, Figure 43): a body of mass m on springs and
dashpots k, c to ground, driven by F sin(w t), responds in the steady state with

    X = F / sqrt((k - m w^2)^2 + (c w)^2),   phi = -atan2(c w, k - m w^2);

a modal structure (MODAL card) with its receptance from the modes
(x3dpd.physics.modal.receptance). :func:`linear_sdof` and :func:`linear_modal` recognise them in
a model; the design baselines (x3dpd.design.baselines) and the rules of thumb of ``x3dpd
check`` (x3dpd.model.rules_of_thumb) use them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from x3dpd.model.model import Model
from x3dpd.physics.modal import receptance


@dataclass(frozen=True)
class Sdof:
    """A linear SDOF structure: mass m, stiffness k [force/length], damping c [force s/length]."""

    m: float
    k: float
    c: float

    def receptance(self, omega: float) -> complex:
        """X/F = 1 / (k - m w^2 + i c w) [length/force]."""
        return 1.0 / complex(self.k - self.m * omega**2, self.c * omega)

    def response(self, drive: float, omega: float) -> tuple[float, float]:
        """Steady-state amplitude X [length] and phase phi [rad] under drive sin(omega t)."""
        re, im = self.k - self.m * omega**2, self.c * omega
        return drive / math.hypot(re, im), -math.atan2(im, re)

    def dissipated_per_cycle(self, amplitude: float, omega: float) -> float:
        """Energy the dashpot takes per cycle, pi c w X^2 [force length]."""
        return math.pi * self.c * omega * amplitude**2


@dataclass(frozen=True)
class ModalLinear:
    """A linear structure given by its modes, driven at one DOF (shape values ``phi`` (M,) of
    the coupled modes there; x3dpd.model.modal_structure) and measured there or, with
    ``phi_out``, at another."""

    omega: np.ndarray
    zeta: np.ndarray
    coupling: np.ndarray
    phi: np.ndarray
    phi_out: np.ndarray | None = None

    def receptance(self, omega: float, at_drive: bool = False) -> complex:
        """X/F [length/force] at the measured DOF (``at_drive``: at the driven one)."""
        out = self.phi if (at_drive or self.phi_out is None) else self.phi_out
        return complex(
            receptance(
                omega / (2.0 * math.pi), self.omega, self.zeta, out, self.phi, self.coupling
            )[0]
        )

    def measured_at(self, phi_out: np.ndarray) -> ModalLinear:
        """The same structure measured where the shape values are ``phi_out``."""
        return ModalLinear(self.omega, self.zeta, self.coupling, self.phi, phi_out)

    def response(self, drive: float, omega: float) -> tuple[float, float]:
        """Steady-state amplitude X [length] and phase phi [rad] under drive sin(omega t)."""
        h = self.receptance(omega)
        return abs(drive * h), math.atan2(h.imag, h.real)

    def dissipated_per_cycle(self, amplitude: float, omega: float) -> float:
        """Energy the modal damping takes per cycle = the drive's work, pi F X sin(-phi) =
        pi X^2 (-Im H) / |H|^2 [force length]."""
        h = self.receptance(omega, at_drive=True)
        return math.pi * amplitude**2 * (-h.imag) / abs(h) ** 2

    def modal_amplitudes(self, drive: float, omega: float) -> np.ndarray:
        """(M,) complex modal amplitudes Q under drive sin(omega t) (u = Im(phi.Q e^{i omega
        t}))."""
        damping = np.diag(2.0 * self.zeta * self.omega)
        if self.coupling.size:
            damping = damping + self.coupling
        dyn = np.diag(self.omega**2 - omega * omega).astype(complex) + 1j * omega * damping
        return np.linalg.solve(dyn, drive * self.phi.astype(complex))


def rigid_body(model: Model, i: int) -> tuple[set[int], float, int]:
    """(node indices, mass, master index) of the body node index ``i`` belongs to: the rigid
    body it is master or slave of, else the node alone."""
    for b, master in enumerate(model.rigid_master):
        slaves = model.rigid_slaves[model.rigid_ptr[b] : model.rigid_ptr[b + 1]]
        if master == i or i in slaves:
            return {int(master)} | set(slaves.tolist()), float(model.rigid_mass[b]), int(master)
    return {i}, float(model.mass[i]), i


def _axis_springs_node(model: Model, node: int) -> int | None:
    """Index of ``node`` in a model whose elements all act along the global axes (no axial or
    rotational element, MATID types 2 and 3), else None (or when there is no such node)."""
    if model.axial_nodes.shape[0] or model.rotational_nodes.shape[0]:
        return None
    try:
        return model.index_of(node)
    except KeyError:
        return None


def linear_modal(
    model: Model, node: int, dof: int, *, ignore_particles: bool = False
) -> ModalLinear | None:
    """The modal structure of a particle-free model whose ``node`` (a modal node) is driven
    along ``dof`` (1-6), or None: no modal structure, particles (unless ``ignore_particles``:
    then the structure without them), or springs and dashpots (they are not in the modes)."""
    ms = model.modal
    if ms is None or (model.n_particles and not ignore_particles) or dof not in range(1, 7):
        return None
    if np.any(model.spring_k != 0.0) or np.any(model.spring_c != 0.0):
        return None
    i = _axis_springs_node(model, node)
    if i is None or i not in set(ms.nodes.tolist()):
        return None
    return ModalLinear(ms.omega, ms.zeta, ms.coupling, ms.shape_at(i, dof - 1))


def linear_sdof(
    model: Model, node: int, dof: int, *, ignore_particles: bool = False
) -> Sdof | None:
    """The closed-form SDOF of a particle-free model driven at ``node`` along ``dof``, or None.

    None unless: no particles; ``dof`` is a translation (1-3); the driven node's body (the node,
    or the rigid body it is master of) is free along ``dof`` and fixed in every other DOF; every
    other node is fixed along ``dof``; every spring joins the body to ground along the global
    axes (MATID type 1: an axial or rotational element, types 2 and 3, is not in this form).
    ``ignore_particles``: the structure of a model with particles, without them (their nodes
    have no springs; their mass is not counted).
    """
    if (model.n_particles and not ignore_particles) or dof not in (1, 2, 3):
        return None
    i = _axis_springs_node(model, node)
    if i is None:
        return None
    d = dof - 1
    body = {i}
    mass = float(model.mass[i])
    for b, master in enumerate(model.rigid_master):
        if master == i:
            body |= set(model.rigid_slaves[model.rigid_ptr[b] : model.rigid_ptr[b + 1]].tolist())
            mass = float(model.rigid_mass[b])
        elif i in model.rigid_slaves[model.rigid_ptr[b] : model.rigid_ptr[b + 1]]:
            return None
    free = ~model.fixed[i]
    if not free[d] or np.count_nonzero(free) != 1:
        return None
    others = [j for j in range(model.particle_start) if j not in body]
    if others and not np.all(model.fixed[others, d]):
        return None
    k = c = 0.0
    for (a, b), ks, cs in zip(model.spring_nodes, model.spring_k, model.spring_c):
        if b != -1 or a not in body:
            return None
        k += float(ks[d])
        c += float(cs[d])
    return Sdof(m=mass, k=k, c=c) if mass > 0 and k > 0 else None
