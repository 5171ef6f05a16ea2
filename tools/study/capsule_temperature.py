"""Figure 20 at temperature: the capsule_wc7 design's ring-downs pooled by temperature.

    x3dpd design designs/capsule_wc7_temperature.toml --out capsule_wc7_temperature --workers 2
    python tools/study/capsule_temperature.py capsule_wc7_temperature [--figure PNG]

Reads DIR/design.csv (the design's rows: % zeta at 25 amplitudes per ring-down), takes the
configurations within 0.5 F of each nominal temperature (-94, 70, 365, 850 F) as replicas of it
(the design runs each at T and T +- 0.1, 0.2 F: the same temperature, other draws of the spheres'
chaotic motion), and prints, per temperature: the bores' clearance along the axis and across
at T (``x3dpd check decks/capsule_wc7.inp --temperature T``), the peak % zeta and where it
lies, and % zeta at 5, 10, 15, 20 and 25 dB re 1 g (mean +- standard deviation over the
replicas, each ring-down linear in dB between its points). Then a one-way analysis of variance
of each replica's mean % zeta over 2-25 dB: does the temperature explain more of the spread
than the draws do? The figure (default docs/img/capsule_wc7_temperature.png): % zeta against
amplitude, each temperature's mean and its +- 1 standard deviation band where at least three
of its runs reach, beside the beam's own zeta (the design's baseline_zeta_percent).
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

import warnings

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

NOMINAL = (-94.0, 70.0, 365.0, 850.0)
AT_DB = (5.0, 10.0, 15.0, 20.0, 25.0)
BAND = (2.0, 25.0)
GRID = np.arange(-10.0, 28.01, 0.5)
#: The figure draws a temperature's mean where at least this many of its runs reach.
MIN_RUNS = 3


def replicas(design_csv: Path) -> tuple[dict[float, list[np.ndarray]], float]:
    """{nominal T: [zeta % on GRID (NaN outside the ring-down's range), ...]}, the baseline."""
    rows = list(csv.DictReader(design_csv.open()))
    out: dict[float, list[np.ndarray]] = {t: [] for t in NOMINAL}
    for config in dict.fromkeys(r["config"] for r in rows):
        mine = [r for r in rows if r["config"] == config]
        t = float(mine[0]["temperature"])
        nominal = min(NOMINAL, key=lambda n: abs(n - t))
        if abs(nominal - t) > 0.5:
            continue
        a = np.array([float(r["amplitude_db"]) for r in mine])
        z = np.array([float(r["zeta_percent"]) for r in mine])
        order = np.argsort(a)
        a, z = a[order], z[order]
        curve = np.interp(GRID, a, z, left=np.nan, right=np.nan)
        out[nominal].append(curve)
    return out, float(rows[0]["baseline_zeta_percent"])


def clearances(t: float) -> dict[str, float]:
    """The bores' clearances at ``t`` F (x3dpd check's), set 1's."""
    import x3dpd.api

    model = x3dpd.api.build(ROOT / "decks" / "capsule_wc7.inp", temperature=f"{t:g}F")
    return {c.what: c.operating for c in model.temperature.clearances if c.set_id == 1}


def _band_means(curves: list[np.ndarray]) -> np.ndarray:
    keep = (GRID >= BAND[0]) & (GRID <= BAND[1])
    return np.array([np.nanmean(c[keep]) for c in curves])


def table(data: dict[float, list[np.ndarray]]) -> list[str]:
    head = (
        "| T [°F] | clearance along / across [in] | runs | peak % ζ (at dB) | "
        + " | ".join(f"% ζ at {a:g} dB" for a in AT_DB)
        + f" | mean % ζ, {BAND[0]:g}-{BAND[1]:g} dB |"
    )
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for t, curves in data.items():
        stack = np.array(curves)
        peaks = np.nanmax(stack, axis=1)
        where = GRID[np.nanargmax(stack, axis=1)]
        gaps = clearances(t)
        cells = [
            f"{t:g}",
            f"{gaps['cylinder along its axis']:.6f} / {gaps['cylinder across']:.6f}",
            f"{len(curves)}",
            f"{peaks.mean():.1f} ± {peaks.std(ddof=1):.1f} ({where.mean():+.0f})",
        ]
        for a in AT_DB:
            col = stack[:, int(np.argmin(abs(GRID - a)))]
            cells.append(f"{np.nanmean(col):.2f} ± {np.nanstd(col, ddof=1):.2f}")
        band = _band_means(curves)
        cells.append(f"{band.mean():.2f} ± {band.std(ddof=1):.2f}")
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def anova(data: dict[float, list[np.ndarray]]) -> str:
    from scipy.stats import f_oneway

    groups = [_band_means(c) for c in data.values()]
    f, p = f_oneway(*groups)
    return (
        f"one-way ANOVA of the replicas' mean % zeta over {BAND[0]:g}-{BAND[1]:g} dB against "
        f"temperature: F = {f:.2f}, p = {p:.2f}"
    )


def figure(data: dict[float, list[np.ndarray]], baseline: float, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.0, 4.2))
    for k, (t, curves) in enumerate(data.items()):
        stack = np.array(curves)
        enough = np.sum(np.isfinite(stack), axis=0) >= MIN_RUNS
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            mean, sd = np.nanmean(stack, axis=0), np.nanstd(stack, axis=0, ddof=1)
        mean, sd = np.where(enough, mean, np.nan), np.where(enough, sd, np.nan)
        ax.plot(GRID, mean, color=f"C{k}", label=f"{t:g} °F ({len(curves)} runs)")
        ax.fill_between(GRID, mean - sd, mean + sd, color=f"C{k}", alpha=0.15, lw=0)
    ax.axhline(baseline, color="k", ls=":", label=f"beam alone {baseline:.3g} %")
    ax.set_xlabel("amplitude [dB re 1 g]")
    ax.set_ylabel("damping [% zeta]")
    ax.set_title("capsule_wc7: seven 1/8 in WC spheres in titanium bores, ring-downs", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path, help="the design's output folder (design.csv)")
    ap.add_argument(
        "--figure", type=Path, default=ROOT / "docs" / "img" / "capsule_wc7_temperature.png"
    )
    args = ap.parse_args(argv)
    data, baseline = replicas(args.out / "design.csv")
    print("\n".join(table(data)))
    print(anova(data))
    figure(data, baseline, args.figure)
    print(f"wrote {args.figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
