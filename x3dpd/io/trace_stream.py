"""Read a trace block by block, for tools that walk a whole run (movies, exports, plots).

:func:`x3dpd.io.trace.read_trace` holds a trace in memory; a 15 s run of a 512-particle deck is
over a gigabyte of text. :func:`iter_blocks` streams it instead: one output time at a time,
optionally every ``every``-th one, parsing only the blocks it yields. :func:`trace_info` gives
what the sidecar says about the run (node ids, deck, units) without reading the trace.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np

from x3dpd.errors import TraceError
from x3dpd.io.trace import COLUMNS, DEFAULT_UNITS, _read_sidecar


@dataclass(frozen=True)
class TraceInfo:
    """What a trace's sidecar records (``meta`` holds all of it)."""

    path: str
    node_ids: np.ndarray
    deck_path: str | None
    deck_sha256: str | None
    units: dict
    meta: dict = field(default_factory=dict)


def trace_info(path: str | os.PathLike) -> TraceInfo:
    """The sidecar of trace ``path``; TraceError when the trace or its sidecar is missing."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise TraceError(f"{path}: no such trace file")
    meta = _read_sidecar(path)
    if meta is None:
        raise TraceError(
            f"{path}: no sidecar {path}.json; this command needs the traced node "
            f"ids and the deck it records"
        )
    return TraceInfo(
        path,
        np.asarray(meta["node_ids"], dtype=np.int64),
        meta.get("deck_path"),
        meta.get("deck_sha256"),
        dict(meta.get("units") or DEFAULT_UNITS),
        meta,
    )


def iter_blocks(
    path: str | os.PathLike,
    n_rows: int,
    *,
    every: int = 1,
    t_from: float = -np.inf,
    t_to: float = np.inf,
) -> Iterator[tuple[float, np.ndarray]]:
    """Yield ``(time, data)`` for every ``every``-th block with ``t_from <= time <= t_to``.

    ``data`` is ``(n_rows, 9)``: ``x y z vx vy vz wx wy wz`` per traced node. A cut-off last
    block (a killed run) is left out. Raises TraceError with ``FILE:LINE`` on a malformed row.
    """
    if every < 1:
        raise ValueError("every must be >= 1")
    ncols = len(COLUMNS)
    path = os.fspath(path)
    with open(path, "rb") as f:
        k = 0
        line_no = 0
        while True:
            lines = []
            for _ in range(n_rows):
                line = f.readline()
                if not line.endswith(b"\n"):
                    return
                lines.append(line)
            line_no += n_rows
            if k % every == 0:
                t = _time_of(lines[0], path, line_no - n_rows + 1)
                if t > t_to:
                    return
                if t >= t_from:
                    try:
                        rows = np.array([[float(v) for v in ln.split(b";")] for ln in lines])
                    except ValueError:
                        rows = None
                    if rows is None or rows.shape != (n_rows, ncols):
                        raise TraceError(
                            f"{path}:{line_no - n_rows + 1}: expected {n_rows} rows "
                            f"of {ncols} ';'-separated numbers in this block"
                        )
                    yield float(rows[0, 0]), rows[:, 1:]
            k += 1


def _time_of(line: bytes, path: str, line_no: int) -> float:
    try:
        return float(line.split(b";", 1)[0])
    except ValueError:
        raise TraceError(f"{path}:{line_no}: expected a time in the first field") from None
