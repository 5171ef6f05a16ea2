"""The CSV mode file: one row per node and component, one column per mode.

Layout (``docs/deck-reference.md``, "Mode files")::

    # comment lines start with #; blank lines are skipped
    units,m,N,s                       optional: LENGTH FORCE TIME (x3dpd.units names)
    freq_hz,,12.5,80.1,220.4          required: natural frequency of each mode [Hz]
    damping,,0.01,0.01,0.02           optional: modal damping ratio of each mode
    modal_mass,,1,1,1                 optional: generalized mass of each mode
    node,dof,1,2,3                    required: the table's header; then the mode numbers
    101,x,0.0123,-0.0456,0.0789       one row per node and component (1-6 or x y z rx ry rz)
    101,rz,0.0012,0.0031,-0.0050

The per-mode rows (freq_hz, damping, modal_mass) come before the header; their second cell may
be left empty so that their values stand under the mode columns. An empty value cell means the
file gives no value there (NaN); a node and component without a row likewise.
"""

from __future__ import annotations

import csv
import io

import numpy as np

from x3dpd._files import write_atomically
from x3dpd.errors import ModeFileError
from x3dpd.deck.modes.modeset import DOF_NAMES, ModeSet, parse_dof, sorted_mode_set
from x3dpd.units import parse_units

_PER_MODE = ("freq_hz", "damping", "modal_mass")
_KEYWORDS = ("units",) + _PER_MODE


# Over 80 lines: one CSV reader whose every check names its line.
def read_modes_csv(path) -> ModeSet:
    """Read a CSV mode file; every problem is a ModeFileError ``FILE:LINE: message``."""
    rows = list(_rows(path))
    header_at = next(
        (i for i, (_, cells) in enumerate(rows) if cells and cells[0].lower() == "node"), None
    )
    if header_at is None:
        raise ModeFileError(
            path,
            "no 'node,dof,MODE,...' header row; expected one (after the "
            "freq_hz row) naming the mode of each column",
        )
    line, header = rows[header_at]
    if len(header) < 2 or header[1].lower() != "dof":
        raise ModeFileError(
            path, f"header row reads {','.join(header)!r}; expected node,dof,MODE1,MODE2,...", line
        )
    modes = [_integer(path, line, c, "mode number") for c in header[2:]]
    if not modes:
        raise ModeFileError(path, "the header row names no mode; expected node,dof,MODE1,...", line)
    if len(set(modes)) != len(modes):
        dup = next(m for m in modes if modes.count(m) > 1)
        raise ModeFileError(
            path, f"mode {dup} heads more than one column; expected each mode number once", line
        )
    per_mode, units = _keyword_rows(path, rows[:header_at], len(modes), header[2:])
    if "freq_hz" not in per_mode:
        raise ModeFileError(
            path, "no freq_hz row; expected freq_hz,,F1,F2,... [Hz] before the node,dof row", line
        )
    nodes, shape_rows, seen = [], [], {}
    for line, cells in rows[header_at + 1 :]:
        if len(cells) < 2:
            raise ModeFileError(path, f"row {','.join(cells)!r}: expected NODE,DOF,VALUE,...", line)
        if cells[0].lower() in _KEYWORDS:
            raise ModeFileError(
                path,
                f"{cells[0]} row after the node,dof header; expected it before the header",
                line,
            )
        node = _integer(path, line, cells[0], "node id")
        try:
            dof = parse_dof(cells[1])
        except ValueError as e:
            raise ModeFileError(path, str(e), line) from None
        if (node, dof) in seen:
            raise ModeFileError(
                path,
                f"node {node} {DOF_NAMES[dof - 1]} already has a row at "
                f"line {seen[node, dof]}; expected one row per node and "
                "component",
                line,
            )
        seen[node, dof] = line
        values = _values(
            path,
            line,
            cells[2:],
            len(modes),
            f"node {node} {DOF_NAMES[dof - 1]}",
            header[2:],
            empty_ok=True,
        )
        nodes.append(node)
        shape_rows.append((node, dof, values))
    if not shape_rows:
        raise ModeFileError(
            path,
            "the table has no node rows; expected NODE,DOF,VALUE,... rows after the header",
            rows[header_at][0],
        )
    node_ids = np.unique(nodes)
    shapes = np.full((len(modes), len(node_ids), 6), np.nan)
    for node, dof, values in shape_rows:
        shapes[:, np.searchsorted(node_ids, node), dof - 1] = values
    empty = np.isnan(shapes).all(axis=(1, 2))
    if empty.any():
        raise ModeFileError(
            path,
            f"mode {modes[int(np.argmax(empty))]} has no value in any row; expected at least one",
            rows[header_at][0],
        )
    return sorted_mode_set(
        str(path),
        modes,
        per_mode["freq_hz"],
        node_ids,
        shapes,
        damping=per_mode.get("damping"),
        modal_mass=per_mode.get("modal_mass"),
        units=units,
    )


