"""``x3dpd fit MEASURED... --modes N --out DIR``: N modes fitted to a set of measured FRFs (one
reference and several responses, or one response and several references: a roving hammer), as
a mode file and a MODAL card (docs/testing-like-a-test-engineer.md, "Several modes").

The poles come from x3dpd.analysis.lscf (LSCF over orders, stabilised), the modal constants,
residual terms, refined poles and standard errors from x3dpd.analysis.lsfd; the driving-point
FRF scales the shapes to unit modal mass. Outputs: DIR/modes.csv (a CSV mode file),
DIR/modal_card.inp (the MODAL card that reads it), DIR/modal_fit.txt (the printed report) and
DIR/modal_fit.png (the FRFs, their synthesis and the stabilisation diagram).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from x3dpd.api.figures import plot_modal_fit
from x3dpd.api.measurements import (
    DOF_NAMES,
    QUANTITY_ORDER,
    ModalFit,
    ModeSet,
    lscf_poles,
    max_order,
    pole_groups,
    read_frf_set,
    refine_modes,
    select_poles,
    write_modes_csv,
)
from x3dpd.errors import InputError
from x3dpd.testlab.outputs import output_paths
from x3dpd.testlab.trace_signals import parse_band
from x3dpd.units import parse_units

#: Lines a band needs: LINES_PER_MODE per mode, plus MIN_LINES.
LINES_PER_MODE = 5
MIN_LINES = 10
OUTPUTS = ("modes.csv", "modal_card.inp", "modal_fit.txt", "modal_fit.png")
_FORM = {"displacement": "receptance", "velocity": "mobility", "acceleration": "accelerance"}


def point_name(point: tuple[int, int]) -> str:
    """``NODE:DOF`` with the DOF's name (``1:x``)."""
    return f"{point[0]}:{DOF_NAMES[point[1] - 1]}"


@dataclass(frozen=True)
class FrfSet:
    """Measured FRFs of one column (or row) of the FRF matrix: ``h`` (N_o, N_f) at
    ``frequency``, along the points' positive directions; the ``points`` that vary (node, DOF),
    the ``common`` point they share and which end varies (``roving``: "response" or
    "reference"), the index of the ``driving`` point's FRF, the response ``quantity``."""

    files: str
    frequency: np.ndarray
    h: np.ndarray
    points: list[tuple[int, int]]
    common: tuple[int, int]
    roving: str
    driving: int
    quantity: str
    unit: str | None


def _check_frf(m) -> None:
    """An FRF per unit force whose response and reference points are given, each direction
    1-6 or its negative."""
    if m.function != "frequency response function":
        raise InputError(
            f"{m.path}: the FRF {m.label!r} is a {m.function}; a modal fit needs FRFs per "
            "unit force (UFF function type 4)"
        )
    if m.response is None or m.reference is None:
        raise InputError(
            f"{m.path}: the FRF {m.label!r} does not say its response and reference "
            "points; a modal fit needs them (UFF 58 records, or CSV comments "
            "'# response: N:D' and '# drive: N:D')"
        )
    for what, (_, dof) in (("response", m.response), ("reference", m.reference)):
        if not 1 <= abs(dof) <= 6:
            raise InputError(
                f"{m.path}: the FRF {m.label!r} has {what} direction {dof}; expected "
                "1-6 (x y z rx ry rz) or their negatives"
            )


