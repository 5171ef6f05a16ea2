"""Figures of the design tools: sweep.png (Figures 45-48) and ringdown.png (Figure 6).

Both take plain rows and arrays, so they know nothing of how the numbers were computed.
matplotlib is imported lazily with the Agg backend.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence

import numpy as np


def _pyplot():
    """matplotlib.pyplot on the non-interactive Agg backend (imported on first use)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _finish(fig, ax, png, title: str) -> str:
    """Legend, title, save at 90 dpi, close."""
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=9)
    return save_figure(_pyplot(), fig, png)


def peak_attenuation_db(reference_peak: float, damped_peak: float) -> float:
    """Attenuation at the peak, 20 log10(reference peak / damped peak) [dB]."""
    return 20.0 * math.log10(reference_peak / damped_peak)


def attenuations(rows: Sequence[Mapping], curves: Mapping | None = None) -> list[dict]:
    """Peak attenuation of the deck against each baseline, per drive.

    The deck's peak is its largest amplitude over the swept points (any direction); a
    baseline's peak is the largest of its closed-form curve in ``curves`` when there is one
    (a lightly damped peak falls between grid points), else of its swept points.
    """
    curves = curves or {}
    out = []
    drives = sorted({r["drive"] for r in rows if r["config"] == "deck"})
    for drive in drives:
        deck = [r["amplitude"] for r in rows if r["config"] == "deck" and r["drive"] == drive]
        for config in ("undamped", "added-mass"):
            if (config, drive) in curves:
                ref = float(np.max(curves[(config, drive)][1]))
            else:
                ref_rows = [
                    r["amplitude"] for r in rows if r["config"] == config and r["drive"] == drive
                ]
                if not ref_rows:
                    continue
                ref = max(ref_rows)
            out.append(
                {
                    "drive": drive,
                    "baseline": config,
                    "baseline_peak": ref,
                    "deck_peak": max(deck),
                    "attenuation_db": peak_attenuation_db(ref, max(deck)),
                }
            )
    return out


def plot_sweep(
    png: str | os.PathLike,
    rows: Sequence[Mapping],
    curves: Mapping | None = None,
    title: str = "",
    units: str = "in",
    drive_label=None,
) -> str:
    """Amplitude versus frequency, one panel per drive: baselines and the damper overlaid, each
    damper point with its 95 % interval. ``drive_label(drive)``: how a panel's title names its
    drive, with its unit (default: the number)."""
    plt = _pyplot()
    curves = curves or {}
    drives = sorted({r["drive"] for r in rows})
    att = attenuations(rows, curves)
    fig, axes = plt.subplots(1, len(drives), figsize=(5.2 * len(drives), 4.0), squeeze=False)
    for ax, drive in zip(axes[0], drives):
        _sweep_axes(ax, rows, curves, drive, "amplitude", f"displacement amplitude [{units}]")
        lines = [
            f"{a['attenuation_db']:.1f} dB vs {a['baseline']}" for a in att if a["drive"] == drive
        ]
        if lines:
            ax.text(
                0.02,
                0.97,
                "peak attenuation\n" + "\n".join(lines),
                transform=ax.transAxes,
                va="top",
                fontsize=8,
            )
        label = drive_label(drive) if drive_label is not None else f"{drive:.5g}"
        ax.set_title(f"drive {label}", fontsize=9)
    return save_figure(plt, fig, png, title)


