# Over 400 lines: the measured-data readers (CSV, UFF 58) share their checks and their errors.
"""Measured data in: frequency response functions and ring-down time histories from a test.

Two formats each (docs/testing-like-a-test-engineer.md):

* **CSV** -- a header row of column names, then one row of numbers per sample; lines starting
  with ``#`` are comments, and a comment ``# quantity: acceleration`` (or ``displacement``,
  ``velocity``) says what the response is. An FRF has the columns ``frequency_hz`` and either
  ``re, im`` or ``mag, phase_deg`` (optional ``coherence``) -- or ``h1_re, h1_im``, so that the
  ``frf.csv`` of ``x3dpd frf`` reads back when it holds one run and one response; a ring-down has
  ``time`` and ``displacement`` or ``acceleration``. Other columns are ignored; names are
  case-insensitive.
* **UFF** (universal file format, ASCII or binary), dataset 58 (function at a nodal DOF), read
  with pyuff: function type 4 (FRF) or 5 (transmissibility) for FRFs, 1 (time response) for a
  ring-down. The ordinate's specific data type gives the quantity (8 displacement, 11 velocity,
  12 acceleration).

Every problem is an :class:`~x3dpd.errors.InputError` naming the file (and line and column for a
CSV).
"""

from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass

import numpy as np

from x3dpd.errors import InputError

QUANTITIES = ("displacement", "velocity", "acceleration")
#: UFF 58 ordinate specific data types that name a response quantity.
UFF_QUANTITY = {8: "displacement", 11: "velocity", 12: "acceleration"}
#: UFF 58 function types read as FRFs, and as time histories.
UFF_FRF_TYPES = {4: "frequency response function", 5: "transmissibility"}
UFF_TIME_TYPES = {1: "time response"}
UFF_SUFFIXES = (".uff", ".unv", ".uf")


@dataclass(frozen=True)
class MeasuredFrf:
    """A measured FRF: ``frequency`` [Hz] (increasing), complex ``h``, optional ``coherence``,
    the response ``quantity`` (None when the file does not say), a ``label``, the ``unit`` of
    ``h`` (None when unknown), the ``response`` and ``reference`` points (node, direction 1-6,
    negative along -x ...; None when the file does not say) and the ``function`` (a UFF file's
    "transmissibility" when it says so)."""

    frequency: np.ndarray
    h: np.ndarray
    coherence: np.ndarray | None
    quantity: str | None
    label: str
    path: str
    unit: str | None = None
    response: tuple[int, int] | None = None
    reference: tuple[int, int] | None = None
    function: str = "frequency response function"


@dataclass(frozen=True)
class MeasuredHistory:
    """A measured time history: ``time`` [s] (uniformly spaced), ``signal``, its ``kind``
    (``displacement`` or ``acceleration``) and a ``label``."""

    time: np.ndarray
    signal: np.ndarray
    kind: str
    label: str
    path: str


def is_uff(path: str | os.PathLike) -> bool:
    """True for a file to be read as UFF (by its suffix)."""
    return os.fspath(path).lower().endswith(UFF_SUFFIXES)


# ---------------------------------------------------------------------------------------------
# CSV
# ---------------------------------------------------------------------------------------------


def _read_csv(
    path: str, what: str, required: str
) -> tuple[dict[str, list[tuple[int, int, str]]], dict, int]:
    """Raw cells by lower-case column name (each ``(line, column, text)``), the ``# key:
    value`` comments, and the header's line number."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the {what} ({exc})") from None
    meta, names, header_line, cols = {}, None, 0, {}
    for number, line in enumerate(lines, start=1):
        text = line.strip()
        if not text:
            continue
        if text.startswith("#"):
            key, colon, value = text[1:].partition(":")
            if colon:
                meta[key.strip().lower()] = value.strip()
            continue
        cells = next(csv.reader([line]))
        if names is None:
            names, header_line = [c.strip().lower() for c in cells], number
            if len(set(names)) != len(names):
                raise InputError(
                    f"{path}:{number}:1: a column name is repeated ({', '.join(names)})"
                )
            cols = {n: [] for n in names}
            continue
        if len(cells) != len(names):
            raise InputError(
                f"{path}:{number}:1: {len(cells)} values, the header has {len(names)} columns"
            )
        col = 1
        for name, cell in zip(names, cells):
            cols[name].append((number, col, cell))
            col += len(cell) + 1
    if names is None:
        raise InputError(f"{path}: no header row; a {what} CSV starts with the columns {required}")
    return cols, meta, header_line


def _numbers(path: str, cells: list[tuple[int, int, str]]) -> np.ndarray:
    """The floats of one column's cells (an error at the first cell that is not one)."""
    out = np.empty(len(cells))
    for k, (line, col, text) in enumerate(cells):
        try:
            out[k] = float(text)
        except ValueError:
            raise InputError(f"{path}:{line}:{col}: {text.strip()!r} is not a number") from None
        if not math.isfinite(out[k]):
            raise InputError(f"{path}:{line}:{col}: {text.strip()!r} is not finite")
    return out


