"""Figures of ``x3dpd design`` (docs/design.md): what a designer reads off a design study.

* :func:`plot_attenuation_vs_mass` -- peak attenuation (or peak amplitude) versus added mass,
  one line per particle material and size, one panel per drive level (Figures 45-48 condensed
  to one number per configuration); in an equal-mass study, versus the particle count;
* :func:`plot_damping_families` -- % zeta versus amplitude, one line per configuration
  coloured by its added mass (the report's damping surfaces, Figures 7, 8, 11-13, as line
  families), and the mean % zeta versus added mass.

The best configuration within the mass budget is starred; the budget is a dashed line. Plain
rows in (design.csv's), files out; matplotlib on the Agg backend.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence

import numpy as np

from x3dpd.analysis.design_plots import _pyplot, save_figure


def _family(row: Mapping) -> str:
    """A line's label: the particles' material and radius, and the contact stiffness scale
    when it is not 1 (the amount -- count, fill, cavities -- runs along the line)."""
    if not row.get("count"):
        return "no particles"
    out = f"{row.get('material') or 'deck material'}, R = {row['radius']:g}"
    scale = row.get("stiffness_scale")
    if scale not in (None, "") and float(scale) != 1.0:
        out += f", E x {float(scale):g}"
    return out


def _by_config(rows: Sequence[Mapping]) -> dict[str, list[Mapping]]:
    out: dict[str, list[Mapping]] = {}
    for r in rows:
        out.setdefault(r["config"], []).append(r)
    return out


def _budget(ax, budget: float | None) -> None:
    if budget is not None:
        ax.axvline(budget, color="k", ls="--", lw=1.0, label=f"mass budget {budget:.4g}")
        lo, hi = ax.get_xlim()
        if hi > budget:
            ax.axvspan(budget, hi, color="0.9", zorder=0)
            ax.set_xlim(lo, hi)


def _peak_interval_db(mine: Sequence[Mapping], drive) -> float:
    """The 95 % half-width [dB] of a configuration's peak attenuation at one drive: its peak
    point's amplitude interval, 20 / ln 10 x ci / X."""
    here = [r for r in mine if r["drive"] == drive]
    peak = max(here, key=lambda r: r["amplitude"])
    ci = float(peak.get("amplitude_ci", 0.0) or 0.0)
    return 20.0 / math.log(10.0) * ci / peak["amplitude"] if peak["amplitude"] > 0 else math.nan


