"""Writing trace files (x3dpd.io.trace_format): :class:`TraceWriter` appends blocks of rows,
keeps the sidecar's status, and resumes a trace at a restart dump's byte offset."""

from __future__ import annotations

import os
import shutil
import warnings
from collections.abc import Iterable, Mapping
from typing import Any, Self

import numpy as np

from x3dpd import __version__
from x3dpd.errors import TraceError, UnstableRunError
from x3dpd.io._streamed import create_new, reopen_at
from x3dpd.io.trace_format import (
    COLUMNS,
    ROW_FORMAT,
    STATUSES,
    TRACE_FORMAT,
    TraceWarning,
    _read_sidecar,
    _units,
    _write_json,
    sidecar_path,
)

_ROWS_PER_CHUNK = 32768  # rows formatted per pass of write_block (bounds the memory used)


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

    def __init__(
        self,
        path: str | os.PathLike,
        node_ids: Iterable[int],
        sidecar: Mapping[str, Any] | None = None,
        *,
        overwrite: bool = False,
        append_at: tuple[int, int] | None = None,
        units: Mapping[str, str] | None = None,
    ):
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
            "deck_path": None,
            "deck_sha256": None,
            "dt": None,
            "itrac": None,
            "effects": [],
        }
        self._meta.update(dict(sidecar or {}))
        if isinstance(self._meta.get("effects"), (set, frozenset, tuple)):
            self._meta["effects"] = sorted(self._meta["effects"])
        self._meta.update(
            {
                "format": TRACE_FORMAT,
                "columns": list(COLUMNS),
                "units": _units(units),
                "node_ids": self.node_ids.tolist(),
                "x3dpd_version": __version__,
            }
        )

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
        self._f = create_new(
            path,
            overwrite=overwrite,
            error=TraceError,
            what="trace file",
            option="--trace",
            companions=[(sidecar_path(path), path + ".bak.json")],
        )

    def _open_append(self, append_at: tuple[int, int], overwrite: bool) -> None:
        path = self.path
        nbytes, nblocks = (int(v) for v in append_at)
        if not os.path.isfile(path):
            raise TraceError(
                f"cannot resume trace {path}: the file does not exist (the restart "
                f"dump expects {nblocks} output times in it)"
            )
        old = _read_sidecar(path)
        if old is not None and old["node_ids"] != self.node_ids.tolist():
            raise TraceError(
                f"cannot resume trace {path}: it traces nodes {old['node_ids']}, "
                f"this run traces {self.node_ids.tolist()}"
            )
        size = os.path.getsize(path)
        # a complete trace is only cut back with overwrite; appending to its end (a finished
        # run extended from its end-of-run dump) loses nothing
        backup = old is not None and old.get("status") == "complete" and nbytes < size
        if backup and not overwrite:
            raise TraceError(
                f"trace {path} is complete; resuming would cut it at byte "
                f"{nbytes}. Pass --overwrite to keep a copy in {path}.bak, or "
                "choose another --trace path"
            )
        if nbytes < 0 or nblocks < 0 or nbytes > size:
            raise TraceError(
                f"cannot resume trace {path} at byte {nbytes}: the file has only "
                f"{size} bytes (is it the trace of this restart dump?)"
            )

        def check(f) -> None:
            lines, last = _count_lines(f, nbytes)
            if lines != nblocks * self.n_nodes:
                raise TraceError(
                    f"cannot resume trace {path}: its first {nbytes} bytes hold {lines} complete "
                    f"rows, the restart dump expects {nblocks} x {self.n_nodes} = "
                    f"{nblocks * self.n_nodes} (is it the trace of this restart dump?)"
                )
            if last is not None:
                try:
                    self._last_time = float(last.split(b";", 1)[0])
                except ValueError:
                    raise TraceError(
                        f"cannot resume trace {path}: row {lines} is not a trace row"
                    ) from None
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
            raise ValueError(
                f"write_block expects times (k,) and data (k, {R}, 9); got {t.shape} and {d.shape}"
            )
        if k == 0:
            return
        if not (t[0] > self._last_time and np.all(np.diff(t) > 0)):
            raise ValueError(
                f"trace times must increase: got {t.tolist()[:4]}... after {self._last_time}"
            )
        rows = np.empty((k * R, 10), dtype=np.float64)
        rows[:, 0] = np.repeat(t, R)
        rows[:, 1:] = d.reshape(k * R, 9)
        per = max(1, _ROWS_PER_CHUNK // R)  # whole blocks per formatting pass
        for start in range(0, k, per):
            part = rows[start * R : (start + per) * R]
            text = self._row_format(part.shape[0]) % tuple(part.ravel().tolist())
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
            raise TraceError(
                f"cannot write trace sidecar {sidecar_path(self.path)}: {exc}"
            ) from None

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
                warnings.warn(
                    f"{self.path}: could not close the trace cleanly: {err}",
                    TraceWarning,
                    stacklevel=2,
                )


def _count_lines(f, nbytes: int) -> tuple[int, bytes | None]:
    """Newlines in the first ``nbytes`` of ``f`` and the last full line there (or None)."""
    if nbytes == 0:
        return 0, None
    f.seek(nbytes - 1)
    if f.read(1) != b"\n":
        raise TraceError(
            f"cannot resume trace {f.name} at byte {nbytes}: that is not the end "
            "of a row (is it the trace of this restart dump?)"
        )
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