def frf_set(measured: Sequence[str], quantity: str | None = None) -> FrfSet:
    """Read and check a set of FRFs (module docstring): points given, one frequency axis, one
    quantity, one shared point, each other point once, and a driving point."""
    files = ", ".join(os.fspath(m) for m in measured)
    frfs = read_frf_set(measured)
    for m in frfs:
        _check_frf(m)
    first = frfs[0]
    for m in frfs[1:]:
        if m.frequency.shape != first.frequency.shape or not np.allclose(
            m.frequency, first.frequency, rtol=1e-9, atol=0.0
        ):
            raise InputError(
                f"{m.path}: the FRF {m.label!r} has {m.frequency.size} lines over "
                f"{m.frequency[0]:g}-{m.frequency[-1]:g} Hz, {first.path}'s "
                f"{first.label!r} {first.frequency.size} over {first.frequency[0]:g}-"
                f"{first.frequency[-1]:g} Hz; a modal fit needs one frequency axis"
            )
    qs = {quantity or m.quantity for m in frfs}
    if None in qs:
        raise InputError(
            f"{files}: the file does not say what the response is; give --quantity "
            "displacement|velocity|acceleration"
        )
    if len(qs) > 1:
        raise InputError(f"{files}: the FRFs are of {', '.join(sorted(qs))}; expected one quantity")
    refs = {(m.reference[0], abs(m.reference[1])) for m in frfs}
    rsps = {(m.response[0], abs(m.response[1])) for m in frfs}
    if len(refs) == 1:
        roving, common = "response", refs.pop()
        points = [(m.response[0], abs(m.response[1])) for m in frfs]
    elif len(rsps) == 1:
        roving, common = "reference", rsps.pop()
        points = [(m.reference[0], abs(m.reference[1])) for m in frfs]
    else:
        raise InputError(
            f"{files}: the FRFs have {len(refs)} references and {len(rsps)} responses; a "
            "modal fit takes one reference (several responses) or one response (a roving "
            "hammer): fit each reference's FRFs on their own"
        )
    repeated = sorted({p for p in points if points.count(p) > 1})
    if repeated:
        raise InputError(
            f"{files}: {len(points)} FRFs for {len(set(points))} points (point "
            f"{point_name(repeated[0])} more than once); expected one FRF per point"
        )
    if common not in points:
        raise InputError(
            f"{files}: no driving-point FRF (response and reference both at "
            f"{point_name(common)}); the mass-normalised shapes are scaled by it: measure it "
            "and add it to the set"
        )
    sign = np.array([np.sign(m.response[1]) * np.sign(m.reference[1]) for m in frfs])
    h = np.array([m.h for m in frfs]) * sign[:, None]
    return FrfSet(
        files,
        first.frequency,
        h,
        points,
        common,
        roving,
        points.index(common),
        qs.pop(),
        first.unit,
    )


def _lines(fs: FrfSet, band: tuple[float, float] | None, n_modes: int):
    """The band (default: the file's lines above 0 Hz), checked, and its line mask."""
    f = fs.frequency
    lo, hi = band if band is not None else (float(f[f > 0][0]), float(f[-1]))
    if hi > f[-1] or lo < f[0]:
        raise InputError(
            f"{fs.files}: --band {lo:g}:{hi:g} Hz reaches outside the measured data "
            f"({f[0]:g} .. {f[-1]:g} Hz)"
        )
    sel = (f >= lo) & (f <= hi) & (f > 0)
    need = LINES_PER_MODE * n_modes + MIN_LINES
    if np.count_nonzero(sel) < need:
        raise InputError(
            f"{fs.files}: the band {lo:g}:{hi:g} Hz holds {np.count_nonzero(sel)} lines "
            f"(of {f.size}); --modes {n_modes} needs at least {need} ({LINES_PER_MODE} per "
            f"mode and {MIN_LINES}): widen --band or lower --modes"
        )
    for o, point in enumerate(fs.points):  # (the readers refuse values that are not finite)
        if not np.any(fs.h[o, sel] != 0):
            raise InputError(
                f"{fs.files}: the FRF at {point_name(point)} is 0 over the band {lo:g}:{hi:g} Hz"
            )
    return (lo, hi), sel


def fit_set(fs: FrfSet, n_modes: int, band, *, force_scale: float = 1.0):
    """LSCF poles, stabilisation and refinement of the set over ``band`` (None: the lines above
    0 Hz): (the band, the poles per order, the :class:`ModalFit`)."""
    (lo, hi), sel = _lines(fs, band, n_modes)
    f, h = fs.frequency[sel], fs.h[:, sel] / force_scale
    order = QUANTITY_ORDER[fs.quantity]
    try:
        orders = lscf_poles(f, h, band=(lo, hi), max_order=max_order(n_modes, f.size))
        lam = select_poles(pole_groups(orders), n_modes, band=(lo, hi))
        fn0, zeta0 = np.abs(lam) / (2 * np.pi), -lam.real / np.abs(lam)
        fit = refine_modes(f, h, fn0, zeta0, order=order, driving=fs.driving, band=(lo, hi))
    except InputError as exc:
        raise InputError(f"{fs.files}: {exc}") from None
    return (lo, hi), orders, fit


