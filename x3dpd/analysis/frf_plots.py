"""Figures of the test-engineer tools: frf.png (the report's Figs 58-63: FRF magnitude in dB
over a linear frequency axis, here with phase and coherence below), spectrum.png (Fig. 10) and
fit.png (a measured FRF and its single-mode fit), modal_fit.png (a set of FRFs, their multi-mode
fit and its stabilisation diagram).

They take plain arrays and labels and know nothing of where the numbers came from.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from x3dpd.analysis.design_plots import _pyplot, save_figure


@dataclass(frozen=True)
class Curve:
    """One FRF on a plot: ``h`` complex at ``frequency`` [Hz]; optional ``h2``, ``coherence`` and
    confidence radius ``r95``; ``measured`` curves are drawn dashed in black and grey,
    ``baseline`` curves (a closed form) dash-dotted."""

    label: str
    frequency: np.ndarray
    h: np.ndarray
    h2: np.ndarray | None = None
    coherence: np.ndarray | None = None
    r95: np.ndarray | None = None
    measured: bool = False
    baseline: bool = False


def phase_degrees(h) -> np.ndarray:
    """The phase of a complex FRF over increasing frequency [deg], unwrapped (no jump of 360
    deg where it passes +/-180 deg, as an accelerance does below resonance) and shifted by whole
    turns so that its mean lies within (-180, 180]."""
    phase = np.degrees(np.unwrap(np.angle(np.asarray(h, dtype=complex))))
    if phase.size:
        phase -= 360.0 * np.round(np.mean(phase) / 360.0)
    return phase


def _db(x) -> np.ndarray:
    with np.errstate(divide="ignore"):
        return 20.0 * np.log10(np.abs(x))


def _style(k: int, curve: Curve, n_measured: list[int]) -> dict:
    if curve.measured:
        n_measured[0] += 1
        return {"color": ("k", "0.45", "0.7")[(n_measured[0] - 1) % 3], "ls": "--", "lw": 1.2}
    return {"color": f"C{k % 10}", "ls": "-." if curve.baseline else "-", "lw": 1.3}


def plot_frf(
    png: str | os.PathLike,
    curves: Sequence[Curve],
    *,
    ylabel: str,
    band: tuple[float, float] | None = None,
    title: str = "",
) -> str:
    """Magnitude [dB re 1 unit], phase [deg] and coherence of each curve over frequency.

    H1 is drawn solid, H2 dotted in the same colour, the 95 % confidence band of H1 shaded (when
    given); measured curves dashed.
    """
    plt = _pyplot()
    fig, (ax_m, ax_p, ax_c) = plt.subplots(
        3, 1, figsize=(7.0, 7.5), sharex=True, gridspec_kw={"height_ratios": [3, 1.3, 1]}
    )
    measured_count = [0]
    k_sim = 0
    for curve in curves:
        style = _style(k_sim, curve, measured_count)
        if not curve.measured:
            k_sim += 1
        f = curve.frequency
        ax_m.plot(f, _db(curve.h), label=curve.label, **style)
        if curve.h2 is not None:
            ax_m.plot(f, _db(curve.h2), color=style["color"], ls=":", lw=0.9)
        if curve.r95 is not None:
            mag = np.abs(curve.h)
            lo = np.maximum(mag - curve.r95, mag * 1e-3)
            ax_m.fill_between(
                f, _db(lo), _db(mag + curve.r95), color=style["color"], alpha=0.2, lw=0
            )
        ax_p.plot(f, phase_degrees(curve.h), **style)
        if curve.coherence is not None:
            ax_c.plot(f, curve.coherence, **style)
    ax_m.set_ylabel(f"|H| [dB re 1 {ylabel}]")
    ax_p.set_ylabel("phase [deg]")
    ax_p.set_yticks([-180, -90, 0, 90, 180])
    ax_c.set_ylabel("coherence")
    ax_c.set_ylim(0.0, 1.05)
    ax_c.set_xlabel("frequency [Hz]")
    if band is not None:
        ax_c.set_xlim(*band)
    for ax in (ax_m, ax_p, ax_c):
        ax.grid(True, alpha=0.3)
    ax_m.legend(fontsize=8)
    if title:
        ax_m.set_title(title, fontsize=9)
    return save_figure(plt, fig, png)


def plot_spectrum(
    png: str | os.PathLike,
    curves: Sequence[tuple[str, np.ndarray, np.ndarray]],
    *,
    ylabel: str,
    band: tuple[float, float] | None = None,
    title: str = "",
) -> str:
    """Spectra ``(label, frequency, values)`` on a log scale over linear frequency (Fig. 10)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.0, 4.0))
    for k, (label, f, v) in enumerate(curves):
        ax.semilogy(f, v, color=f"C{k % 10}", lw=1.1, label=label)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel(ylabel)
    if band is not None:
        ax.set_xlim(*band)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=9)
    return save_figure(plt, fig, png)