def plot_responses(
    png: str | os.PathLike,
    rows: Sequence[Mapping],
    responses,
    curves: Mapping,
    title: str = "",
    units: str = "in",
    force: str = "lbf",
    time: str = "s",
    base=None,
    drive_label=None,
) -> str:
    """Accelerance (acceleration amplitude / drive) versus frequency at each measured response
    (``--response``; a row of panels each, one panel per drive), baselines overlaid (``curves``:
    {(node, dof): {(config, drive): (f, X)}}). ``base(f, drive)``: a base drive's displacement
    amplitude U at frequencies ``f`` [Hz]; the panels then show the transmissibility X / U.
    ``drive_label(drive)``: how a panel's title names its drive (default: the number)."""
    plt = _pyplot()
    drives = sorted({r["drive"] for r in rows})
    fig, axes = plt.subplots(
        len(responses),
        len(drives),
        squeeze=False,
        figsize=(5.2 * len(drives), 4.0 * len(responses)),
    )
    for row_axes, (node, dof) in zip(axes, responses):
        measured = [
            {**r, **m}
            for r in rows
            for m in r.get("responses", ())
            if (m["response_node"], m["response_dof"]) == (node, dof)
        ]
        for ax, drive in zip(row_axes, drives):
            if base is None:
                _sweep_axes(
                    ax,
                    measured,
                    curves.get((node, dof), {}),
                    drive,
                    "accelerance",
                    f"accelerance [({units}/{time}^2) / {force}]",
                )
            else:
                _sweep_axes(
                    ax,
                    measured,
                    curves.get((node, dof), {}),
                    drive,
                    "transmissibility",
                    "transmissibility (acceleration / base's)",
                    base,
                )
            label = drive_label(drive) if drive_label is not None else f"{drive:.5g}"
            ax.set_title(f"node {node} dof {dof}, drive {label}", fontsize=9)
    return save_figure(plt, fig, png, title)


def save_figure(plt, fig, png: str | os.PathLike, suptitle: str = "") -> str:
    """Lay out, write (90 dpi) and close a figure; its title above all panels if given."""
    if suptitle:
        fig.suptitle(suptitle, fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=90)
    plt.close(fig)
    return str(png)


# Over 80 lines: one panel's layers (baselines, FRFs, points, labels) in drawing order.
def _sweep_axes(ax, rows, curves, drive: float, quantity: str, ylabel: str, base=None) -> None:
    """One panel: the baselines' curves and points, measured FRFs (``curves`` keys "measured
    ...", dashed) and the damper's points at one drive, as
    displacement ``amplitude``, ``accelerance`` (w^2 X / |F|) or ``transmissibility`` (X / U,
    ``base(f, drive)`` = U)."""
    styles = {"undamped": ("k", "--"), "added-mass": ("0.5", ":")}
    markers = {"": "o", "up": "^", "down": "v"}

    def y_of(f, amp):
        f, amp = np.asarray(f, float), np.asarray(amp, float)
        if quantity == "transmissibility":
            return amp / base(f, drive)
        return amp if quantity == "amplitude" else (2 * np.pi * f) ** 2 * amp / abs(drive)

    for config, (color, ls) in styles.items():
        if (config, drive) in curves:
            f, a = curves[(config, drive)]
            ax.plot(f, y_of(f, a), color=color, ls=ls, lw=1.2, label=f"{config} (closed form)")
        pts = sorted(
            (r["frequency_hz"], r["amplitude"])
            for r in rows
            if r["config"] == config and r["drive"] == drive and r.get("method") != "closed-form"
        )
        if pts:
            f, a = zip(*pts)
            ax.plot(f, y_of(f, a), color=color, ls=ls, marker=".", label=config)
    grey = 0
    for (config, d), (f, a) in curves.items():
        if d == drive and config.startswith("measured"):
            ax.plot(
                f,
                y_of(f, a),
                color=("C2", "C4", "C8")[grey % 3],
                ls=(0, (6, 2)),
                lw=1.0,
                label=config,
            )
            grey += 1
    for direction, marker in markers.items():
        pts = [
            r
            for r in rows
            if r["config"] == "deck" and r["drive"] == drive and r["direction"] == direction
        ]
        if not pts:
            continue
        pts.sort(key=lambda r: r["frequency_hz"])
        f = [r["frequency_hz"] for r in pts]
        a = [r["amplitude"] for r in pts]
        color = "C3" if direction != "down" else "C0"
        ax.plot(
            f,
            y_of(f, a),
            color=color,
            marker=marker,
            ms=5,
            label="damper" + (f" ({direction})" if direction else ""),
        )
        # each point's 95 % interval (amplitude_ci), where it has a finite one
        ci = np.array([r.get("amplitude_ci", 0.0) for r in pts], float)
        shown = np.isfinite(ci) & (ci > 0)
        if shown.any():
            fa, aa, ca = (np.asarray(v, float)[shown] for v in (f, a, ci))
            lo, hi = y_of(fa, aa - ca), y_of(fa, aa + ca)
            mid = y_of(fa, aa)
            ax.errorbar(
                fa,
                mid,
                yerr=[mid - lo, hi - mid],
                fmt="none",
                ecolor=color,
                elinewidth=1.0,
                capsize=2.5,
                label="95 % interval",
            )
        bad = [(r["frequency_hz"], r["amplitude"]) for r in pts if not r["converged"]]
        if bad:
            bf, ba = zip(*bad)
            ax.plot(bf, y_of(bf, ba), ls="none", marker="x", color="k", ms=8, label="not converged")
    ax.set_yscale("log")
    ax.set_xlabel("drive frequency [Hz]")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="best")


