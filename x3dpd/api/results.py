"""What :func:`x3dpd.run` returns: the recorded trace, the energy ledger, the run summary and the
final state to continue from.

``result.trace`` is the same :class:`~x3dpd.io.trace.TraceData` that :func:`x3dpd.read_trace`
returns for a trace file (``time`` (T,), ``node_ids`` (N,), ``position``, ``velocity``,
``spin`` (T, N, 3)); ``result.energy`` the same :class:`~x3dpd.io.energy.EnergyData` as
:func:`x3dpd.io.energy.read_energy` (``columns``, ``data`` (T, 12), ``energy["residual"]``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from x3dpd.io.energy import EnergyData
from x3dpd.io.trace import TraceAxes, TraceData


@dataclass(frozen=True)
class FinalState:
    """The solver state at the end of a run, to continue from (``initial_state=``).

    It holds the positions, velocities, rotations, contact histories (Maxwell terms, friction)
    and the energy ledger, and remembers the deck's key and the time step it belongs to, so a
    run continues only a state of the same scene at the same step. Picklable.
    """

    state: Any  # x3dpd.solver.state.State (copied)
    deck_key: str
    dt: float
    time: float
    checkpoint: dict | None = None  # a step chosen by accuracy: its level (dt is DTMAX)

    def __repr__(self) -> str:
        return f"FinalState(time={self.time!r}, dt={self.dt!r}, step={self.state.step})"


@dataclass(frozen=True)
class Chunk(TraceAxes):
    """The rows one chunk of steps produced, as handed to ``run(stop=...)``.

    ``time`` (k,), ``node_ids`` (N,), ``position`` / ``velocity`` / ``spin`` (k, N, 3), ``energy``
    (k, 12) in :data:`x3dpd.solver.simulation.ENERGY_COLUMNS` order.
    """

    time: np.ndarray
    node_ids: np.ndarray
    data: np.ndarray
    energy: np.ndarray


@dataclass
class RunResult:
    """Everything a run produced.

    Attributes
    ----------
    trace : TraceData or None
        The recorded rows (None with ``keep_trace=False``).
    energy : EnergyData or None
        The energy ledger at the recorded times (None with ``keep_trace=False``).
    summary : dict
        ``status`` ("complete", "stopped", "interrupted" or "unstable"), ``t_start``, ``t_end``
        [s], ``steps`` (this run), ``dt`` [s], ``itrac``, ``wall_s`` (the whole call),
        ``step_wall_s`` (stepping only), ``compile_s``, ``steps_per_s``, ``effects``,
        ``energy_scale`` (the largest of the ledger's terms so far [energy]),
        ``relative_residual`` (the last ledger residual / energy scale, dimensionless: what the
        audit compares with ``energy_tolerance``), ``residual_energy`` (the last ledger residual
        [energy], as ``energy["residual"][-1]``), ``residual`` (= ``relative_residual``, an older
        name), ``energy_tolerance``, ``last_energy``
        (the last ledger row as a dict), ``usrfrc`` (the forces applied), ``code_files`` (the
        USRFRC Python files it executed), ``usrfrc_replaced``
        (the deck's USRFRC specs that ``usrfrc=`` replaced), ``trace_file``, ``energy_file``,
        ``restart_file``, ``dumps``.
    final_state : FinalState
    model : x3dpd.model.model.Model
    """

    trace: TraceData | None
    energy: EnergyData | None
    summary: dict
    final_state: FinalState | None
    model: Any = field(repr=False, default=None)


class Recorder:
    """Accumulates the rows of a run in memory (``keep_trace``)."""

    def __init__(self, node_ids: np.ndarray, columns: tuple[str, ...], keep: bool):
        self.node_ids = np.asarray(node_ids, dtype=np.int64)
        self.columns = tuple(columns)
        self.keep = keep
        self._times: list[np.ndarray] = []
        self._data: list[np.ndarray] = []
        self._energy: list[np.ndarray] = []

    def add(self, times: np.ndarray, data: np.ndarray, energy: np.ndarray) -> None:
        if self.keep and times.shape[0]:
            self._times.append(np.array(times, copy=True))
            self._data.append(np.array(data, copy=True))
            self._energy.append(np.array(energy, copy=True))

    def trace(self, meta: dict) -> TraceData | None:
        if not self.keep:
            return None
        r = self.node_ids.shape[0]
        times = np.concatenate(self._times) if self._times else np.zeros(0)
        data = np.concatenate(self._data) if self._data else np.zeros((0, r, 9))
        return TraceData(
            times=times,
            node_ids=self.node_ids,
            data=np.ascontiguousarray(data),
            path="",
            meta=dict(meta),
        )

    def energy(self) -> EnergyData | None:
        if not self.keep:
            return None
        rows = np.concatenate(self._energy) if self._energy else np.zeros((0, len(self.columns)))
        return EnergyData(self.columns, rows)
