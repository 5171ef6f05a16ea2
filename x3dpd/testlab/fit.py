"""``x3dpd fit MEASURED --out DIR``: a single-mode SDOF fitted to a measured FRF, written as the
deck records of the report's beam decks (MASS, a MATID type 1 spring/damper, its ELEMENTS record)
or, with ``--records modal``, as a MODAL card's values, to DIR/fit.txt, with DIR/fit.png
(measured vs fitted). The fit is :mod:`x3dpd.analysis.sdof_fit`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np

from x3dpd.api.figures import plot_fit
from x3dpd.api.measurements import (
    QUANTITY_ORDER,
    MeasuredFrf,
    SdofFit,
    fit_sdof,
    read_measured_frf,
)
from x3dpd.errors import InputError
from x3dpd.testlab.outputs import output_paths
from x3dpd.testlab.trace_signals import parse_band

_AXES = "XYZ"


def modal_records(
    fit: SdofFit, values: dict[str, float], *, node: int, dof: int, drive: str
) -> list[str]:
    """The fit as a MODAL card (docs/deck-reference.md): one mode of frequency fn and damping
    zeta whose mass-normalised shape value at the point is phi = 1/sqrt(m) (its receptance
    there phi^2 / (wn^2 - w^2 + 2 i zeta wn w) is the fitted SDOF's), HOUSING included (the
    effective mass m is the whole structure's at the point: no MASS record)."""
    phi = 1.0 / math.sqrt(values["mass"])
    return [
        f"$ The structure as one mode (MODAL card): node {node} moves along "
        f"{_AXES[dof - 1].lower()} as phi q, phi = 1/sqrt(m);",
        "$ the node needs no MASS record (HOUSING included: m is in the mode); give it "
        "shape values only in this DOF",
        f"$ and drive it with S times the excitation, e.g. {drive}",
        "MODAL",
        "$ MODE K FREQ ZETA",
        f"   MODE 1 {fit.fn:.10g} {fit.zeta:.10g}",
        "$ SHAPE NODE DOF PHI",
        f"   SHAPE {node} {dof} {phi:.10g}",
        "   HOUSING included",
        "END",
    ]


def fit_text(
    source: MeasuredFrf,
    fit: SdofFit,
    values: dict[str, float],
    *,
    node: int,
    dof: int,
    quantity: str,
    mid: int = 2,
    records: str = "sdof",
) -> str:
    """The fit's description and deck records (``$`` comment lines, then MATID, ELEMENTS, MASS
    in the beam decks' layout: decks/beam_64.inp; or with ``records`` "modal" a MODAL card,
    :func:`modal_records`)."""
    k = [1.0e12, 1.0e12, 1.0e12]
    k[dof - 1] = values["stiffness"]
    lo, hi = fit.band
    q = QUANTITY_ORDER[quantity]
    lines = [
        f"$ x3dpd fit {source.path} ({source.label}): single-mode SDOF, {quantity} per unit of "
        "excitation",
        f"$   H(f) = (i w)^{q} R / (wn^2 - w^2 + 2 i zeta wn w) over {lo:.6g}-{hi:.6g} Hz "
        f"({fit.n_points} points)",
        f"$   fn   = {fit.fn:.8g} Hz  (+- {fit.fn_se:.2g}, one standard error)",
        f"$   zeta = {fit.zeta:.8g}  (+- {fit.zeta_se:.2g})",
        f"$   R    = {fit.residue:.8g}  (+- {fit.residue_se:.2g}) = force scale / effective mass",
        f"$   residual: RMS |H_fit - H| / |H| = {fit.residual:.4g}",
        f"$   force scale S = {values['force_scale']:.8g} (force per unit of the FRF's "
        "excitation), effective mass m = S / R",
        f"$   m = {values['mass']:.8g}, k = m wn^2 = {values['stiffness']:.8g}, "
        f"c = 2 zeta m wn = {values['damping']:.8g}",
    ]
    drive = f"USRFRC sine:node={node},dof={dof},amp={values['force_scale']:.8g},hz={fit.fn:.6g}"
    if records == "modal":
        return "\n".join(lines + modal_records(fit, values, node=node, dof=dof, drive=drive)) + "\n"
    lines += [
        f"$ The structure as the beam decks model it: node {node} with mass m on a spring k and "
        f"damper c to ground along {_AXES[dof - 1].lower()};",
        f"$ fix its other DOFs in BOUNDARY CONDITIONS and drive it with S times the excitation, "
        f"e.g. {drive}",
        "MATID",
        "$ MID TYPE MASS SCALE KX KY KZ C",
        f"   {mid} 1 1e-12 1.0 {k[0]:.10g} {k[1]:.10g} {k[2]:.10g} {values['damping']:.10g}",
        "END",
        "ELEMENTS",
        "$ ID MID NODE1 [NODE2]",
        f"   1 {mid} {node}",
        "END",
        "MASS",
        "$ NODE MASS IXX IYY IZZ",
        f"   {node} {values['mass']:.10g} 1e+20 1e+20 1e+20",
        "END",
    ]
    return "\n".join(lines) + "\n"


#: The fewest lines a band may hold (x3dpd.analysis.sdof_fit fits three parameters).
MIN_LINES = 5


def _enough_lines(measured: str, source: MeasuredFrf, band: tuple[float, float] | None) -> None:
    """An error naming the file when the band holds fewer than :data:`MIN_LINES` usable lines
    (above 0 Hz, H not 0), with how many it holds and how far apart the file's lines are."""
    f = source.frequency
    lo, hi = band if band is not None else (f[0], f[-1])
    usable = np.count_nonzero((f >= lo) & (f <= hi) & (f > 0) & (np.abs(source.h) > 0))
    if usable < MIN_LINES:
        where = f"--band {lo:g}:{hi:g} Hz" if band is not None else "the file"
        raise InputError(
            f"{measured}: {where} holds {usable} usable line(s) of the file's {f.size} "
            f"({float(np.median(np.diff(f))):.4g} Hz apart); a fit needs at least {MIN_LINES}: "
            "widen the band"
        )


def _measured_frf(measured: str, dataset: int, quantity: str | None, band_hz):
    """The ``dataset``-th FRF of the file ``measured`` and its response quantity (the file's,
    or ``quantity``), checked against ``band_hz`` (inside the data, enough lines in it)."""
    frfs = read_measured_frf(measured)
    if not 1 <= dataset <= len(frfs):
        raise InputError(f"{measured}: --dataset {dataset}: the file holds {len(frfs)} FRF(s)")
    source = frfs[dataset - 1]
    q = quantity or source.quantity
    if q is None:
        raise InputError(
            f"{measured}: the file does not say what the response is; give "
            "--quantity displacement|velocity|acceleration"
        )
    if q not in QUANTITY_ORDER:
        raise InputError(f"--quantity {q!r}: expected one of {', '.join(QUANTITY_ORDER)}")
    if band_hz is not None and (
        band_hz[1] > source.frequency[-1] or band_hz[0] < source.frequency[0]
    ):
        raise InputError(
            f"--band {band_hz[0]:g}:{band_hz[1]:g} Hz reaches outside the measured "
            f"data ({source.frequency[0]:g} .. {source.frequency[-1]:g} Hz) of "
            f"{measured}"
        )
    _enough_lines(measured, source, band_hz)
    return source, q


def fit_command(
    measured: str,
    *,
    out: str,
    band: str | None = None,
    quantity: str | None = None,
    dataset: int = 1,
    node: int = 9,
    dof: int = 1,
    mass: float | None = None,
    force_scale: float | None = None,
    records: str = "sdof",
    overwrite: bool = False,
    echo: Callable[[str], None] = print,
) -> SdofFit:
    """Fit the FRF of ``measured`` (a CSV, or the ``dataset``-th FRF of a UFF file) over
    ``band`` (default the whole file); write DIR/fit.txt and DIR/fit.png. ``records``: "sdof"
    (MATID, ELEMENTS, MASS) or "modal" (a MODAL card)."""
    from x3dpd._files import write_atomically

    if dof not in (1, 2, 3):
        raise InputError(f"--dof {dof}: the spring acts along x, y or z (1, 2, 3)")
    if records not in ("sdof", "modal"):
        raise InputError(f"--records {records!r}: expected sdof or modal")
    band_hz = parse_band(band)
    paths = output_paths(out, ("fit.txt", "fit.png"), overwrite)
    source, q = _measured_frf(measured, dataset, quantity, band_hz)
    try:
        fit = fit_sdof(source.frequency, source.h, order=QUANTITY_ORDER[q], band=band_hz)
    except InputError as exc:
        raise InputError(f"{measured}: {exc}") from None
    scale = 1.0 if force_scale is None else force_scale
    if mass is None and math.isfinite(scale) and scale * fit.residue < 0:
        raise InputError(
            f"{measured}: the FRF's sign is reversed (fitted R = {fit.residue:.4g}: drive "
            "and response in opposite directions, common in hammer tests); pass "
            f"--force-scale {-scale:g}"
        )
    values = fit.deck_values(mass=mass, force_scale=force_scale)
    text = fit_text(source, fit, values, node=node, dof=dof, quantity=q, records=records)
    f = source.frequency
    lo, hi = fit.band
    span = hi - lo
    view = (f >= lo - 0.25 * span) & (f <= hi + 0.25 * span)
    paths[0].parent.mkdir(parents=True, exist_ok=True)
    tmp = paths[1].with_name("." + paths[1].name + ".tmp.png")
    try:
        plot_fit(
            str(tmp),
            f[view],
            source.h[view],
            fit.model(f[view]),
            ylabel=source.unit or f"{q} unit",
            band=fit.band,
            title=f"{Path(measured).name}: fn {fit.fn:.5g} Hz, zeta {100 * fit.zeta:.4g} %",
        )
        write_atomically(paths[0], lambda fh: fh.write(text.encode()))
        tmp.replace(paths[1])
    finally:
        if tmp.exists():
            tmp.unlink()
    echo(
        f"fit {measured}: fn {fit.fn:.6g} Hz, zeta {fit.zeta:.5g}, m {values['mass']:.6g}, "
        f"k {values['stiffness']:.6g}, c {values['damping']:.6g} (force scale "
        f"{values['force_scale']:g}); residual {fit.residual:.3g}"
    )
    if not math.isfinite(fit.fn_se) or fit.residual > 0.2:
        echo("note: the residual is large: is the band around one mode only (--band LO:HI)?")
    if not lo <= fit.fn <= hi:
        echo(
            f"note: the fitted natural frequency {fit.fn:.6g} Hz lies outside the band "
            f"{lo:g}-{hi:g} Hz: the band holds no resonance and the fit extrapolates to one "
            "(its damping is then weakly determined); give a band around the peak"
        )
    echo(f"wrote {paths[0]} and {paths[1]}")
    return fit