def plot_ringdown(
    png: str | os.PathLike, series: Mapping[str, Mapping[str, np.ndarray]], title: str = ""
) -> str:
    """% zeta versus amplitude in dB re 1 g (Figure 6, right), one line per series (measured
    ones, named ``measured ...``, dashed black), shaded over each level's 95 % interval
    (``zeta_ci_percent``) where the series has one."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 4.0))
    for k, (name, cols) in enumerate(series.items()):
        style = (
            {"color": "k", "ls": "--"}
            if name.startswith("measured")
            else {"color": "C3" if k == 0 else "C0"}
        )
        db, zeta = np.asarray(cols["amplitude_db"]), 100.0 * np.asarray(cols["zeta"])
        ax.plot(db, zeta, lw=1.5, label=name, **style)
        ci = np.asarray(cols.get("zeta_ci_percent", np.full(db.shape, np.nan)), float)
        if np.isfinite(ci).any():
            ax.fill_between(db, zeta - ci, zeta + ci, color=style["color"], alpha=0.2, lw=0)
    ax.set_xlabel("amplitude [dB re 1 g]")
    ax.set_ylabel("damping [% zeta]")
    ax.grid(True, alpha=0.3)
    return _finish(fig, ax, png, title)


def plot_configurations(
    png: str | os.PathLike,
    series: Mapping[str, Sequence[Mapping]],
    curves: Mapping[str, tuple[np.ndarray, np.ndarray]],
    title: str = "",
    units: str = "in",
) -> str:
    """One drive level, several designs (Figures 45-48): closed-form baselines as lines,
    each damper's swept points as markers joined by lines, amplitude on a log scale.

    ``series`` maps a label to its rows (one direction, one drive); ``curves`` a baseline
    label to (f, X).
    """
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for (label, (f, a)), ls in zip(curves.items(), ("--", ":", "-.")):
        ax.plot(f, a, color="k", ls=ls, lw=1.2, label=label)
    for k, (label, rows) in enumerate(series.items()):
        pts = sorted((r["frequency_hz"], r["amplitude"], bool(r["converged"])) for r in rows)
        if not pts:
            continue
        f, a, ok = zip(*pts)
        ax.plot(f, a, color=f"C{k}", marker="o", ms=4, lw=1.2, label=label)
        bad = [(x, y) for x, y, c in pts if not c]
        if bad:
            ax.plot(*zip(*bad), ls="none", marker="x", color="k", ms=8)
    ax.set_yscale("log")
    ax.set_xlabel("drive frequency [Hz]")
    ax.set_ylabel(f"displacement amplitude [{units}]")
    ax.grid(True, which="both", alpha=0.3)
    return _finish(fig, ax, png, title)