def _names(cols: dict) -> str:
    names = [n[:24] for n in cols]
    return (", ".join(names[:8]) + (" ..." if len(names) > 8 else "")) or "none"


def _quantity(path: str, text: str | None) -> str | None:
    if text is None:
        return None
    q = text.strip().lower()
    if q not in QUANTITIES:
        raise InputError(f"{path}: quantity {text!r}: expected one of {', '.join(QUANTITIES)}")
    return q


def _check_axis(path: str, name: str, values: np.ndarray, cells=None) -> None:
    """At least 3 samples, strictly increasing (an error at the first row that is not)."""
    if values.size < 3:
        raise InputError(f"{path}: {values.size} data rows; at least 3 are needed")
    bad = np.flatnonzero(np.diff(values) <= 0)
    if bad.size:
        where = f"{path}:{cells[int(bad[0]) + 1][0]}:1" if cells else path
        raise InputError(f"{where}: {name} must increase from row to row")


def read_frf_csv(path: str | os.PathLike) -> MeasuredFrf:
    """A measured FRF from a CSV (module docstring)."""
    path = os.fspath(path)
    need = "frequency_hz and re, im (or mag, phase_deg)"
    cols, meta, line = _read_csv(path, "measured FRF", need)
    if "re" not in cols and "mag" not in cols and {"h1_re", "h1_im"} <= cols.keys():
        _one_curve(path, cols, line)
        cols["re"], cols["im"] = cols["h1_re"], cols["h1_im"]
    if "frequency_hz" not in cols or not (
        {"re", "im"} <= cols.keys() or {"mag", "phase_deg"} <= cols.keys()
    ):
        raise InputError(
            f"{path}:{line}:1: a measured FRF needs the columns {need}; found {_names(cols)}"
        )
    num = {
        n: _numbers(path, cols[n])
        for n in ("frequency_hz", "re", "im", "mag", "phase_deg", "coherence")
        if n in cols
    }
    f = num["frequency_hz"]
    _check_axis(path, "frequency_hz", f, cols["frequency_hz"])
    if f[0] < 0:
        raise InputError(f"{path}:{cols['frequency_hz'][0][0]}:1: frequency_hz must be >= 0")
    if {"re", "im"} <= num.keys():
        h = num["re"] + 1j * num["im"]
    else:
        h = num["mag"] * np.exp(1j * np.radians(num["phase_deg"]))
    return MeasuredFrf(
        f,
        h,
        num.get("coherence"),
        _quantity(path, meta.get("quantity")),
        meta.get("label", os.path.basename(path)),
        path,
        meta.get("unit"),
        parse_point(path, "response", meta.get("response")),
        parse_point(path, "reference", meta.get("reference")) or _drive(path, meta),
    )


def _drive(path: str, meta: dict) -> tuple[int, int] | None:
    """The ``# drive:`` comment's point, when it names one (``x3dpd frf`` writes ``node N dof
    D``; other files may describe their drive in words)."""
    try:
        return parse_point(path, "drive", meta.get("drive"))
    except InputError:
        return None


_DOF_CODES = {"x": 1, "y": 2, "z": 3, "rx": 4, "ry": 5, "rz": 6}


