"""The sweep's table: ``sweep.csv``'s columns, rows in order, branches, reading and writing
(x3dpd.design.sweep runs the points; docs/design-guide.md lists the columns)."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

__all__ = [
    "COLUMNS",
    "RESPONSE_COLUMNS",
    "sort_rows",
    "label_branches",
    "write_csv",
    "expand_responses",
    "read_csv",
    "write_atomic",
]

#: sweep.csv columns, in order.
COLUMNS = (
    "config",
    "frequency_hz",
    "drive",
    "drive_quantity",
    "direction",
    "amplitude",
    "amplitude_ci",
    "phase",
    "phase_ci",
    "velocity",
    "acceleration",
    "accelerance",
    "transmissibility",
    "peak",
    "mean",
    "spread",
    "dissipated_per_cycle",
    "dissipated_per_cycle_ci",
    "dissipated_particles_per_cycle",
    "input_work_per_cycle",
    "cycles",
    "kept_cycles",
    "tau_cycles",
    "stopped_by",
    "replicas",
    "converged",
    "extrapolated",
    "irregular",
    "branch",
    "measured_amplitude",
    "change",
    "method",
    "start",
    "t_start",
    "t_end",
    "steps",
    "compile_s",
    "wall_s",
    "response_node",
    "response_dof",
)
#: Columns a measured response (``--response``) has of its own; the rest are its point's.
RESPONSE_COLUMNS = (
    "response_node",
    "response_dof",
    "amplitude",
    "amplitude_ci",
    "phase",
    "phase_ci",
    "velocity",
    "acceleration",
    "accelerance",
    "transmissibility",
    "peak",
    "mean",
    "spread",
    "measured_amplitude",
    "change",
    "converged",
)


def write_atomic(path: Path, data: bytes) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def sort_rows(rows: Sequence[dict]) -> list[dict]:
    """Rows ordered by config (deck first), drive, direction, frequency."""
    order = {"deck": 0, "undamped": 1, "added-mass": 2}
    return sorted(
        rows,
        key=lambda r: (
            order.get(r["config"], 9),
            r["config"],
            r["drive"],
            r["direction"],
            r["frequency_hz"],
        ),
    )


def label_branches(rows: list[dict]) -> None:
    """Say which branch each point is on (``branch`` column).

    Where an up and a down chain of the same config and drive disagree at a frequency by more
    than their tolerance (hysteresis), the larger amplitude is on the ``high`` branch and the
    smaller on the ``low`` one; elsewhere the response is ``single``-valued. Points run from the
    initial state (no direction) or in closed form are ``single``; an irregular point is
    ``irregular`` whatever its neighbours. The two must also differ by more than their
    combined 95 % interval, sqrt(ci_up^2 + ci_down^2): chaos alone makes no branches.
    """
    by = {}
    for r in rows:
        by.setdefault((r["config"], r["drive"], r["frequency_hz"]), {})[r["direction"]] = r
    for group in by.values():
        up, down = group.get("up"), group.get("down")
        for r in group.values():
            r["branch"] = "single"
        if up and down:
            tol = 3.0 * max(abs(up["change"]), abs(down["change"]), 0.01)
            both = math.hypot(up.get("amplitude_ci", 0.0), down.get("amplitude_ci", 0.0))
            if abs(up["amplitude"] - down["amplitude"]) > max(
                tol * max(up["amplitude"], down["amplitude"]), both
            ):
                hi, lo = (up, down) if up["amplitude"] > down["amplitude"] else (down, up)
                hi["branch"], lo["branch"] = "high", "low"
        for r in group.values():
            if r.get("irregular"):
                r["branch"] = "irregular"


def write_csv(path: Path, rows: Sequence[dict]) -> None:
    """sweep.csv: one row per point and measured node, columns :data:`COLUMNS` (full precision,
    repr floats): the driven node's row (``response_node``, ``response_dof`` the drive's), then
    a row per ``--response`` with that node's :data:`RESPONSE_COLUMNS` and the point's others."""
    lines = [",".join(COLUMNS)]
    for r in expand_responses(rows):
        lines.append(",".join(_cell(r.get(c, "")) for c in COLUMNS))
    write_atomic(path, ("\n".join(lines) + "\n").encode())


def expand_responses(rows: Sequence[dict]) -> list[dict]:
    """One row per point and measured node (see :func:`write_csv`)."""
    out = []
    for r in rows:
        point = {k: v for k, v in r.items() if k != "responses"}
        out.append(point)
        out.extend({**point, **m} for m in r.get("responses", ()))
    return out


def _cell(v) -> str:
    if isinstance(v, bool) or isinstance(v, np.bool_):
        return "1" if v else "0"
    if isinstance(v, float):  # np.float64 too: its repr is np.float64(...) on numpy 2
        return repr(float(v))
    return str(v)


def read_csv(path: str | os.PathLike) -> list[dict]:
    """Rows of a sweep.csv, numbers as floats (for plots and comparisons)."""
    text = Path(path).read_text().splitlines()
    head = text[0].split(",")
    out = []
    for line in text[1:]:
        row = {}
        for k, v in zip(head, line.split(",")):
            try:
                row[k] = float(v)
            except ValueError:
                row[k] = v
        out.append(row)
    return out