def write_modes_csv(path, modes: ModeSet) -> None:
    """Write ``modes`` as a CSV mode file (atomically). Numbers are written in their shortest
    round-trip form, so reading the file gives back the same values bit for bit."""

    def num(x):
        return "" if np.isnan(x) else repr(float(x))

    out = io.StringIO()
    out.write(
        f"# x3dpd mode file: {modes.n_modes} modes, {modes.n_nodes} nodes; shape values "
        "per node and component (x y z rx ry rz), one column per mode\n"
    )
    if modes.units is not None:
        out.write("units," + ",".join(modes.units) + "\n")
    for key in _PER_MODE:
        values = modes.freq_hz if key == "freq_hz" else getattr(modes, key)
        if values is not None:
            out.write(f"{key},," + ",".join(num(v) for v in values) + "\n")
    out.write("node,dof," + ",".join(str(m) for m in modes.mode_numbers) + "\n")
    for i, node in enumerate(modes.node_ids):
        given = [c for c in range(6) if not np.isnan(modes.shapes[:, i, c]).all()]
        for c in given or [0]:  # a node without any value keeps its place: one empty row
            column = modes.shapes[:, i, c]
            out.write(f"{node},{DOF_NAMES[c]}," + ",".join(num(v) for v in column) + "\n")
    data = out.getvalue().encode("utf-8")
    write_atomically(path, lambda f: f.write(data))


def _rows(path):
    """(line number, cells) of each non-blank, non-comment line, cells stripped and trailing
    empty cells dropped (spreadsheets pad rows to the table's width)."""
    with open(path, "rb") as f:
        raw = f.read()
    for number, chunk in enumerate(raw.split(b"\n"), start=1):
        if b"\0" in chunk:
            raise ModeFileError(path, "binary data (a NUL byte); expected a CSV text file", number)
        try:
            text = chunk.decode("utf-8-sig" if number == 1 else "utf-8")
        except UnicodeDecodeError:
            raise ModeFileError(
                path, "bytes that are not UTF-8 text; expected a CSV text file", number
            ) from None
        if not text.strip() or text.lstrip().startswith("#"):
            continue
        if ";" in text and "," not in text:
            raise ModeFileError(
                path,
                "cells separated by ';'; expected commas (and a decimal point in numbers)",
                number,
            )
        cells = [c.strip() for c in next(csv.reader([text.rstrip("\r")]))]
        while cells and cells[-1] == "":
            cells.pop()
        if cells:
            yield number, cells


def _keyword_rows(path, rows, n_modes, mode_cells):
    per_mode, units, where = {}, None, {}
    for line, cells in rows:
        key = cells[0].lower()
        if key not in _KEYWORDS:
            raise ModeFileError(
                path,
                f"row {cells[0]!r} before the node,dof header; expected one "
                f"of {', '.join(_KEYWORDS)} or node,dof,MODE,...",
                line,
            )
        if key in where:
            raise ModeFileError(
                path, f"a second {key} row (the first is at line {where[key]}); expected one", line
            )
        where[key] = line
        if key == "units":
            try:
                units = parse_units([c for c in cells[1:] if c])
            except ValueError as e:
                raise ModeFileError(path, f"units: {e}", line) from None
            continue
        values = cells[2:] if len(cells) > 1 and cells[1] == "" else cells[1:]
        per_mode[key] = _values(path, line, values, n_modes, key, mode_cells, empty_ok=False)
        checks = {
            "freq_hz": (lambda v: v >= 0, ">= 0 Hz"),
            "damping": (lambda v: (v >= 0) & (v < 1), "in [0, 1)"),
            "modal_mass": (lambda v: v > 0, "> 0"),
        }
        ok, expected = checks[key]
        bad = ~ok(per_mode[key])
        if bad.any():
            j = int(np.argmax(bad))
            raise ModeFileError(
                path,
                f"{key} of mode {mode_cells[j]} is {per_mode[key][j]:g}; expected {expected}",
                line,
            )
    return per_mode, units


def _values(path, line, cells, n_modes, what, mode_cells, empty_ok) -> np.ndarray:
    if len(cells) > n_modes:
        raise ModeFileError(
            path,
            f"{what}: {len(cells)} value(s) for {n_modes} mode columns; "
            "expected one per mode column",
            line,
        )
    if not empty_ok and len(cells) < n_modes:
        raise ModeFileError(
            path,
            f"{what}: {len(cells)} value(s) for {n_modes} mode columns; "
            "expected one per mode column",
            line,
        )
    out = np.full(n_modes, np.nan)
    for j, cell in enumerate(cells):
        if cell == "":
            if empty_ok:
                continue
            raise ModeFileError(
                path, f"{what} of mode {mode_cells[j]} is empty; expected a number", line
            )
        try:
            out[j] = float(cell)
        except ValueError:
            raise ModeFileError(
                path, f"{what} of mode {mode_cells[j]}: {cell!r} is not a number", line
            ) from None
        if not np.isfinite(out[j]):
            raise ModeFileError(
                path,
                f"{what} of mode {mode_cells[j]} is {cell!r}; expected a "
                "finite number (leave the cell empty where the file gives "
                "no value)",
                line,
            )
    return out


def _integer(path, line, cell, what) -> int:
    try:
        value = float(cell)
        if value == int(value):
            return int(value)
    except (ValueError, OverflowError):
        pass
    raise ModeFileError(path, f"{what} {cell!r}: expected an integer", line)
