"""Measured FRFs on a sweep's plots (``x3dpd sweep --measured FILE[@NODE:DOF]``).

A measured FRF (CSV or UFF dataset 58, x3dpd.io.measured) is a response quantity q per unit drive
at one point: per unit force for a force drive, per unit base acceleration for a base drive.
The file's ``quantity`` says q (a file that does not say is taken as an acceleration: an
accelerance, or a transmissibility); ``--measured-scale`` multiplies it first (a unit
conversion). It is drawn on the panel of its point (``@NODE:DOF``; default the first
``--response``, else the driven point) at every drive level, as the displacement amplitude the
sweep would measure there if the structure were the measured linear one:

    force drive:   X(f) = |H_q| F / w^q,
    a base drive:  X(f) = |T| U(f),  T = H_q (i w)^(2 - q)

so each panel shows it in its own quantity: sweep.png the amplitude X (F |receptance|),
sweep_responses.png the accelerance w^2 X / F (the measured accelerance itself), a base drive's
sweep.png the transmissibility X / U (the measured T).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from x3dpd.api.measurements import QUANTITY_ORDER, MeasuredFrf, read_measured_frf
from x3dpd.design.drive import displacement_amplitude
from x3dpd.design.spec import SweepSpec, parse_point
from x3dpd.errors import InputError


def read_measured(
    texts: Sequence[str], points: Sequence[tuple[int, int]], scale: float = 1.0
) -> list[tuple[tuple[int, int], MeasuredFrf]]:
    """``--measured FILE[@NODE:DOF]`` values -> [(point, FRF)], every file read and checked
    now (before the sweep writes anything). ``points``: the points the sweep measures, the
    default first."""
    if not (np.isfinite(scale) and scale != 0):
        raise InputError(f"--measured-scale {scale!r}: expected a finite number other than 0")
    out = []
    for text in texts:
        path, at, where = str(text).rpartition("@") if "@" in str(text) else (text, "", "")
        point = parse_point(where, f"--measured {text!r}:") if at else points[0]
        if point not in points:
            raise InputError(
                f"--measured {text!r}: the sweep does not measure node {point[0]} "
                f"dof {point[1]} (it measures "
                f"{', '.join(f'{n}:{d}' for n, d in points)})"
            )
        for frf in read_measured_frf(path):
            out.append((point, frf))
    return out


def measured_curves(measured, spec: SweepSpec, point: tuple[int, int], scale: float = 1.0) -> dict:
    """{("measured LABEL", drive): (f, X)} of the measured FRFs at ``point`` (module doc),
    within the swept band."""
    lo, hi = min(spec.frequencies), max(spec.frequencies)
    out = {}
    for where, frf in measured:
        if where != point:
            continue
        keep = (frf.frequency >= lo) & (frf.frequency <= hi) & (frf.frequency > 0)
        f = frf.frequency[keep]
        w = 2.0 * np.pi * f
        q = QUANTITY_ORDER[frf.quantity or "acceleration"]
        label = frf.label if frf.label.startswith("measured") else f"measured {frf.label}"
        for drive in spec.drives:
            if spec.base:
                t = frf.h[keep] * scale * (1j * w) ** (2 - q)
                u = np.array([displacement_amplitude(drive, spec.quantity, x) for x in w])
                x = np.abs(t) * u
            else:
                x = np.abs(frf.h[keep] * scale) * abs(drive) / w**q
            out[(label, drive)] = (f, x)
    return out
