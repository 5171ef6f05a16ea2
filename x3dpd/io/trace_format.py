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
from collections.abc import Mapping
from typing import Any

from x3dpd.errors import TraceError
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
    body = ",\n".join(
        f"  {json.dumps(str(k))}: {json.dumps(v, default=to_jsonable)}" for k, v in obj.items()
    )
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
        raise TraceError(
            f"{spath}: trace sidecar is not readable JSON ({exc}); move it away "
            "to read the trace without it"
        ) from None
    if not isinstance(meta, dict) or meta.get("format") != TRACE_FORMAT:
        fmt = meta.get("format") if isinstance(meta, dict) else None
        raise TraceError(f"{spath}: sidecar format is {fmt!r}, expected {TRACE_FORMAT!r}")
    ids = meta.get("node_ids")
    if (
        not isinstance(ids, list)
        or not ids
        or not all(isinstance(i, int) and not isinstance(i, bool) for i in ids)
    ):
        raise TraceError(f"{spath}: sidecar has no valid 'node_ids' list")
    return meta