def plot_fit(
    png: str | os.PathLike,
    frequency,
    measured,
    fitted,
    *,
    ylabel: str,
    band: tuple[float, float],
    title: str = "",
) -> str:
    """A measured FRF (markers) and the fitted model (line): magnitude in dB and phase."""
    plt = _pyplot()
    fig, (ax_m, ax_p) = plt.subplots(
        2, 1, figsize=(6.5, 5.5), sharex=True, gridspec_kw={"height_ratios": [2, 1]}
    )
    f = np.asarray(frequency)
    ax_m.plot(f, _db(measured), "o", ms=2.5, color="0.35", label="measured")
    ax_m.plot(f, _db(fitted), color="C3", lw=1.4, label="SDOF fit")
    ax_p.plot(f, phase_degrees(measured), "o", ms=2.5, color="0.35")
    ax_p.plot(f, phase_degrees(fitted), color="C3", lw=1.4)
    for ax in (ax_m, ax_p):
        ax.axvspan(*band, color="C0", alpha=0.06)
        ax.grid(True, alpha=0.3)
    ax_m.set_ylabel(f"|H| [dB re 1 {ylabel}]")
    ax_p.set_ylabel("phase [deg]")
    ax_p.set_yticks([-180, -90, 0, 90, 180])
    ax_p.set_xlabel("frequency [Hz]")
    ax_m.legend(fontsize=8)
    if title:
        ax_m.set_title(title, fontsize=9)
    return save_figure(plt, fig, png)


def plot_modal_fit(
    png: str | os.PathLike,
    frequency,
    measured,
    fitted,
    *,
    labels: Sequence[str],
    ylabel: str,
    band: tuple[float, float],
    stabilisation: tuple[Sequence[int], Sequence, Sequence],
    modes,
    title: str = "",
) -> str:
    """A multi-mode fit: each measured FRF (markers) and its synthesis from the fitted modes
    (line) in dB, and below the stabilisation diagram -- the physical LSCF poles per order
    (``stabilisation``: orders, each order's pole frequencies and stable flags; stable filled),
    the fitted ``modes`` [Hz] as vertical lines."""
    plt = _pyplot()
    fig, (ax_m, ax_s) = plt.subplots(
        2, 1, figsize=(7.0, 6.5), sharex=True, gridspec_kw={"height_ratios": [3, 2]}
    )
    f = np.asarray(frequency)
    for k, (h, model) in enumerate(zip(measured, fitted)):
        color = f"C{k % 10}"
        ax_m.plot(f, _db(h), "o", ms=2.0, color=color, alpha=0.6)
        ax_m.plot(f, _db(model), color=color, lw=1.1, label=labels[k])
    orders, freqs, stable = stabilisation
    for order, fo, so in zip(orders, freqs, stable):
        fo, so = np.asarray(fo), np.asarray(so, dtype=bool)
        ax_s.plot(fo[~so], np.full((~so).sum(), order), "o", ms=3, mfc="none", color="0.6")
        ax_s.plot(fo[so], np.full(so.sum(), order), "o", ms=3, color="C3")
    for fn in modes:
        for ax in (ax_m, ax_s):
            ax.axvline(fn, color="k", lw=0.6, ls=":")
    for ax in (ax_m, ax_s):
        ax.set_xlim(*band)
        ax.grid(True, alpha=0.3)
    ax_m.set_ylabel(f"|H| [dB re 1 {ylabel}]")
    ax_s.set_ylabel("LSCF order (filled: stable)")
    ax_s.set_xlabel("frequency [Hz]")
    ax_m.legend(fontsize=7, ncol=2, title="measured (dots), fitted (lines)", title_fontsize=7)
    if title:
        ax_m.set_title(title, fontsize=9)
    return save_figure(plt, fig, png)