def parse_point(path: str, what: str, text: str | None) -> tuple[int, int] | None:
    """A measured point ``(node, dof)`` from ``node N dof D`` (how ``x3dpd frf`` writes its
    ``# drive:`` line) or ``N:D``, D 1-6 or x y z rx ry rz (with a sign: -1 is along -x, as
    in UFF); None for None."""
    if text is None:
        return None
    words = text.replace(":", " ").split()
    if len(words) == 4 and words[0].lower() == "node" and words[2].lower() == "dof":
        words = [words[1], words[3]]
    try:
        node = int(words[0])
        key = words[1].lower()
        sign = -1 if key.startswith("-") else 1
        dof = sign * _DOF_CODES.get(key.lstrip("+-"), int(key.lstrip("+-")))
        if len(words) != 2 or not 1 <= abs(dof) <= 6:
            raise ValueError
    except (ValueError, IndexError):
        raise InputError(
            f"{path}: {what} {text!r}: expected 'node N dof D' or N:D (D 1-6 or x y z rx ry rz)"
        ) from None
    return node, dof


def _one_curve(path: str, cols: dict, line: int) -> None:
    """An ``x3dpd frf`` CSV reads as one FRF only when it holds one run and one response."""
    for key in ("run", "response"):
        values = sorted({text.strip() for _, _, text in cols.get(key, [])})
        if len(values) > 1:
            raise InputError(
                f"{path}:{line}:1: the file holds the FRFs of {len(values)} "
                f"{key}s ({', '.join(values[:6])}); write one per file (x3dpd frf "
                "with one TRACE and one --response)"
            )


def read_history_csv(path: str | os.PathLike) -> MeasuredHistory:
    """A measured ring-down from a CSV (module docstring)."""
    path = os.fspath(path)
    need = "time and displacement or acceleration"
    cols, meta, line = _read_csv(path, "measured ring-down", need)
    kinds = [k for k in ("displacement", "acceleration") if k in cols]
    if "time" not in cols or len(kinds) != 1:
        raise InputError(
            f"{path}:{line}:1: a measured ring-down needs the columns {need} (one of "
            f"the two); found {_names(cols)}"
        )
    t = _numbers(path, cols["time"])
    _check_axis(path, "time", t, cols["time"])
    _check_uniform(path, t)
    return MeasuredHistory(
        t, _numbers(path, cols[kinds[0]]), kinds[0], meta.get("label", os.path.basename(path)), path
    )


def _check_uniform(path: str, t: np.ndarray) -> None:
    step = np.diff(t)
    if np.max(np.abs(step - step.mean())) > 1e-6 * step.mean():
        raise InputError(
            f"{path}: the time column is not uniformly spaced (steps "
            f"{step.min():.6g} .. {step.max():.6g} s)"
        )


# ---------------------------------------------------------------------------------------------
# UFF dataset 58
# ---------------------------------------------------------------------------------------------


def _uff_sets(path: str) -> list[dict]:
    """Every dataset 58 of a UFF file (an error naming the types found when there is none)."""
    import pyuff

    if not os.path.isfile(path):
        raise InputError(f"{path}: no such file")
    try:
        uff = pyuff.UFF(path)
        types = [int(t) for t in uff.get_set_types()]
    except Exception as exc:  # pyuff raises bare Exceptions on foreign files
        raise InputError(f"{path}: not a readable UFF file ({exc})") from None
    if 58 not in types:
        found = ", ".join(str(t) for t in sorted(set(types))) or "none"
        raise InputError(
            f"{path}: holds UFF dataset type(s) {found}, not 58 (function at a "
            "nodal DOF), which measured FRFs and time histories use"
        )
    try:
        sets = [uff.read_sets(k) for k, t in enumerate(types) if t == 58]
    except Exception as exc:
        raise InputError(f"{path}: cannot read its dataset 58 ({exc})") from None
    return sets


def _uff_label(s: dict) -> str:
    return (
        f"rsp {s.get('rsp_node')}:{s.get('rsp_dir')} / ref {s.get('ref_node')}:{s.get('ref_dir')}"
    )