def fit_modes(fs: FrfSet, n_modes: int, band, *, force_scale: float = 1.0):
    """:func:`fit_set` and the mass-normalised shapes: (the band, the poles per order, the fit,
    the shapes (N_o, N) and their standard errors); an error saying what to pass when the
    driving point's FRF is of reversed sign."""
    lo_hi, orders, fit = fit_set(fs, n_modes, band, force_scale=force_scale)
    if np.all(fit.constants[fs.driving] < 0):
        raise InputError(
            f"{fs.files}: the driving-point FRF ({point_name(fs.common)}) has every mode's "
            "modal constant negative: its sign is reversed (drive and response in opposite "
            f"directions, common in hammer tests); pass --force-scale {-force_scale:g}"
        )
    try:
        phi, phi_se = fit.shapes()
    except InputError as exc:
        raise InputError(f"{fs.files}: {exc}") from None
    return lo_hi, orders, fit, phi, phi_se


def mode_set(path: str, fs: FrfSet, fit: ModalFit, phi: np.ndarray, units) -> ModeSet:
    """The fitted modes as a :class:`ModeSet` (mode numbers 1..N; each measured point's DOF
    holds its shape values, the others none)."""
    nodes = sorted({p[0] for p in fs.points})
    shapes = np.full((fit.fn.size, len(nodes), 6), np.nan)
    for o, (node, dof) in enumerate(fs.points):
        shapes[:, nodes.index(node), dof - 1] = phi[o]
    numbers = np.arange(1, fit.fn.size + 1)
    return ModeSet(path, numbers, fit.fn, np.array(nodes), shapes, fit.zeta, None, units)


def report(fs: FrfSet, fit: ModalFit, phi, phi_se, *, band, orders, force_scale) -> list[str]:
    """The fit as printed and written to DIR/modal_fit.txt."""
    n = fit.fn.size
    lines = [
        f"fit --modes {n} of {len(fs.points)} FRF(s) ({fs.files}): {fs.roving}s at "
        + " ".join(point_name(p) for p in fs.points)
        + f", {'reference' if fs.roving == 'response' else 'response'} {point_name(fs.common)}; "
        f"{_FORM[fs.quantity]} per unit force (force scale {force_scale:g})",
        f"band {band[0]:g}-{band[1]:g} Hz, {fit.frequency.size} lines; LSCF orders "
        f"{orders.orders[0]}-{orders.orders[-1]}, {n} stable mode(s) refined by least squares; "
        f"misfit {100 * float(np.sqrt(np.mean(fit.misfit**2))):.3g} % RMS of each FRF's RMS",
        "mode  fn [Hz] (+- one standard error)  zeta",
    ]
    for r in range(n):
        lines.append(
            f"{r + 1:>4}  {fit.fn[r]:.8g} +- {fit.fn_se[r]:.2g}  {fit.zeta[r]:.6g} +- "
            f"{fit.zeta_se[r]:.2g}"
        )
    lines.append(f"mass-normalised shapes (driving point {point_name(fs.common)}):")
    lines.append(
        "point  " + "".join(f"{'mode ' + str(r + 1):>11}{'':11}" for r in range(n)).rstrip()
    )
    for o, p in enumerate(fs.points):
        cells = [f"{phi[o, r]:>11.6g} +- {phi_se[o, r]:<7.2g}" for r in range(n)]
        lines.append(f"{point_name(p):<7}" + "".join(cells).rstrip())
    lines.append(
        "residual terms (receptance per unit force): lower L / (i w)^2 (modes below the band "
        "and rigid-body motion), upper U (modes above)"
    )
    for o, p in enumerate(fs.points):
        se_l, se_u = np.sqrt(np.maximum(np.diag(fit.coef_cov[o, 0])[n:], 0.0))
        lines.append(
            f"{point_name(p):<7} L {fit.lower[o]:.4g} +- {se_l:.2g}, U {fit.upper[o]:.4g} +- "
            f"{se_u:.2g}; misfit {100 * fit.misfit[o]:.3g} %"
        )
    return lines


