"""Signals of a run for the test-engineer tools (``x3dpd frf``, ``spectrum``): the drive,
recomputed from the run's force and motion specs, and a node's response, read from its trace.

The trace holds positions and velocities only. The drive is recomputed, not recorded: the trace's
sidecar keeps every built-in USRFRC law the run applied (``usrfrc``: the deck's card and the
command line's) and every prescribed motion (``motion``), and the law kernels are pure functions
of time, so evaluating the same specs at the output times t0 + n ITRAC DT gives the force (or base
acceleration) the step loop applied at those times, bit for bit. A user force file's force is a
function of the state as well and cannot be recomputed; a drive DOF loaded by one is an error.
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from x3dpd.api import TraceData, read_trace
from x3dpd.api.measurements import (
    MIN_SEGMENT,
    RANDOM_DEFAULT_PERIOD,
    central_difference,
    force_table,
    force_values,
    law_count,
    motion_history,
    motion_rows,
    motion_table,
    split_specs,
)
from x3dpd.api.traces import TraceWarning
from x3dpd.errors import InputError

#: Quantities a response can be read as, and their unit in terms of the trace's length unit.
RESPONSE_UNITS = {
    "displacement": "{length}",
    "velocity": "{length}/s",
    "acceleration": "{length}/s^2",
}
_NODE = re.compile(r"node\s*=\s*(\d+)", re.IGNORECASE)
_PERIOD = re.compile(r"\bperiod\s*=\s*([^,\s]+)", re.IGNORECASE)
#: How close to a whole number of output intervals a periodic drive's period must be
#: (relative): the printed output times carry 9 significant digits.
WHOLE_PERIOD_TOLERANCE = 1e-6


@dataclass(frozen=True)
class DriveSignal:
    """The drive at a trace's output times: ``values``, ``kind`` ("force" or "base
    acceleration"), ``unit``, the specs it comes from and notes for the user."""

    values: np.ndarray
    kind: str
    unit: str
    specs: tuple[str, ...]
    notes: tuple[str, ...] = ()


def parse_band(text: str | None, what: str = "--band") -> tuple[float, float] | None:
    """``LO:HI`` [Hz] -> (lo, hi) with 0 <= lo < hi, or None."""
    if text is None:
        return None
    lo, colon, hi = str(text).partition(":")
    try:
        band = float(lo), float(hi)
    except ValueError:
        band = (math.nan, math.nan)
    if not colon or not (0.0 <= band[0] < band[1] < math.inf):
        raise InputError(f"{what} {text!r}: expected LO:HI in Hz with 0 <= LO < HI")
    return band


