#!/usr/bin/env python3
"""Figures 71-72 of the report from a run of designs/mip_apparatus.toml: the apparatus's
velocity response at 800 lbf with each MIP damper against its own mode at that level (Table 6),
and the table of peak velocity reduction.

    x3dpd design designs/mip_apparatus.toml --out mip_apparatus --workers 2
    python tools/study/mip_report.py mip_apparatus

Reads each configuration's sweep.csv (OUT/configs/NAME/sweep/sweep.csv: the damper's points and
the closed-form baselines at the same frequencies); writes OUT/mip_velocity.png (a panel per
sphere size: the undamped level's mode and each shim's response, velocity in ips rms = the
fundamental velocity amplitude / sqrt 2, as the report's plots) and OUT/mip_reduction.csv, and
prints the table: the peak over the swept band, with and without the damper, and the reduction.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path


def read_rows(out: Path) -> dict[str, list[dict]]:
    """{configuration: its sweep.csv rows}."""
    found = {}
    for path in sorted(out.glob("configs/*/sweep/sweep.csv")):
        with path.open() as f:
            found[path.parts[-3]] = list(csv.DictReader(f))
    return found


def curve(rows: list[dict], config: str) -> tuple[list[float], list[float]]:
    """(frequencies [Hz], velocity [in/s rms]) of ``config`` (deck, undamped, added-mass)."""
    mine = sorted(
        (float(r["frequency_hz"]), float(r["velocity"]) / math.sqrt(2.0))
        for r in rows
        if r["config"] == config and r["response_node"] in ("", "1")
    )
    return [f for f, _ in mine], [v for _, v in mine]


def reductions(found: dict[str, list[dict]]) -> list[dict]:
    out = []
    for name, rows in found.items():
        f, damped = curve(rows, "deck")
        _, bare = curve(rows, "undamped")
        k = max(range(len(damped)), key=damped.__getitem__)
        out.append(
            {
                "config": name,
                "peak_undamped_ips_rms": max(bare),
                "peak_damped_ips_rms": damped[k],
                "peak_damped_hz": f[k],
                "reduction_percent": 100.0 * (1.0 - damped[k] / max(bare)),
                "converged": all(r["converged"] == "1" for r in rows if r["config"] == "deck"),
            }
        )
    return out


def plot(path: Path, found: dict[str, list[dict]]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sizes = sorted({n.split("_")[0] for n in found}, reverse=True)
    fig, axes = plt.subplots(1, len(sizes), figsize=(5.2 * len(sizes), 4.2), sharey=True)
    for ax, size in zip(list(axes) if len(sizes) > 1 else [axes], sizes):
        names = sorted(
            (n for n in found if n.startswith(size + "_")), key=lambda n: float(n.split("shim")[-1])
        )
        f, bare = curve(found[names[0]], "undamped")
        ax.plot(f, bare, "k--", lw=1.4, label="undamped (Table 6's mode at 800 lbf)")
        for k, name in enumerate(names):
            f, v = curve(found[name], "deck")
            ax.plot(
                f,
                v,
                "o-",
                ms=3,
                color=plt.cm.viridis(k / max(1, len(names) - 1)),
                label=f"{name.split('_')[1].replace('shim', '')} in shims",
            )
        ax.set_title(f"{size[1:]} in spheres, 800 lbf")
        ax.set_xlabel("frequency [Hz]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    (axes[0] if len(sizes) > 1 else axes).set_ylabel("velocity [ips rms]")
    fig.suptitle("MIP damper on the Sec. 11.3 apparatus (designs/mip_apparatus.toml)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path, help="the design's --out folder")
    args = ap.parse_args(argv)
    found = read_rows(args.out)
    if not found:
        raise SystemExit(f"{args.out}: no configs/*/sweep/sweep.csv (run the design first)")
    table = reductions(found)
    with (args.out / "mip_reduction.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0]))
        w.writeheader()
        w.writerows(table)
    plot(args.out / "mip_velocity.png", found)
    print("| configuration | peak without [ips rms] | peak with | at [Hz] | reduction |")
    print("|---|---:|---:|---:|---:|")
    for r in table:
        flag = "" if r["converged"] else " (not every point converged)"
        print(
            f"| {r['config']} | {r['peak_undamped_ips_rms']:.2f} | "
            f"{r['peak_damped_ips_rms']:.2f} | {r['peak_damped_hz']:g} | "
            f"{r['reduction_percent']:.1f} %{flag} |"
        )
    print(f"wrote {args.out / 'mip_velocity.png'} and {args.out / 'mip_reduction.csv'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