# Over 80 lines: one figure: axes, series, the best's star and labels in the order they are drawn.
def plot_attenuation_vs_mass(
    png: str | os.PathLike,
    rows: Sequence[Mapping],
    budget: float | None = None,
    title: str = "",
    mass_unit: str = "",
    force_unit: str = "",
) -> str:
    """Peak attenuation vs the undamped baseline (else vs added mass; else the peak amplitude)
    against added mass, one panel per drive, a line per (material, radius), each point with its
    95 % interval. A dwell (one frequency per drive) shows the attenuation at its frequency."""
    plt = _pyplot()
    drives = sorted({r["drive"] for r in rows})
    dwell = all(len({r["frequency_hz"] for r in rows if r["drive"] == d}) == 1 for d in drives)
    what = (
        f"attenuation at {rows[0]['frequency_hz']:g} Hz" if dwell and rows else "peak attenuation"
    )
    quantity, label = "peak_attenuation_undamped_db", f"{what} vs undamped [dB]"
    if not any(math.isfinite(r[quantity]) for r in rows):
        quantity, label = "peak_attenuation_added_mass_db", f"{what} vs added mass [dB]"
    if not any(math.isfinite(r[quantity]) for r in rows):
        quantity, label = "peak_amplitude", "peak amplitude" if not dwell else "amplitude"
    masses = {r["added_mass"] for r in rows}
    # an equal-mass study (the report's particle-count study): against the count instead
    by_count = len({r["count"] for r in rows}) > 1 and max(masses) - min(masses) <= 1e-9 * max(
        masses
    )
    x_key = "count" if by_count else "added_mass"
    fig, axes = plt.subplots(1, len(drives), figsize=(5.4 * len(drives), 4.2), squeeze=False)
    for ax, drive in zip(axes[0], drives):
        per_config = {}
        for config, mine in _by_config(rows).items():
            here = [r for r in mine if r["drive"] == drive]
            if here:
                per_config[config] = (here[0], _peak_interval_db(mine, drive))
        best = [r for r, _ in per_config.values() if r.get("best")]
        if best:
            # under the points and their names: the star marks, the label names
            b = best[0]
            ax.plot(
                b[x_key],
                b[quantity],
                marker="*",
                ms=20,
                color="gold",
                mec="0.4",
                ls="none",
                label=f"best: {b['config']}",
                zorder=1,
            )
        families: dict[str, list] = {}
        for config, (r, ci) in per_config.items():
            family = "equal mass" if by_count else _family(r)
            families.setdefault(family, []).append((r[x_key], r[quantity], ci, config))
        for k, (name, pts) in enumerate(sorted(families.items())):
            pts.sort()
            x, y, ci = (np.array([p[j] for p in pts], float) for j in range(3))
            ax.plot(x, y, marker="o", color=f"C{k}", label=name, zorder=3)
            if quantity != "peak_amplitude" and np.isfinite(ci).any():
                ax.errorbar(
                    x,
                    y,
                    yerr=np.where(np.isfinite(ci), ci, 0.0),
                    fmt="none",
                    ecolor=f"C{k}",
                    capsize=2.5,
                    zorder=3,
                )
            for m, v, _, config in pts:
                ax.annotate(
                    config, (m, v), fontsize=6, xytext=(4, 6), textcoords="offset points", zorder=4
                )
        if by_count:
            ax.set_xscale("log")
            ax.set_xlabel(
                f"particle count (equal added mass {max(masses):.4g}"
                f"{f' {mass_unit}' if mass_unit else ''})"
            )
        else:
            _budget(ax, budget)
            ax.set_xlabel(f"added (particle) mass{f' [{mass_unit}]' if mass_unit else ''}")
        ax.set_ylabel(label)
        if quantity == "peak_amplitude":
            ax.set_yscale("log")
        ax.set_title(f"drive {drive:.5g}{f' {force_unit}' if force_unit else ''}", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    return save_figure(plt, fig, png, title)


def plot_damping_families(
    png: str | os.PathLike,
    rows: Sequence[Mapping],
    budget: float | None = None,
    title: str = "",
    mass_unit: str = "",
) -> str:
    """% zeta vs amplitude, a line per configuration coloured by added mass; beside it the
    mean % zeta vs added mass per (material, radius)."""
    plt = _pyplot()
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11.0, 4.2))
    configs = _by_config(rows)
    masses = [mine[0]["added_mass"] for mine in configs.values()]
    lo, hi = (min(masses), max(masses)) if masses else (0.0, 1.0)
    cmap = plt.get_cmap("viridis")
    norm = plt.Normalize(lo, hi if hi > lo else lo + 1.0)
    for config, mine in configs.items():
        best = bool(mine[0].get("best"))
        for drive in sorted({str(r["drive"]) for r in mine}):
            pts = [r for r in mine if str(r["drive"]) == drive]
            ax.plot(
                [r["amplitude_db"] for r in pts],
                [r["zeta_percent"] for r in pts],
                color=cmap(norm(mine[0]["added_mass"])),
                lw=3.0 if best else 1.2,
                label=f"best: {config}" if best and drive == str(pts[0]["drive"]) else None,
            )
    base = [r["baseline_zeta_percent"] for r in rows if math.isfinite(r["baseline_zeta_percent"])]
    if base:
        ax.axhline(base[0], color="k", ls=":", label=f"structure alone {base[0]:.3g} %")
    sm = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.colorbar(sm, ax=ax, label=f"added mass{f' [{mass_unit}]' if mass_unit else ''}")
    ax.set_xlabel("amplitude [dB re 1 g]")
    ax.set_ylabel("damping [% zeta]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    families: dict[str, list] = {}
    for config, mine in configs.items():
        families.setdefault(_family(mine[0]), []).append(
            (mine[0]["added_mass"], float(np.mean([r["zeta_percent"] for r in mine])), config)
        )
    for k, (name, pts) in enumerate(sorted(families.items())):
        pts.sort()
        ax2.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", color=f"C{k}", label=name)
    best = [mine[0] for mine in configs.values() if mine[0].get("best")]
    if best:
        ax2.plot(
            best[0]["added_mass"],
            best[0]["score"],
            marker="*",
            ms=18,
            color="gold",
            mec="k",
            ls="none",
            label=f"best: {best[0]['config']}",
            zorder=5,
        )
    _budget(ax2, budget)
    ax2.set_xlabel(f"added (particle) mass{f' [{mass_unit}]' if mass_unit else ''}")
    ax2.set_ylabel("mean damping [% zeta]")
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=7)
    return save_figure(plt, fig, png, title)
