"""Trace files: the X3D text format that ``pmov.m`` reads, plus a JSON sidecar.

A trace is plain text, ``;``-separated, without a header: one row per traced node, in the TRACE
card's order, at t = 0 and every ITRAC steps. Each row is::

    time; x; y; z; vx; vy; vz; wx; wy; wz

(time [s], current coordinates, translational and angular velocities), every number written
with ``"% .9e"`` (a sign or a space, 10 significant digits), so rows line up and files diff
cleanly. MATLAB reads it with ``dlmread('trace.txt', ';')`` (report AFRL-VA-WP-TR-2003-3053,
Appendix E), numpy with ``numpy.loadtxt(path, delimiter=';')``.

The R rows written for one output time are a *block*. Beside ``trace.txt`` the writer keeps
``trace.txt.json`` (format ``x3dpd-trace/1``): node ids, units, deck, time step and run status.
See ``docs/trace-format.md``.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import warnings
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any, Self, TextIO

import numpy as np

from x3dpd import __version__
from x3dpd.errors import TraceError, UnstableRunError
from x3dpd.io._streamed import create_new, reopen_at
from x3dpd.io.restart import to_jsonable, write_atomically
from x3dpd.units import trace_units

TRACE_FORMAT = "x3dpd-trace/1"
"""Format tag of the sidecar; :func:`read_trace` refuses sidecars with another tag."""

COLUMNS = ("time", "x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz")
"""Columns of a trace row, in file order."""

DATA_COLUMNS = COLUMNS[1:]
"""Columns of :attr:`TraceData.data` (the row without the time)."""

NUMBER_FORMAT = "% .9e"
ROW_FORMAT = ";".join([NUMBER_FORMAT] * len(COLUMNS)) + "\n"

DEFAULT_UNITS = {"time": "s", "length": "in", "velocity": "in/s", "angular_velocity": "rad/s"}

STATUSES = ("running", "complete", "interrupted", "unstable")

_ROWS_PER_CHUNK = 32768  # rows formatted per pass of write_block (bounds the memory used)


class TraceWarning(UserWarning):
    """A trace was readable but not whole (its last output time was cut off)."""


def _units(units) -> dict[str, str]:
    """Sidecar units from a mapping (merged over :data:`DEFAULT_UNITS`) or from a deck's unit
    system ``(length, force, time)`` (``Model.units``, the UNITS card: x3dpd.units)."""
    if units is None:
        return dict(DEFAULT_UNITS)
    if isinstance(units, Mapping):
        return {**DEFAULT_UNITS, **dict(units)}
    return trace_units(tuple(units))


def sidecar_path(path: str | os.PathLike) -> str:
    """The sidecar of trace ``path``: ``path + ".json"``."""
    return os.fspath(path) + ".json"


def sha256_file(path: str | os.PathLike) -> str:
    """Hex SHA-256 of a file (for the sidecar's ``deck_sha256``)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _write_json(path: str, obj: Mapping[str, Any]) -> None:
    """Write ``obj`` atomically, one top-level key per line (lists stay on their line)."""
    body = ",\n".join(f"  {json.dumps(str(k))}: {json.dumps(v, default=to_jsonable)}"
                      for k, v in obj.items())
    data = ("{\n" + body + "\n}\n").encode("utf-8")
    write_atomically(path, lambda f: f.write(data), sync_dir=False)


def _read_sidecar(path: str) -> dict[str, Any] | None:
    """The sidecar of trace ``path`` as a dict, None when there is none."""
    spath = sidecar_path(path)
    try:
        with open(spath, encoding="utf-8") as f:
            meta = json.load(f)
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as exc:
        raise TraceError(f"{spath}: trace sidecar is not readable JSON ({exc}); move it away "
                         "to read the trace without it") from None
    if not isinstance(meta, dict) or meta.get("format") != TRACE_FORMAT:
        fmt = meta.get("format") if isinstance(meta, dict) else None
        raise TraceError(f"{spath}: sidecar format is {fmt!r}, expected {TRACE_FORMAT!r}")
    ids = meta.get("node_ids")
    if (not isinstance(ids, list) or not ids
            or not all(isinstance(i, int) and not isinstance(i, bool) for i in ids)):
        raise TraceError(f"{spath}: sidecar has no valid 'node_ids' list")
    return meta


# --------------------------------------------------------------------------------------------
# writing


class TraceWriter:
    """Stream a trace file block by block, with its JSON sidecar.

    Use as a context manager. Leaving the ``with`` block normally records status
    ``"complete"``; :class:`KeyboardInterrupt` records ``"interrupted"``,
    :class:`~x3dpd.errors.UnstableRunError` ``"unstable"``, any other exception
    ``"interrupted"``. :meth:`close` takes an explicit status.

    Parameters
    ----------
    path : str or PathLike
        The trace file. Its sidecar is ``path + ".json"``.
    node_ids : (R,) int sequence
        User node ids of the traced nodes, in TRACE order (the row order of every block).
    sidecar : dict, optional
        Run description merged into the sidecar: normally ``deck_path``, ``deck_sha256``
        (see :func:`sha256_file`), ``dt`` [s], ``itrac``, ``effects``; extra keys are kept.
        The keys the writer manages (``format``, ``columns``, ``units``, ``node_ids``,
        ``x3dpd_version``, ``status``, ``blocks``, ``bytes``, ``last_time``) are overridden.
    overwrite : bool
        If ``path`` exists, rename it to ``path + ".bak"`` (and its sidecar to
        ``path + ".bak.json"``), replacing an older backup, instead of refusing.
    append_at : (nbytes, nblocks), optional
        Resume an existing trace: truncate it to ``nbytes`` bytes, which must hold exactly
        ``nblocks`` complete blocks (the values :meth:`tell` and :attr:`blocks_written`
        had when the restart dump was taken), and append. A trace whose sidecar says
        ``"complete"`` is only resumed with ``overwrite=True``, which first copies it to
        ``path + ".bak"``.
    units : dict, optional
        Units recorded in the sidecar, merged over :data:`DEFAULT_UNITS`.

    Raises
    ------
    TraceError
        ``path`` exists (and neither ``overwrite`` nor ``append_at``), cannot be created, or
        cannot be resumed at ``append_at``.
    """

    def __init__(self, path: str | os.PathLike, node_ids: Iterable[int],
                 sidecar: Mapping[str, Any] | None = None, *, overwrite: bool = False,
                 append_at: tuple[int, int] | None = None,
                 units: Mapping[str, str] | None = None):
        self.path = os.fspath(path)
        ids = np.asarray(list(node_ids) if not isinstance(node_ids, np.ndarray) else node_ids)
        if ids.ndim != 1 or ids.size == 0 or not np.issubdtype(ids.dtype, np.integer):
            raise ValueError("node_ids must be a non-empty 1-D sequence of integers")
        self.node_ids = ids.astype(np.int64)
        self.n_nodes = int(ids.size)
        self.status = "running"
        self._closed = False
        self._f = None
        self._blocks = 0
        self._offset = 0
        self._last_time = -np.inf
        self._fmt_cache: dict[int, str] = {}

        self._meta: dict[str, Any] = {
            "deck_path": None, "deck_sha256": None, "dt": None, "itrac": None, "effects": [],
        }
        self._meta.update(dict(sidecar or {}))
        if isinstance(self._meta.get("effects"), (set, frozenset, tuple)):
            self._meta["effects"] = sorted(self._meta["effects"])
        self._meta.update({
            "format": TRACE_FORMAT,
            "columns": list(COLUMNS),
            "units": _units(units),
            "node_ids": self.node_ids.tolist(),
            "x3dpd_version": __version__,
        })

        if append_at is not None:
            self._open_append(append_at, overwrite)
        else:
            self._open_new(overwrite)
        try:
            self._write_sidecar()
        except BaseException:
            self._f.close()
            raise

    # -- opening ------------------------------------------------------------------------------

    def _open_new(self, overwrite: bool) -> None:
        path = self.path
        self._f = create_new(path, overwrite=overwrite, error=TraceError, what="trace file",
                             option="--trace",
                             companions=[(sidecar_path(path), path + ".bak.json")])

    def _open_append(self, append_at: tuple[int, int], overwrite: bool) -> None:
        path = self.path
        nbytes, nblocks = (int(v) for v in append_at)
        if not os.path.isfile(path):
            raise TraceError(f"cannot resume trace {path}: the file does not exist (the restart "
                             f"dump expects {nblocks} output times in it)")
        old = _read_sidecar(path)
        if old is not None and old["node_ids"] != self.node_ids.tolist():
            raise TraceError(f"cannot resume trace {path}: it traces nodes {old['node_ids']}, "
                             f"this run traces {self.node_ids.tolist()}")
        size = os.path.getsize(path)
        # a complete trace is only cut back with overwrite; appending to its end (a finished
        # run extended from its end-of-run dump) loses nothing
        backup = old is not None and old.get("status") == "complete" and nbytes < size
        if backup and not overwrite:
            raise TraceError(f"trace {path} is complete; resuming would cut it at byte "
                             f"{nbytes}. Pass --overwrite to keep a copy in {path}.bak, or "
                             "choose another --trace path")
        if nbytes < 0 or nblocks < 0 or nbytes > size:
            raise TraceError(f"cannot resume trace {path} at byte {nbytes}: the file has only "
                             f"{size} bytes (is it the trace of this restart dump?)")

        def check(f) -> None:
            lines, last = _count_lines(f, nbytes)
            if lines != nblocks * self.n_nodes:
                raise TraceError(
                    f"cannot resume trace {path}: its first {nbytes} bytes hold {lines} complete "
                    f"rows, the restart dump expects {nblocks} x {self.n_nodes} = "
                    f"{nblocks * self.n_nodes} (is it the trace of this restart dump?)")
            if last is not None:
                try:
                    self._last_time = float(last.split(b";", 1)[0])
                except ValueError:
                    raise TraceError(f"cannot resume trace {path}: row {lines} is not a trace "
                                     "row") from None
            if backup:
                try:
                    shutil.copy2(path, path + ".bak")
                    shutil.copy2(sidecar_path(path), path + ".bak.json")
                except OSError as exc:
                    raise TraceError(f"cannot copy {path} to {path}.bak: {exc}") from None

        self._f = reopen_at(path, nbytes, error=TraceError, what="trace", check=check)
        self._offset = nbytes
        self._blocks = nblocks

    # -- writing ------------------------------------------------------------------------------

    @property
    def blocks_written(self) -> int:
        """Number of complete blocks (output times) in the file."""
        return self._blocks

    def tell(self) -> int:
        """Byte offset of the end of the last complete block (store it in restart dumps)."""
        return self._offset

    def _row_format(self, nrows: int) -> str:
        fmt = self._fmt_cache.get(nrows)
        if fmt is None:
            if len(self._fmt_cache) > 4:
                self._fmt_cache.clear()
            fmt = self._fmt_cache[nrows] = ROW_FORMAT * nrows
        return fmt

    def write_block(self, times: Any, data: np.ndarray) -> None:
        """Append k output times of R rows each.

        Parameters
        ----------
        times : (k,) float or float
            Output times [s], strictly increasing and later than any time already written.
        data : (k, R, 9) float, or (R, 9) when ``times`` is a scalar
            ``x y z vx vy vz wx wy wz`` of every traced node, in TRACE order.
        """
        if self._closed:
            raise ValueError(f"trace {self.path} is closed")
        t = np.asarray(times, dtype=np.float64)
        d = np.asarray(data, dtype=np.float64)
        if t.ndim == 0:
            t, d = t[None], d[None]
        k, R = t.shape[0], self.n_nodes
        if t.ndim != 1 or d.shape != (k, R, 9):
            raise ValueError(f"write_block expects times (k,) and data (k, {R}, 9); got "
                             f"{t.shape} and {d.shape}")
        if k == 0:
            return
        if not (t[0] > self._last_time and np.all(np.diff(t) > 0)):
            raise ValueError(f"trace times must increase: got {t.tolist()[:4]}... after "
                             f"{self._last_time}")
        rows = np.empty((k * R, 10), dtype=np.float64)
        rows[:, 0] = np.repeat(t, R)
        rows[:, 1:] = d.reshape(k * R, 9)
        per = max(1, _ROWS_PER_CHUNK // R)  # whole blocks per formatting pass
        for start in range(0, k, per):
            part = rows[start * R:(start + per) * R]
            text = (self._row_format(part.shape[0]) % tuple(part.ravel().tolist()))
            chunk = text.encode("ascii")
            self._f.write(chunk)
            self._offset += len(chunk)
            self._blocks += part.shape[0] // R
            self._last_time = float(part[-1, 0])

    # -- status -------------------------------------------------------------------------------

    def _sidecar(self) -> dict[str, Any]:
        meta = {
            "format": TRACE_FORMAT,
            "status": self.status,
            "blocks": self._blocks,
            "bytes": self._offset,
            "last_time": self._last_time if np.isfinite(self._last_time) else None,
        }
        meta.update((k, v) for k, v in self._meta.items() if k not in meta)
        return meta

    def _write_sidecar(self) -> None:
        try:
            _write_json(sidecar_path(self.path), self._sidecar())
        except OSError as exc:
            raise TraceError(f"cannot write trace sidecar {sidecar_path(self.path)}: "
                             f"{exc}") from None

    def describe(self, **fields: Any) -> None:
        """Add or update run-description fields of the sidecar (written at the next flush or
        close)."""
        self._meta.update(fields)

    def flush(self) -> None:
        """Flush and ``fsync`` the trace, then update the sidecar (blocks, bytes, status)."""
        if self._closed:
            return
        self._f.flush()
        os.fsync(self._f.fileno())
        self._write_sidecar()

    def close(self, status: str | None = None) -> None:
        """Flush, close, and record ``status`` (default: the current one, else "complete")."""
        if self._closed:
            return
        if status is not None:
            if status not in STATUSES:
                raise ValueError(f"status must be one of {STATUSES}, got {status!r}")
            self.status = status
        elif self.status == "running":
            self.status = "complete"
        try:
            self._f.flush()
            os.fsync(self._f.fileno())
        finally:
            self._f.close()
            self._closed = True
        self._write_sidecar()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            status = None
        elif issubclass(exc_type, UnstableRunError):
            status = "unstable"
        else:
            status = "interrupted"
        if exc_type is None:
            self.close(status)
        else:
            try:
                self.close(status)
            except (OSError, TraceError) as err:  # do not mask the original error
                warnings.warn(f"{self.path}: could not close the trace cleanly: {err}",
                              TraceWarning, stacklevel=2)


def _count_lines(f, nbytes: int) -> tuple[int, bytes | None]:
    """Newlines in the first ``nbytes`` of ``f`` and the last full line there (or None)."""
    if nbytes == 0:
        return 0, None
    f.seek(nbytes - 1)
    if f.read(1) != b"\n":
        raise TraceError(f"cannot resume trace {f.name} at byte {nbytes}: that is not the end "
                         "of a row (is it the trace of this restart dump?)")
    f.seek(0)
    count, left, tail = 0, nbytes, b""
    while left:
        chunk = f.read(min(left, 1 << 22))
        if not chunk:
            break
        count += chunk.count(b"\n")
        left -= len(chunk)
        tail = (tail + chunk)[-4096:]
    last = tail[:-1].rsplit(b"\n", 1)[-1]
    return count, last


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
            raise KeyError(f"node {nid} is not in trace {self.path or '<trace>'} (traced: "
                           f"{_abbrev(self.node_ids.tolist())})")
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


class _Lines:
    """Complete lines of a text file for ``numpy.loadtxt``; remembers a cut last line."""

    def __init__(self, f: TextIO):
        self.f = f
        self.count = 0
        self.cut = ""

    def __iter__(self) -> Iterator[str]:
        blank = 0
        for line in self.f:
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
                return TraceError(f"{path}:{lineno}: expected {ncols} ';'-separated numbers "
                                  f"({'; '.join(COLUMNS)}), found {len(fields)}")
            for col, text in enumerate(fields):
                try:
                    float(text)
                except ValueError:
                    return TraceError(f"{path}:{lineno}: column {col + 1} ({COLUMNS[col]}): "
                                      f"{text.strip()!r} is not a number")
    return TraceError(f"{path}: not a trace file")


def read_trace(path: str | os.PathLike, *, node_ids: Iterable[int] | None = None,
               strict: bool = False) -> TraceData:
    """Read a trace file (with its sidecar ``path + ".json"`` when there is one).

    The number R of rows per output time comes from, in this order: ``node_ids``, the
    sidecar's ``node_ids``, or -- for a bare file -- the number of leading rows that share the
    first row's time (then ``node_ids`` are the positions 1..R).

    A last output time with fewer than R rows, or a last line without its newline, is what an
    interrupted write leaves: it is dropped with a :class:`TraceWarning` (``dropped_rows`` says
    how many rows), or raises :class:`~x3dpd.errors.TraceError` when ``strict``.

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
            lines = _Lines(f)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)  # "input contained no data"
                rows = np.loadtxt(lines, delimiter=";", comments=None, ndmin=2,
                                  dtype=np.float64)
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
            raise TraceError(f"{spath}: the trace is empty and has no sidecar; cannot tell how "
                             "many nodes it traces")
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
        where = (f"t = {rows[k * R, 0]:.9e}" if dropped else "the last output time")
        msg = (f"{spath}: the last output time ({where}) is incomplete ({dropped} of {R} rows"
               f"{' and a line cut short' if cut else ''}); the run was probably interrupted "
               "while writing")
        if strict:
            raise TraceError(msg)
        warnings.warn(msg + f"; dropped {total} row(s)", TraceWarning, stacklevel=2)
    blocks = rows[: k * R].reshape(k, R, len(COLUMNS))
    times = blocks[:, 0, 0].copy()

    same = blocks[:, :, 0] == times[:, None]
    if not same.all():
        b, r = np.argwhere(~same)[0]
        src = "the sidecar" if meta and node_ids is None else (
            "node_ids" if node_ids is not None else "the first output time")
        raise TraceError(f"{spath}:{b * R + r + 1}: time {blocks[b, r, 0]:.9e} differs from "
                         f"{times[b]:.9e} on line {b * R + 1}; each output time should have "
                         f"{R} rows (from {src})")
    if k > 1:
        bad = np.flatnonzero(~(np.diff(times) > 0))
        if bad.size:
            b = int(bad[0]) + 1
            raise TraceError(f"{spath}:{b * R + 1}: time {times[b]:.9e} does not come after "
                             f"{times[b - 1]:.9e}")
    if meta.get("status") == "complete" and meta.get("blocks") not in (None, k):
        warnings.warn(f"{spath}: the sidecar records a complete run of {meta['blocks']} output "
                      f"times but the file holds {k}", TraceWarning, stacklevel=2)
    return TraceData(times=times, node_ids=ids, data=np.ascontiguousarray(blocks[:, :, 1:]),
                     path=spath, meta=meta, node_ids_known=known,
                     dropped_rows=dropped + (1 if cut else 0))
