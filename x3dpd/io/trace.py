"""Trace files: reading them back (:func:`read_trace`, :class:`TraceData`).

The format -- the X3D text rows ``pmov.m`` reads plus a JSON sidecar -- is described in
:mod:`x3dpd.io.trace_format` and docs/trace-format.md; :class:`TraceWriter`
(:mod:`x3dpd.io.trace_writer`) writes it. Both modules' public names are re-exported here, the
one place callers import trace things from.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from typing import TextIO

import numpy as np

from x3dpd.errors import TraceError
from x3dpd.io.trace_format import (
    COLUMNS,
    DATA_COLUMNS,
    DEFAULT_UNITS,
    NUMBER_FORMAT,
    ROW_FORMAT,
    STATUSES,
    TRACE_FORMAT,
    TraceWarning,
    _read_sidecar,
    sha256_file,
    sidecar_path,
)
from x3dpd.io.trace_writer import TraceWriter

#: Reading lives here; the format's names and the writer are re-exported from their modules.
__all__ = [
    "COLUMNS",
    "DATA_COLUMNS",
    "DEFAULT_UNITS",
    "NUMBER_FORMAT",
    "ROW_FORMAT",
    "STATUSES",
    "TRACE_FORMAT",
    "TraceAxes",
    "TraceData",
    "TraceWarning",
    "TraceWriter",
    "read_trace",
    "sha256_file",
    "sidecar_path",
]


# --------------------------------------------------------------------------------------------
# reading


class TraceAxes:
    """Named views of a ``data`` array of trace rows, (T, N, 9): ``x y z vx vy vz wx wy wz``."""

    data: np.ndarray

    @property
    def position(self) -> np.ndarray:
        """Coordinates ``x y z`` [length], (T, N, 3) (a view of ``data``)."""
        return self.data[:, :, 0:3]

    @property
    def velocity(self) -> np.ndarray:
        """Velocities ``vx vy vz`` [length/s], (T, N, 3) (a view of ``data``)."""
        return self.data[:, :, 3:6]

    @property
    def spin(self) -> np.ndarray:
        """Angular velocities ``wx wy wz`` [rad/s], (T, N, 3) (a view of ``data``)."""
        return self.data[:, :, 6:9]


@dataclass(frozen=True, eq=False)
class TraceData(TraceAxes):
    """A trace in memory.

    Attributes
    ----------
    times : (k,) float64
        Output times [s].
    node_ids : (R,) int64
        Traced user node ids in row order. Without a sidecar the ids are unknown and these are
        the row positions 1..R (``node_ids_known`` is False).
    data : (k, R, 9) float64
        ``x y z vx vy vz wx wy wz`` per time and node.
    columns : tuple of str
        Names of ``data``'s last axis (:data:`DATA_COLUMNS`).
    path : str
    meta : dict
        The sidecar ({} when there was none).
    node_ids_known : bool
    dropped_rows : int
        Rows of a cut-off last block that were dropped (0 for a whole trace).
    """

    times: np.ndarray
    node_ids: np.ndarray
    data: np.ndarray
    columns: tuple[str, ...] = DATA_COLUMNS
    path: str = ""
    meta: dict = field(default_factory=dict)
    node_ids_known: bool = True
    dropped_rows: int = 0

    @property
    def units(self) -> dict[str, str]:
        """Units from the sidecar, else :data:`DEFAULT_UNITS`."""
        return dict(self.meta.get("units") or DEFAULT_UNITS)

    @property
    def status(self) -> str | None:
        """Run status from the sidecar (None without one)."""
        return self.meta.get("status")

    @property
    def time(self) -> np.ndarray:
        """Output times [s], (T,) (the same array as ``times``)."""
        return self.times

    def index(self, nid: int) -> int:
        """Row position of node ``nid`` (its first occurrence); KeyError if not traced."""
        hits = np.flatnonzero(self.node_ids == nid)
        if hits.size == 0:
            raise KeyError(
                f"node {nid} is not in trace {self.path or '<trace>'} (traced: "
                f"{_abbrev(self.node_ids.tolist())})"
            )
        return int(hits[0])

    def node(self, nid: int) -> np.ndarray:
        """History of node ``nid``: (k, 9) array of ``x y z vx vy vz wx wy wz``."""
        return self.data[:, self.index(nid), :]

    def column(self, name: str) -> np.ndarray:
        """One column for all nodes: (k, R) array (``"time"`` gives ``times``, shape (k,))."""
        if name == "time":
            return self.times
        return self.data[:, :, self.columns.index(name)]


def _abbrev(items: list, n: int = 8) -> str:
    return ", ".join(map(str, items[:n])) + (", ..." if len(items) > n else "")


#: Lines read between two calls of read_trace's ``progress``.
PROGRESS_LINES = 1 << 15


class _Lines:
    """Complete lines of a text file for ``numpy.loadtxt``; remembers a cut last line and,
    with ``progress``, reports the bytes read (latin-1: one byte a character) every
    :data:`PROGRESS_LINES` lines."""

    def __init__(self, f: TextIO, progress: Callable[[int, int], None] | None = None):
        self.f = f
        self.count = 0
        self.cut = ""
        self.progress = progress
        self.total = os.fstat(f.fileno()).st_size if progress is not None else 0

    def __iter__(self) -> Iterator[str]:
        blank = 0
        done = 0
        for line in self.f:
            if self.progress is not None:
                done += len(line)
                if self.count % PROGRESS_LINES == 0:
                    self.progress(done, self.total)
            if not line.endswith("\n"):
                self.cut = line
                return
            if len(line) <= 2 and not line.strip():
                blank += 1
                continue
            if blank:
                raise TraceError(f"{self.f.name}:{self.count + 1}: blank line inside the trace")
            self.count += 1
            yield line


def _locate_error(path: str, ncols: int = len(COLUMNS)) -> TraceError:
    """Re-scan ``path`` slowly to name the first line numpy could not read."""
    with open(path, encoding="latin-1", newline="") as f:
        for lineno, line in enumerate(f, 1):
            if not line.endswith("\n") or not line.strip():
                continue
            fields = line.rstrip("\r\n").split(";")
            if len(fields) != ncols:
                return TraceError(
                    f"{path}:{lineno}: expected {ncols} ';'-separated numbers "
                    f"({'; '.join(COLUMNS)}), found {len(fields)}"
                )
            for col, text in enumerate(fields):
                try:
                    float(text)
                except ValueError:
                    return TraceError(
                        f"{path}:{lineno}: column {col + 1} ({COLUMNS[col]}): "
                        f"{text.strip()!r} is not a number"
                    )
    return TraceError(f"{path}: not a trace file")


# Over 80 lines: one reader: header, rows and sidecar checked together.
def read_trace(
    path: str | os.PathLike,
    *,
    node_ids: Iterable[int] | None = None,
    strict: bool = False,
    progress: Callable[[int, int], None] | None = None,
) -> TraceData:
    """Read a trace file (with its sidecar ``path + ".json"`` when there is one).

    The number R of rows per output time comes from, in this order: ``node_ids``, the
    sidecar's ``node_ids``, or -- for a bare file -- the number of leading rows that share the
    first row's time (then ``node_ids`` are the positions 1..R).

    A last output time with fewer than R rows, or a last line without its newline, is what an
    interrupted write leaves: it is dropped with a :class:`TraceWarning` (``dropped_rows`` says
    how many rows), or raises :class:`~x3dpd.errors.TraceError` when ``strict``.

    ``progress(bytes_read, file_size)`` is called as the rows are read (every
    :data:`PROGRESS_LINES` lines) and once at the end, for a progress line over a big file.

    Raises
    ------
    TraceError
        Missing file; a line that is not 10 ``;``-separated numbers (with its line number);
        rows of one block with different times; times that do not increase; a bad sidecar.
    """
    spath = os.fspath(path)
    if not os.path.isfile(spath):
        raise TraceError(f"trace file {spath} does not exist")
    meta = _read_sidecar(spath) or {}
    known = True
    ids = None
    if node_ids is not None:
        ids = np.asarray(list(node_ids), dtype=np.int64)
    elif meta:
        ids = np.asarray(meta["node_ids"], dtype=np.int64)

    lines = None
    try:
        with open(spath, encoding="latin-1", newline="") as f:
            lines = _Lines(f, progress)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)  # "input contained no data"
                rows = np.loadtxt(lines, delimiter=";", comments=None, ndmin=2, dtype=np.float64)
            if progress is not None:
                progress(lines.total, lines.total)
    except ValueError:
        raise _locate_error(spath) from None
    except OSError as exc:
        raise TraceError(f"cannot read trace file {spath}: {exc}") from None
    if rows.shape[0] and rows.shape[1] != len(COLUMNS):
        raise _locate_error(spath)
    if rows.shape[0] == 0:
        rows = np.zeros((0, len(COLUMNS)))
    cut = lines.cut

    if ids is None:
        known = False
        if rows.shape[0] == 0:
            raise TraceError(
                f"{spath}: the trace is empty and has no sidecar; cannot tell how "
                "many nodes it traces"
            )
        R = int(np.argmax(rows[:, 0] != rows[0, 0])) or rows.shape[0]
        ids = np.arange(1, R + 1, dtype=np.int64)
    R = int(ids.size)
    if R == 0:
        raise TraceError(f"{spath}: no traced nodes")

    n = rows.shape[0]
    dropped = n % R
    k = n // R
    if dropped or cut:
        total = dropped + (1 if cut else 0)
        where = f"t = {rows[k * R, 0]:.9e}" if dropped else "the last output time"
        msg = (
            f"{spath}: the last output time ({where}) is incomplete ({dropped} of {R} rows"
            f"{' and a line cut short' if cut else ''}); the run was probably interrupted "
            "while writing"
        )
        if strict:
            raise TraceError(msg)
        warnings.warn(msg + f"; dropped {total} row(s)", TraceWarning, stacklevel=2)
    blocks = rows[: k * R].reshape(k, R, len(COLUMNS))
    times = blocks[:, 0, 0].copy()

    same = blocks[:, :, 0] == times[:, None]
    if not same.all():
        b, r = np.argwhere(~same)[0]
        src = (
            "the sidecar"
            if meta and node_ids is None
            else ("node_ids" if node_ids is not None else "the first output time")
        )
        raise TraceError(
            f"{spath}:{b * R + r + 1}: time {blocks[b, r, 0]:.9e} differs from "
            f"{times[b]:.9e} on line {b * R + 1}; each output time should have "
            f"{R} rows (from {src})"
        )
    if k > 1:
        bad = np.flatnonzero(~(np.diff(times) > 0))
        if bad.size:
            b = int(bad[0]) + 1
            raise TraceError(
                f"{spath}:{b * R + 1}: time {times[b]:.9e} does not come after {times[b - 1]:.9e}"
            )
    if meta.get("status") == "complete" and meta.get("blocks") not in (None, k):
        warnings.warn(
            f"{spath}: the sidecar records a complete run of {meta['blocks']} output "
            f"times but the file holds {k}",
            TraceWarning,
            stacklevel=2,
        )
    return TraceData(
        times=times,
        node_ids=ids,
        data=np.ascontiguousarray(blocks[:, :, 1:]),
        path=spath,
        meta=meta,
        node_ids_known=known,
        dropped_rows=dropped + (1 if cut else 0),
    )
