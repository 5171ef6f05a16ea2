"""The modal structure of a model (MODAL card): what the solver integrates and ``check`` shows.

Built by x3dpd.model.build_modal; integrated by x3dpd.physics.modal. N modal nodes (deck nodes
with shape values), M modes. Shapes are mass-normalised in the deck's units:
translations [1/sqrt(mass)], rotations [1/(sqrt(mass) length)].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from x3dpd.units import si_size


@dataclass(frozen=True)
class ModalStructure:
    """The modes the solver integrates: those given, coupled with the deck's mass on modal
    nodes when the housing is added (x3dpd.model.build_modal).

    nodes : (N,) int64 node indices of the modal nodes.
    shape : (N, 6, M) coupled mode shapes at each node's 6 DOFs (0 where held).
    omega : (M,) circular frequencies of the coupled modes [rad per time unit].
    zeta : (M,) their modal damping ratios.
    coupling : (M, M) damping that couples the coupled modes (zero diagonal), or (0, 0).
    body : (N,) rigid body whose master the node is, or -1.
    held : (N, 6) bool, DOFs that do not move (no shape value, or fixed by BOUNDARY).
    added_mass : (N, 6, 6) the deck's mass on each node coupled into the modes.
    given_numbers, given_freq, given_zeta : (M,) the modes as given (numbers, cycles per time
        unit, damping ratios); given_shape : (N, 6, M) their shapes.
    housing : "added" | "included"; source : where the modes came from.
    """

    nodes: np.ndarray
    shape: np.ndarray
    omega: np.ndarray
    zeta: np.ndarray
    coupling: np.ndarray
    body: np.ndarray
    held: np.ndarray
    added_mass: np.ndarray
    given_numbers: np.ndarray
    given_freq: np.ndarray
    given_zeta: np.ndarray
    given_shape: np.ndarray
    housing: str = "added"
    source: str = ""

    @property
    def n_modes(self) -> int:
        return int(self.omega.shape[0])

    @property
    def freq(self) -> np.ndarray:
        """Frequencies of the coupled modes [cycles per time unit]."""
        return self.omega / (2.0 * math.pi)

    def shape_at(self, node_index: int, dof: int) -> np.ndarray:
        """(M,) shape values of DOF ``dof`` (0-5) at node index ``node_index`` (zeros when the
        node is not modal)."""
        hit = np.flatnonzero(self.nodes == node_index)
        if hit.size == 0:
            return np.zeros(self.n_modes)
        return self.shape[int(hit[0]), dof].copy()


def unit_factors(source: tuple[str, str, str], target: tuple[str, str, str]):
    """(frequency, translational shape, rotational shape) factors that turn values in the unit
    system ``source`` (length, force, time) into ``target``: frequency [1/T] by T_t/T_s; shapes
    [1/sqrt(mass)] by sqrt(M_t/M_s) and [1/(sqrt(mass) length)] by sqrt(M_t/M_s) L_t/L_s, with
    mass = force time^2 / length."""
    ls, fs, ts = si_size(source)
    lt, ft, tt = si_size(target)
    ms, mt = fs * ts * ts / ls, ft * tt * tt / lt
    root = math.sqrt(mt / ms)
    return tt / ts, root, root * lt / ls
