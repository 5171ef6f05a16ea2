"""A study's outputs: the terminal table, ``study.csv`` and ``study.png`` (error vs cost)."""

from __future__ import annotations

import csv
import math
import os

import numpy as np

from x3dpd.study.scene import QUANTITIES

_FIRST = (
    "setting",
    "dt",
    "contact",
    "friction",
    "repeat",
    "own",
    "status",
    "wall_s_per_sim_s",
    "error",
)


def columns(kind: str) -> list[str]:
    qs = QUANTITIES[kind]
    return (
        list(_FIRST)
        + list(qs)
        + [f"{q}_error" for q in qs]
        + [
            "trace_norm",
            "residual",
            "pareto",
            "steps",
            "stiffness_scale",
            "spread",
            "speedup",
            "walls",
            "cpu_s_per_sim_s",
            "message",
        ]
    )


def records(result) -> list[dict]:
    """One flat dict per run, in CSV column order (numbers as Python floats)."""
    out = []
    own = next((r for r in result.rows if r["setting"].own), None)
    own_wall = own.get("wall_s_per_sim_s", math.nan) if own else math.nan
    for r in result.rows:
        s = r["setting"]
        rec = {
            "setting": s.label,
            "dt": "auto" if s.auto else repr(float(s.dt)),
            "contact": s.contact,
            "friction": s.friction,
            "repeat": s.repeat,
            "own": int(s.own),
            "status": r["status"],
        }
        for c in columns(result.scene.kind)[len(rec) :]:
            v = r.get(c, "")
            rec[c] = int(v) if isinstance(v, bool) else v
        # the run-to-run spread the errors compare with, and the time saved against the
        # deck's own setting (own / this run's wall time per simulated second)
        rec["stiffness_scale"] = s.stiffness
        rec["walls"] = s.walls
        rec["spread"] = result.spread
        wall = r.get("wall_s_per_sim_s", math.nan)
        rec["speedup"] = own_wall / wall if wall and wall > 0 else math.nan
        out.append(rec)
    return out


def write_csv(path, result) -> None:
    cols = columns(result.scene.kind)
    tmp = f"{path}.tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for rec in records(result):
            w.writerow({k: _fmt(v) for k, v in rec.items()})
    os.replace(tmp, path)


def _fmt(v):
    if isinstance(v, (float, np.floating)):
        return "" if math.isnan(v) else repr(float(v))
    if isinstance(v, np.integer):
        return int(v)
    return v


def table(result) -> str:
    """The terminal table: one line per run."""
    main = result.scene.main
    lines = [
        f"{'setting':<34} {'status':<9} {'wall s/sim s':>12} {'cpu s/sim s':>11} "
        f"{'error':>9} {main:>14}"
    ]
    for r in result.rows:
        err = r.get("error", math.nan)
        val = r.get(main, math.nan)
        mark = " *" if r["setting"].own else ("  " if not r.get("pareto") else " +")
        lines.append(
            f"{r['setting'].label:<34} {r['status']:<9} "
            f"{r.get('wall_s_per_sim_s', math.nan):>12.4g} "
            f"{r.get('cpu_s_per_sim_s', math.nan):>11.4g} "
            f"{'' if math.isnan(err) else f'{err:.3%}':>9} {val:>14.6g}{mark}"
        )
    lines.append("(* the deck's own setting, + on the Pareto front)")
    if result.spread > 0:
        lines.append(
            f"run-to-run spread of the {main}: {result.spread:.3%} (errors below it "
            "are chaos, not the setting)"
        )
    return "\n".join(lines)


def write_png(path, result, title: str = "") -> None:
    """Error of the main quantity versus wall time per simulated second, log-log; the Pareto
    front joined, the deck's own setting highlighted; the reference drawn at the floor."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in result.rows if r["status"] == "complete" and not r["setting"].repeat]
    errs = [r["error"] for r in rows if r["error"] > 0]
    floor = min(errs) / 10 if errs else 1e-6
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=100)
    xs = [r["wall_s_per_sim_s"] for r in rows]
    ys = [r["error"] if r["error"] > floor else floor for r in rows]  # nan, 0: at the floor
    ax.scatter(xs, ys, color="0.5", zorder=2, label="settings")
    front = sorted((r for r in rows if r.get("pareto")), key=lambda r: r["wall_s_per_sim_s"])
    ax.plot(
        [r["wall_s_per_sim_s"] for r in front],
        [r["error"] if r["error"] > floor else floor for r in front],
        "-",
        color="tab:blue",
        zorder=1,
        label="Pareto front",
    )
    for r, x, y in zip(rows, xs, ys):
        ax.annotate(
            r["setting"].label, (x, y), fontsize=7, xytext=(4, 3), textcoords="offset points"
        )
    own = [r for r in rows if r["setting"].own]
    if own:
        e_own = own[0]["error"]
        ax.scatter(
            [own[0]["wall_s_per_sim_s"]],
            [e_own if e_own > floor else floor],
            s=160,
            marker="*",
            color="tab:red",
            zorder=3,
            label="deck's setting",
        )
    if result.spread > 0:
        ax.axhline(result.spread, color="tab:orange", ls="--", lw=1, label="run-to-run spread")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time per simulated second [s]")
    ax.set_ylabel(f"relative error of the {result.scene.main.replace('_', ' ')}")
    ax.set_title(title, fontsize=10)
    ax.text(
        0.01,
        0.01,
        f"reference (finest run) drawn at {floor:.2g}",
        fontsize=7,
        transform=ax.transAxes,
    )
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    tmp = f"{path}.tmp.png"
    fig.savefig(tmp)
    plt.close(fig)
    os.replace(tmp, path)
