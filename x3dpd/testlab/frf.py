"""``x3dpd frf`` and ``x3dpd spectrum``: frequency response functions and response spectra of runs,
with measured FRFs overlaid (docs/testing-like-a-test-engineer.md).

The estimation is :mod:`x3dpd.analysis.frf`; the drive and responses come from
:mod:`x3dpd.testlab.trace_signals`. Every input is read and checked, and every number computed,
before anything is written: bad input leaves DIR untouched.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from x3dpd.api.figures import Curve, plot_frf, plot_spectrum
from x3dpd.api.measurements import (
    QUANTITY_ORDER,
    amplitude_spectrum,
    check_window,
    difference_gain,
    estimate_frf,
    power_spectrum,
    read_measured_frf,
)
from x3dpd.design.spec import parse_point
from x3dpd.errors import InputError
from x3dpd.testlab.outputs import output_paths, write_pair
from x3dpd.testlab.trace_signals import (
    check_band,
    drive_history,
    parse_band,
    period_notes,
    read_record,
    response_history,
    response_unit,
    sampling_rate,
    welch_options,
)


def _window(t: np.ndarray, t_from: float | None, path: str) -> np.ndarray:
    keep = t >= (t_from if t_from is not None else -math.inf)
    if np.count_nonzero(keep) < 16:
        raise InputError(f"{path}: fewer than 16 output times from t = {t_from:g} s on")
    return keep


def _in_band(f: np.ndarray, band: tuple[float, float] | None, df: float) -> np.ndarray:
    """The frequency lines in ``band`` (all without one); an error when there is none."""
    if band is None:
        return np.ones(f.size, bool)
    sel = (f >= band[0]) & (f <= band[1])
    if not sel.any():
        raise InputError(
            f"--band {band[0]:g}:{band[1]:g} Hz holds no frequency line (lines "
            f"every {df:.4g} Hz); widen it or use longer segments"
        )
    return sel


def run_labels(paths: Sequence[str]) -> list[str]:
    """One label per trace: its name without ``.trace.txt``, with its folder when two names
    clash, and a number when even those do."""

    def stem(path: Path) -> str:
        return path.name.removesuffix(".txt").removesuffix(".trace")

    names = [stem(Path(p)) for p in paths]
    if len(set(names)) < len(names):
        names = [f"{Path(p).parent.name}/{stem(Path(p))}" for p in paths]
    seen: dict[str, int] = {}
    out = []
    for name in names:
        seen[name] = seen.get(name, 0) + 1
        out.append(name if names.count(name) == 1 else f"{name} #{seen[name]}")
    return out


def measured_curves(
    files: Sequence[str], quantity: str, scale: float, band: tuple[float, float] | None
) -> list[Curve]:
    """Measured FRFs in the plotted quantity: times (i w)^(q - q_measured) when the file says
    what it measured, and times ``scale`` (a unit conversion)."""
    curves = []
    for path in files:
        for m in read_measured_frf(path):
            h = m.h * scale
            if m.quantity is not None:
                h = h * (2j * np.pi * m.frequency) ** (
                    QUANTITY_ORDER[quantity] - QUANTITY_ORDER[m.quantity]
                )
            keep = (
                np.ones(m.frequency.size, bool)
                if band is None
                else ((m.frequency >= band[0]) & (m.frequency <= band[1]))
            )
            label = f"measured {m.label}" if not m.label.startswith("measured") else m.label
            curves.append(
                Curve(
                    label,
                    m.frequency[keep],
                    h[keep],
                    coherence=None if m.coherence is None else m.coherence[keep],
                    measured=True,
                )
            )
    return curves


def frf_command(
    traces: Sequence[str],
    *,
    drive: str,
    responses: Sequence[str],
    out: str,
    quantity: str = "acceleration",
    window: str = "hann",
    segment: float | None = None,
    nperseg: int | None = None,
    overlap: float = 0.5,
    band: str | None = None,
    t_from: float | None = None,
    measured: Sequence[str] = (),
    measured_scale: float = 1.0,
    baselines: Sequence[str] = (),
    deck: str | None = None,
    overwrite: bool = False,
    echo: Callable[[str], None] = print,
    progress: Callable[[str, int, int], None] | None = None,
) -> list[dict]:
    """``x3dpd frf``: H1, H2 and coherence of every response of every trace against the drive;
    DIR/frf.csv (one row per run, response and frequency) and DIR/frf.png. Returns the rows.
    ``baselines`` (undamped, added-mass): their closed-form FRFs for the first trace's deck (or
    ``deck``) overlaid too (x3dpd.testlab.frf_baselines) and written at the run's frequency
    lines to DIR/baselines.csv (baseline, response, frequency_hz, re, im, mag, phase_deg).
    Every option and measured file is checked before a trace is read; ``progress(path,
    bytes_read, size)`` follows the reading of each trace."""
    if not traces:
        raise InputError("give at least one TRACE")
    if not responses:
        raise InputError("give at least one --response NODE:DOF")
    d_node, d_dof = parse_point(drive, "--drive")
    points = [parse_point(r, "--response") for r in responses]
    band_hz = parse_band(band)
    if quantity not in QUANTITY_ORDER:
        raise InputError(f"--quantity {quantity!r}: expected one of {', '.join(QUANTITY_ORDER)}")
    check_window(window)
    paths = output_paths(
        out, ("frf.csv", "frf.png") + (("baselines.csv",) if baselines else ()), overwrite
    )
    overlays = measured_curves(measured, quantity, measured_scale, band_hz)
    welch = dict(segment=segment, nperseg=nperseg, overlap=overlap, window=window)
    curves, rows, units = [], [], set()
    first = None
    for path, run in zip(traces, run_labels(traces)):
        trace = read_record(path, echo, progress)
        est, kind, trace_units, lines, sel = _trace_frf(
            trace, path, (d_node, d_dof), points, quantity, band_hz, t_from, welch, echo
        )
        first = first or (trace, path, kind, lines[sel])
        units.update(trace_units)
        labelled = len(traces) > 1 or bool(baselines)
        with_r95 = len(traces) * len(points) == 1
        for k, point in enumerate(points):
            curves.append(_curve(est, k, point, sel, run if labelled else None, with_r95))
            rows += _frf_rows(est, k, point, sel, run)
    base_rows: list[dict] = []
    if baselines:
        from x3dpd.testlab.frf_baselines import baseline_curves

        curves += baseline_curves(
            first, deck, baselines, (d_node, d_dof), points, quantity, base_rows
        )
    unit = units.pop() if len(units) == 1 else "unit"
    head = [f"# quantity: {quantity}", f"# unit: {unit}", f"# drive: node {d_node} dof {d_dof}"]
    title = ", ".join(Path(p).name for p in traces)
    write_pair(
        paths[:2],
        _csv_text(head, rows),
        lambda png: plot_frf(png, curves + overlays, ylabel=unit, band=band_hz, title=title),
    )
    if base_rows:
        from x3dpd._files import write_atomically

        text = _csv_text(head[:2], base_rows)
        write_atomically(paths[2], lambda fh: fh.write(text.encode()))
    echo(f"wrote {', '.join(map(str, paths))}")
    return rows


def _trace_frf(trace, path, drive, points, quantity, band_hz, t_from, welch, echo):
    """One trace's FRF estimate (x3dpd.analysis.frf) of every response against the drive:
    (each response's estimate, its differenced rate divided out; the drive's kind; each
    response's unit; the frequency lines; the lines in the band)."""
    fs = sampling_rate(trace, path)
    check_band(band_hz, fs, path)
    keep = _window(trace.time, t_from, path)
    source = drive_history(trace, drive[0], drive[1], path)
    for note in (*source.notes, *period_notes(source, fs)):
        echo(f"note: {path}: {note}")
    signals, differenced = [], []
    for node, dof in points:
        y, diff = response_history(trace, node, dof, quantity, path)
        signals.append(y[keep])
        differenced.append(diff)
    window = welch["window"]
    nps, nov = welch_options(
        fs,
        int(np.count_nonzero(keep)),
        segment=welch["segment"],
        nperseg=welch["nperseg"],
        overlap=welch["overlap"],
    )
    est = estimate_frf(
        source.values[keep], np.array(signals), fs, nperseg=nps, noverlap=nov, window=window
    )
    echo(
        f"{path}: drive {source.kind} on node {drive[0]} dof {drive[1]} "
        f"({'; '.join(source.specs)}), {fs:.6g} samples/s, {est.n_segments} segments of "
        f"{nps} ({nps / fs:.4g} s, resolution {fs / nps:.4g} Hz), {window} window, "
        f"{nov} overlap, {est.n_effective:.1f} equivalent averages"
    )
    f = est.frequency
    sel = _in_band(f, band_hz, fs / nps)
    ests = [est.divided(difference_gain(f, fs)) if d else est for d in differenced]
    units = [f"({response_unit(trace, quantity, dof)})/({source.unit})" for _, dof in points]
    return ests, source.kind, units, f, sel


def _curve(ests, k: int, point, sel, run: str | None, with_r95: bool) -> Curve:
    """Response ``k``'s H1, H2 and coherence in the band, as plotted (with its 95 % radius when
    it is the only curve)."""
    e = ests[k]
    label = f"{run} {point[0]}:{point[1]}" if run is not None else f"node {point[0]} dof {point[1]}"
    r95 = _r95(e, k)
    return Curve(
        label,
        e.frequency[sel],
        e.h1[k][sel],
        e.h2[k][sel],
        e.coherence[k][sel],
        r95[sel] if with_r95 else None,
    )


def _r95(e, k: int) -> np.ndarray:
    """Response ``k``'s 95 % confidence radius of H1 (NaN with two equivalent averages or
    fewer)."""
    f = e.frequency
    return e.confidence_radius()[k] if e.n_effective > 2 else np.full(f.size, np.nan)


def _frf_rows(ests, k: int, point, sel, run: str) -> list[dict]:
    """DIR/frf.csv's rows of response ``k`` in the band."""
    e = ests[k]
    f, h1, h2, coh, r95 = e.frequency, e.h1[k], e.h2[k], e.coherence[k], _r95(e, k)
    return [
        {
            "run": run,
            "response": f"{point[0]}:{point[1]}",
            "frequency_hz": f[j],
            "h1_re": h1[j].real,
            "h1_im": h1[j].imag,
            "h1_mag": abs(h1[j]),
            "h1_phase_deg": math.degrees(np.angle(h1[j])),
            "h2_re": h2[j].real,
            "h2_im": h2[j].imag,
            "coherence": coh[j],
            "h1_r95": r95[j],
        }
        for j in np.flatnonzero(sel)
    ]


def _csv_text(head: list[str], rows: list[dict]) -> str:
    """A CSV with comment lines ``head``, its columns the rows' keys, numbers as repr."""
    names = list(rows[0]) if rows else []
    lines = head + [",".join(names)]
    lines += [
        ",".join(str(v) if isinstance(v, str) else repr(float(v)) for v in r.values()) for r in rows
    ]
    return "\n".join(lines) + "\n"


def spectrum_command(
    traces: Sequence[str],
    *,
    node: int,
    dof: int,
    out: str,
    quantity: str = "acceleration",
    method: str = "fft",
    window: str = "hann",
    segment: float | None = None,
    nperseg: int | None = None,
    overlap: float = 0.5,
    band: str | None = None,
    t_from: float | None = None,
    overwrite: bool = False,
    echo: Callable[[str], None] = print,
    progress: Callable[[str, int, int], None] | None = None,
) -> list[dict]:
    """``x3dpd spectrum``: the amplitude spectrum (one FFT of the record, ``fft``) or the PSD
    (Welch, ``welch``) of a node's response; DIR/spectrum.csv and DIR/spectrum.png.
    ``progress`` as :func:`frf_command`'s."""
    if method not in ("fft", "welch"):
        raise InputError(f"--method {method!r}: expected fft or welch")
    if not traces:
        raise InputError("give at least one TRACE")
    band_hz = parse_band(band)
    check_window(window)
    paths = output_paths(out, ("spectrum.csv", "spectrum.png"), overwrite)
    curves, rows, unit = [], [], ""
    for path, run in zip(traces, run_labels(traces)):
        trace = read_record(path, echo, progress)
        fs = sampling_rate(trace, path)
        check_band(band_hz, fs, path)
        keep = _window(trace.time, t_from, path)
        y, diff = response_history(trace, node, dof, quantity, path)
        y = y[keep]
        if method == "fft":
            f, v = amplitude_spectrum(y, fs, window=window)
            v = v / difference_gain(f, fs) if diff else v
        else:
            nps, nov = welch_options(fs, y.size, segment=segment, nperseg=nperseg, overlap=overlap)
            f, v = power_spectrum(y, fs, nperseg=nps, noverlap=nov, window=window)
            v = v / difference_gain(f, fs) ** 2 if diff else v
        unit = response_unit(trace, quantity, dof)
        sel = _in_band(f, band_hz, f[1] - f[0])
        curves.append(
            (
                run,
                f[sel][1:] if f[sel][0] == 0 else f[sel],
                v[sel][1:] if f[sel][0] == 0 else v[sel],
            )
        )
        column = "amplitude" if method == "fft" else "psd"
        rows += [{"run": run, "frequency_hz": f[j], column: v[j]} for j in np.flatnonzero(sel)]
        echo(f"{path}: node {node} dof {dof} {quantity}, {y.size} samples at {fs:.6g}/s, {method}")
    ylabel = f"amplitude [{unit}]" if method == "fft" else f"PSD [({unit})^2/Hz]"
    head = [
        f"# quantity: {quantity}",
        f"# unit: {unit}" if method == "fft" else f"# unit: ({unit})^2/Hz",
    ]
    write_pair(
        paths,
        _csv_text(head, rows),
        lambda png: plot_spectrum(
            png, curves, ylabel=ylabel, band=band_hz, title=f"node {node} dof {dof}"
        ),
    )
    echo(f"wrote {paths[0]} and {paths[1]}")
    return rows