def read_record(
    path: str, echo: Callable[[str], None], progress: Callable[[str, int, int], None] | None = None
) -> TraceData:
    """The trace at ``path`` for a spectrum or an FRF (``progress(path, bytes_read, size)`` as
    it is read). A file cut after its run ended -- the sidecar says the run is complete but the
    file holds fewer output times, or a row cut short -- is an InputError: the record is short.
    An interrupted run's cut last output time is dropped with a note."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", TraceWarning)
        trace = read_trace(
            path, progress=None if progress is None else (lambda d, t: progress(path, d, t))
        )
    notes = [str(w.message) for w in caught if issubclass(w.category, TraceWarning)]
    blocks = trace.meta.get("blocks")
    held = int(trace.time.size)
    if trace.status == "complete" and (
        trace.dropped_rows or (isinstance(blocks, int) and blocks != held)
    ):
        raise InputError(
            f"{path}: the record is short: the file holds {held} output times"
            + (" and a cut one" if trace.dropped_rows else "")
            + f", but its sidecar says the run wrote {blocks} and completed; the file was "
            "cut or copied in part after the run (copy the whole trace again)"
        )
    for note in notes:
        echo(f"note: {note}")
    return trace


def period_notes(drive: DriveSignal, fs: float) -> list[str]:
    """What is wrong with a periodic (``random:``) drive's period on a record sampled at
    ``fs`` [1/s]: a period that is not a whole number of output intervals (no Welch segment
    then holds whole periods, and the drive's lines cannot fall on frequency bins)."""
    out = []
    for spec in drive.specs:
        if not spec.strip().lower().startswith("random:"):
            continue
        m = _PERIOD.search(spec)
        try:
            period = float(m.group(1)) if m else RANDOM_DEFAULT_PERIOD
        except ValueError:
            continue
        n = period * fs
        if abs(n - round(n)) > WHOLE_PERIOD_TOLERANCE * n:
            out.append(
                f"the drive's period {period:g} s is {n:.2f} output intervals of "
                f"{1.0 / fs:.6g} s, not a whole number: no segment can hold whole periods, so "
                "the periodic drive's lines cannot fall on frequency bins and leak (the exact, "
                "leakage-free FRF of whole periods is lost); trace at an interval that divides "
                "the period (ITRAC x DT)"
            )
    return out


def output_times(trace: TraceData) -> np.ndarray:
    """The trace's output times as the run computed them, t0 + (n ITRAC) DT, when the sidecar
    gives a fixed step and they agree with the printed times; else the printed times."""
    meta = trace.meta
    t = trace.time
    dt, itrac, t0 = meta.get("dt"), meta.get("itrac"), meta.get("t0", 0.0)
    if isinstance(dt, (int, float)) and isinstance(itrac, int) and dt > 0 and itrac > 0:
        n = np.rint((t - t0) / (itrac * dt)).astype(np.int64)
        exact = t0 + (n * itrac) * dt
        if np.all(np.abs(exact - t) <= 1e-8 * np.maximum(np.abs(t), itrac * dt)):
            return exact
    return t


def sampling_rate(trace: TraceData, path: str) -> float:
    """Samples per second of a trace with uniformly spaced output times."""
    t = trace.time
    if t.size < 16:
        raise InputError(f"{path}: {t.size} output times; a spectrum needs many more (at least 16)")
    step = np.diff(t)
    mean = (t[-1] - t[0]) / (t.size - 1)
    if np.max(np.abs(step - mean)) > 1e-6 * mean:
        raise InputError(
            f"{path}: the output times are not uniformly spaced (steps "
            f"{step.min():.6g} .. {step.max():.6g} s)"
        )
    return 1.0 / mean


def check_band(band: tuple[float, float] | None, fs: float, path: str) -> None:
    """A band must lie below the trace's Nyquist frequency fs / 2."""
    if band is not None and band[1] > 0.5 * fs:
        raise InputError(
            f"--band {band[0]:g}:{band[1]:g} Hz reaches above the Nyquist frequency "
            f"{0.5 * fs:.6g} Hz of {path} (one output every {1 / fs:.6g} s); record "
            "the trace more often (ITRAC) or lower the band"
        )


def _node_ids(specs, extra: int) -> np.ndarray:
    ids = {extra}
    for spec in specs:
        ids.update(int(m) for m in _NODE.findall(spec))
    return np.array(sorted(ids), dtype=np.int64)


def drive_history(trace: TraceData, node: int, dof: int, path: str) -> DriveSignal:
    """The drive on ``node`` ``dof`` at the trace's output times (module docstring): a
    prescribed motion's acceleration, else the sum of the built-in force laws on that DOF."""
    meta = trace.meta
    if not meta:
        raise InputError(
            f"{path}: no sidecar ({path}.json): the drive is recomputed from the "
            "run's force and motion specs, which the sidecar records"
        )
    motions = [str(s) for s in meta.get("motion") or []]
    builtin, files = split_specs([str(s) for s in meta.get("usrfrc") or []])
    ids = _node_ids(list(builtin) + motions, node)
    times = output_times(trace)
    units = trace.units
    length, force = units.get("length", "in"), units.get("force", "lbf")
    if motions:
        table = motion_table(motions, ids)
        rows = motion_rows(table)
        hit = [k for k, r in enumerate(rows) if ids[int(r[0])] == node and int(r[1]) == dof - 1]
        if hit:
            acc = motion_history(times, table)[2][:, hit[0]]
            unit = f"{length}/s^2" if dof <= 3 else "rad/s^2"
            return DriveSignal(acc, "base acceleration", unit, (motions[hit[0]],))
    if builtin:
        table = force_table(builtin, ids)
        hit = [
            k
            for k in range(law_count(table))
            if ids[int(table[k, 1])] == node and int(table[k, 2]) == dof - 1
        ]
        if hit:
            values = force_values(times, table)[:, hit].sum(axis=1)
            notes = (
                (
                    f"the run also applied user force file(s) {', '.join(files)}, whose "
                    "force is not part of this drive",
                )
                if files
                else ()
            )
            unit = force if dof <= 3 else f"{force} {length}"
            return DriveSignal(values, "force", unit, tuple(builtin[k] for k in hit), notes)
    applied = [*builtin, *files, *(f"motion {m}" for m in motions)]
    raise InputError(
        f"{path}: no built-in force law or prescribed motion of the run drives node "
        f"{node} dof {dof} (the run applied: {'; '.join(applied) or 'nothing'})"
        + ("; a user force file's force cannot be recomputed" if files else "")
    )


def response_history(
    trace: TraceData, node: int, dof: int, quantity: str, path: str
) -> tuple[np.ndarray, bool]:
    """A node's response along ``dof`` at the trace's output times, and whether it is a central
    difference (whose spectra are then divided by :func:`x3dpd.analysis.frf.difference_gain`):
    the displacement from the first output, the traced velocity, or the acceleration as the
    central difference of the traced velocity (the trace holds no accelerations)."""
    if quantity not in RESPONSE_UNITS:
        raise InputError(f"--quantity {quantity!r}: expected one of {', '.join(RESPONSE_UNITS)}")
    hit = np.flatnonzero(trace.node_ids == node)
    if hit.size == 0:
        ids = trace.node_ids.tolist()
        raise InputError(
            f"{path}: node {node} is not in the trace (it holds node(s) "
            f"{', '.join(map(str, ids[:12]))}{' ...' if len(ids) > 12 else ''})"
        )
    i = int(hit[0])
    if quantity == "displacement":
        if dof > 3:
            raise InputError(
                f"node {node} dof {dof}: the trace holds no rotation angles; read a "
                "rotational DOF as velocity or acceleration"
            )
        x = trace.position[:, i, dof - 1]
        return x - x[0], False
    v = trace.data[:, i, 3 + dof - 1].copy()  # vx vy vz wx wy wz
    if quantity == "velocity":
        return v, False
    return central_difference(v, sampling_rate(trace, path)), True


def response_unit(trace: TraceData, quantity: str, dof: int) -> str:
    if dof > 3:
        return {"velocity": "rad/s", "acceleration": "rad/s^2"}.get(quantity, "rad")
    return RESPONSE_UNITS[quantity].format(length=trace.units.get("length", "in"))


def welch_options(
    fs: float, n: int, *, segment: float | None, nperseg: int | None, overlap: float
) -> tuple[int, int]:
    """``(nperseg, noverlap)`` from ``--segment`` [s] or ``--nperseg`` [samples] (default: the
    length that gives 8 averages at the overlap) and ``--overlap`` (a fraction 0 <= o < 1)."""
    if segment is not None and nperseg is not None:
        raise InputError("give --segment (seconds) or --nperseg (samples), not both")
    if not 0.0 <= overlap < 1.0:
        raise InputError(f"--overlap {overlap:g}: expected a fraction 0 <= overlap < 1")
    if segment is not None:
        if not segment > 0:
            raise InputError(f"--segment {segment:g}: expected a duration > 0 [s]")
        nperseg = int(round(segment * fs))
    elif nperseg is None:
        nperseg = int(n / (1.0 + 7.0 * (1.0 - overlap)))
        if nperseg < MIN_SEGMENT <= n:
            raise InputError(
                f"the record holds {n} samples ({n / fs:.4g} s): 8 Welch averages of it would "
                f"be {nperseg} samples each, and a segment needs at least {MIN_SEGMENT}; give "
                f"--nperseg {MIN_SEGMENT}..{n} (fewer averages), --method fft, or a longer run"
            )
    if nperseg > n:
        raise InputError(
            f"a segment of {nperseg} samples ({nperseg / fs:.4g} s) is longer than "
            f"the record ({n} samples, {n / fs:.4g} s)"
        )
    return nperseg, min(int(round(overlap * nperseg)), nperseg - 1)