def read_frf_uff(path: str | os.PathLike) -> list[MeasuredFrf]:
    """Every FRF (function type 4 or 5) of a UFF file's datasets 58."""
    path = os.fspath(path)
    sets = _uff_sets(path)
    out = []
    for s in sets:
        if int(s.get("func_type", 0)) not in UFF_FRF_TYPES:
            continue
        f = np.asarray(s["x"], dtype=float)
        h = np.asarray(s["data"]).astype(complex)
        _check_axis(path, "the abscissa (frequency)", f)
        quantity = UFF_QUANTITY.get(int(s.get("ordinate_spec_data_type", 0)))
        num, den = (str(s.get(f"{a}_axis_units_lab", "")).strip() for a in ("ordinate", "orddenom"))
        unit = f"({num})/({den})" if num and den and num != "NONE" else None
        points = [(int(s.get(f"{a}_node", 0)), int(s.get(f"{a}_dir", 0))) for a in ("rsp", "ref")]
        kind = UFF_FRF_TYPES[int(s["func_type"])]
        out.append(MeasuredFrf(f, h, None, quantity, _uff_label(s), path, unit, *points, kind))
    if not out:
        found = ", ".join(sorted({str(int(s.get("func_type", 0))) for s in sets}))
        raise InputError(
            f"{path}: its datasets 58 hold function type(s) {found}; an FRF is "
            "type 4 (FRF) or 5 (transmissibility)"
        )
    return out


def read_history_uff(path: str | os.PathLike) -> MeasuredHistory:
    """The first time response (function type 1) of a UFF file's datasets 58."""
    path = os.fspath(path)
    sets = _uff_sets(path)
    for s in sets:
        if int(s.get("func_type", 0)) in UFF_TIME_TYPES:
            kind = UFF_QUANTITY.get(int(s.get("ordinate_spec_data_type", 0)))
            if kind not in ("displacement", "acceleration"):
                raise InputError(
                    f"{path}: the time response is not a displacement (8) or an "
                    "acceleration (12) (ordinate specific data type "
                    f"{s.get('ordinate_spec_data_type')})"
                )
            t = np.asarray(s["x"], dtype=float)
            _check_axis(path, "the abscissa (time)", t)
            _check_uniform(path, t)
            return MeasuredHistory(
                t, np.real(np.asarray(s["data"])).astype(float), kind, _uff_label(s), path
            )
    found = ", ".join(sorted({str(int(s.get("func_type", 0))) for s in sets}))
    raise InputError(
        f"{path}: its datasets 58 hold function type(s) {found}; a ring-down is "
        "type 1 (time response)"
    )


# ---------------------------------------------------------------------------------------------
# Either
# ---------------------------------------------------------------------------------------------


def read_measured_frf(path: str | os.PathLike) -> list[MeasuredFrf]:
    """The measured FRF(s) of a CSV (one) or UFF file (each FRF dataset 58)."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"{path}: no such file")
    return read_frf_uff(path) if is_uff(path) else [read_frf_csv(path)]


def read_measured_history(path: str | os.PathLike) -> MeasuredHistory:
    """A measured ring-down from a CSV or UFF file."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"{path}: no such file")
    return read_history_uff(path) if is_uff(path) else read_history_csv(path)


def write_frf_csv(
    path: str | os.PathLike,
    frequency,
    h,
    *,
    coherence=None,
    quantity: str | None = None,
    label: str | None = None,
    unit: str | None = None,
) -> None:
    """Write an FRF in the CSV format :func:`read_frf_csv` reads (``repr`` of every float: the
    values read back exactly), atomically."""
    from x3dpd._files import write_atomically

    lines = []
    if quantity is not None:
        lines.append(f"# quantity: {_quantity(os.fspath(path), quantity)}")
    if label is not None:
        lines.append(f"# label: {label}")
    if unit is not None:
        lines.append(f"# unit: {unit}")
    names = ["frequency_hz", "re", "im"] + (["coherence"] if coherence is not None else [])
    lines.append(",".join(names))
    h = np.asarray(h, dtype=complex)
    for k, f in enumerate(np.asarray(frequency, dtype=float)):
        row = [f, h[k].real, h[k].imag] + ([coherence[k]] if coherence is not None else [])
        lines.append(",".join(repr(float(v)) for v in row))
    data = ("\n".join(lines) + "\n").encode()
    write_atomically(path, lambda fh: fh.write(data))
