"""A set of measured FRFs, each with its response and reference (drive) point: what a multi-mode
fit reads (``x3dpd fit --modes N``, docs/testing-like-a-test-engineer.md).

* **UFF** -- every FRF dataset 58 of each file (x3dpd.io.measured), its points from the
  dataset's response and reference node and direction;
* **CSV** -- the ``frf.csv`` of ``x3dpd frf`` (one run, one curve per ``response`` NODE:DOF, the
  reference from its ``# drive: node N dof D`` line), or a one-FRF CSV whose comments name its
  points: ``# response: N:D`` and ``# drive: N:D`` (or ``# reference:``).

:func:`write_frf_uff` writes a set as UFF datasets 58 (binary: the values read back bit for
bit), the layout :func:`read_frf_set` reads.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from x3dpd.errors import InputError
from x3dpd.io.measured import (
    UFF_QUANTITY,
    MeasuredFrf,
    _check_axis,
    _drive,
    _numbers,
    _quantity,
    _read_csv,
    is_uff,
    parse_point,
    read_frf_csv,
    read_frf_uff,
)


def read_frf_set(paths: Sequence[str | os.PathLike]) -> list[MeasuredFrf]:
    """Every FRF of every file in ``paths``, in order (module docstring)."""
    out: list[MeasuredFrf] = []
    for path in map(os.fspath, paths):
        if not os.path.isfile(path):
            raise InputError(f"{path}: no such file")
        out += read_frf_uff(path) if is_uff(path) else _read_csv_set(path)
    return out


def _read_csv_set(path: str) -> list[MeasuredFrf]:
    need = "frequency_hz and re, im (or mag, phase_deg)"
    cols, meta, line = _read_csv(path, "measured FRF", need)
    if "response" not in cols:
        return [read_frf_csv(path)]
    runs = sorted({text.strip() for _, _, text in cols.get("run", [])})
    if len(runs) > 1:
        raise InputError(
            f"{path}:{line}:1: the file holds the FRFs of {len(runs)} runs "
            f"({', '.join(runs[:4])}); a modal fit takes the responses of one run"
        )
    re, im = ("h1_re", "h1_im") if "h1_re" in cols else ("re", "im")
    if not {"frequency_hz", re, im} <= cols.keys():
        raise InputError(
            f"{path}:{line}:1: an FRF set needs the columns response, frequency_hz and "
            f"h1_re, h1_im (or re, im)"
        )
    reference = parse_point(path, "reference", meta.get("reference")) or _drive(path, meta)
    f_all = _numbers(path, cols["frequency_hz"])
    h_all = _numbers(path, cols[re]) + 1j * _numbers(path, cols[im])
    names = [text.strip() for _, _, text in cols["response"]]
    out = []
    for name in dict.fromkeys(names):
        rows = np.array([k for k, n in enumerate(names) if n == name])
        cells = [cols["frequency_hz"][k] for k in rows]
        _check_axis(path, "frequency_hz", f_all[rows], cells)
        out.append(
            MeasuredFrf(
                f_all[rows],
                h_all[rows],
                None,
                _quantity(path, meta.get("quantity")),
                f"response {name}",
                path,
                meta.get("unit"),
                parse_point(path, "response", name),
                reference,
            )
        )
    return out


def write_frf_uff(
    path: str | os.PathLike,
    frequency,
    h,
    *,
    responses: Sequence[tuple[int, int]],
    reference: tuple[int, int],
    quantity: str,
    label: str = "x3dpd",
) -> None:
    """Write the FRFs ``h`` (N_o, N_f) at ``frequency`` [Hz] (uniformly spaced), one dataset
    58 (function type 4, binary, double precision) per response point ``(node, dof)``, all from
    ``reference``, as ``quantity`` per unit force; the file is replaced."""
    import pyuff

    code = {q: c for c, q in UFF_QUANTITY.items()}[quantity]
    f = np.asarray(frequency, dtype=float)
    units = {
        f"{axis}_{field}": value
        for axis in ("abscissa", "ordinate", "orddenom", "z_axis")
        for field, value in (
            ("len_unit_exp", 0),
            ("force_unit_exp", 0),
            ("temp_unit_exp", 0),
            ("axis_units_lab", "NONE"),
        )
    }
    sets = [
        pyuff.prepare_58(
            binary=1,
            id1=label,
            id2="NONE",
            id3="NONE",
            id4="NONE",
            id5="NONE",
            func_type=4,
            ver_num=0,
            load_case_id=0,
            rsp_ent_name="NONE",
            rsp_node=int(node),
            rsp_dir=int(dof),
            ref_ent_name="NONE",
            ref_node=int(reference[0]),
            ref_dir=int(reference[1]),
            abscissa_spacing=1,
            abscissa_min=float(f[0]),
            abscissa_inc=float(f[1] - f[0]),
            z_axis_value=0.0,
            abscissa_spec_data_type=18,
            ordinate_spec_data_type=code,
            orddenom_spec_data_type=13,
            z_axis_spec_data_type=0,
            data=np.asarray(row, dtype=complex),
            x=f,
            **units,
        )
        for (node, dof), row in zip(responses, np.atleast_2d(h))
    ]
    if os.path.exists(path):
        os.remove(path)
    pyuff.UFF(os.fspath(path)).write_sets(sets, mode="add")