def modal_card(fs: FrfSet, fit: ModalFit, mode_file: str, units) -> str:
    """The MODAL card that reads ``mode_file``, with what a deck needs around it."""
    nodes = sorted({p[0] for p in fs.points})
    said = (
        f"in {' '.join(units)} (the deck converts them to its UNITS)"
        if units
        else "without units: the deck takes them in its own (give --units L,F,T to declare "
        "the FRFs')"
    )
    lines = [
        f"$ x3dpd fit --modes {fit.fn.size} of {fs.files}: {mode_file} holds the modes' "
        "frequencies, damping ratios",
        f"$ and mass-normalised shapes at the measured points, {said}.",
        f"$ The deck needs the nodes {', '.join(map(str, nodes))} (NODE COORDINATES: the measured "
        "points); a relative FILE path",
        "$ is taken from the deck's folder. HOUSING added couples in the mass the deck puts on "
        "these nodes",
        "$ (a damper's housing not on the tested structure); HOUSING included if it was on it.",
        "MODAL",
        f"  FILE {mode_file}",
        "  HOUSING added",
        "END",
    ]
    return "\n".join(lines) + "\n"


def modal_fit_command(
    measured: Sequence[str],
    *,
    out: str,
    modes: int,
    band: str | None = None,
    quantity: str | None = None,
    force_scale: float | None = None,
    units: str | None = None,
    overwrite: bool = False,
    echo: Callable[[str], None] = print,
) -> ModalFit:
    """Fit ``modes`` modes to the FRFs of the files ``measured`` over ``band`` (default: the
    files' lines above 0 Hz) and write DIR/modes.csv, modal_card.inp, modal_fit.txt and
    modal_fit.png (module docstring)."""
    from x3dpd._files import write_atomically

    if modes < 1:
        raise InputError(f"--modes {modes}: expected a number of modes >= 1")
    band_hz = parse_band(band)
    scale = 1.0 if force_scale is None else float(force_scale)
    if scale == 0 or not math.isfinite(scale):
        raise InputError(f"--force-scale {force_scale!r}: expected a finite non-zero number")
    try:
        unit_names = parse_units(units.replace(",", " ").split()) if units else None
    except ValueError as exc:
        raise InputError(f"--units {units!r}: {exc}") from None
    paths = output_paths(out, OUTPUTS, overwrite)
    fs = frf_set(measured, quantity)
    lo_hi, orders, fit, phi, phi_se = fit_modes(fs, modes, band_hz, force_scale=scale)
    modeset = mode_set(str(paths[0]), fs, fit, phi, unit_names)
    lines = report(fs, fit, phi, phi_se, band=lo_hi, orders=orders, force_scale=scale)
    card = modal_card(fs, fit, paths[0].name, unit_names)
    labels = [f"{'rsp' if fs.roving == 'response' else 'ref'} {point_name(p)}" for p in fs.points]
    sel = (fs.frequency >= lo_hi[0]) & (fs.frequency <= lo_hi[1]) & (fs.frequency > 0)
    paths[0].parent.mkdir(parents=True, exist_ok=True)
    tmp = paths[3].with_name("." + paths[3].name + ".tmp.png")
    try:
        plot_modal_fit(
            str(tmp),
            fs.frequency[sel],
            fs.h[:, sel] / scale,
            fit.model,
            labels=labels,
            ylabel=fs.unit or f"{_FORM[fs.quantity]} unit",
            band=lo_hi,
            stabilisation=(orders.orders, orders.freq, orders.stable),
            modes=fit.fn,
            title=f"{Path(str(measured[0])).name}: {fit.fn.size} modes",
        )
        write_modes_csv(paths[0], modeset)
        write_atomically(paths[1], lambda fh: fh.write(card.encode()))
        write_atomically(paths[2], lambda fh: fh.write(("\n".join(lines) + "\n").encode()))
        tmp.replace(paths[3])
    finally:
        if tmp.exists():
            tmp.unlink()
    for line in lines:
        echo(line)
    echo(f"wrote {', '.join(str(p) for p in paths[:3])} and {paths[3]}")
    return fit
