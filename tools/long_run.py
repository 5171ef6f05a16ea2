#!/usr/bin/env python3
"""The long-run check: the report's decks driven for their full 15 s, ledger and final state.

    python tools/long_run.py                     # both decks, 15 s each (a few minutes)
    python tools/long_run.py --tmax 1 beam_64    # a shorter window, one deck

For each deck it runs ``x3dpd.run`` (nothing written but the summary) and prints one Markdown
table row: the run's status, steps, wall time, the energy ledger at the end (drive work, energy
dissipated by mechanism, residual relative to the energy scale, and the largest |residual| seen),
the drive node's x amplitude over the last second, and whether every particle ended inside its
cavity's box. docs/long-run.md holds the numbers and the date they were measured.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

#: Deck and the forces it runs with (appendix_a_cube.inp has no USRFRC card: App. C's drive).
CASES = {
    "appendix_a_cube": (
        "decks/appendix_a_cube.inp",
        ("sine:node=25,dof=1,amp=4.84040e-3,hz=37.21",),
        25,
    ),
    "beam_64": ("decks/beam_64.inp", (), 9),
}


def long_run(name: str, tmax: float) -> dict:
    import x3dpd

    path, usrfrc, drive = CASES[name]
    res = x3dpd.run(str(ROOT / path), tmax=tmax, usrfrc=usrfrc, handle_signals=True)
    sm, e, tr, model = res.summary, res.energy, res.trace, res.model
    scale = sm["energy_scale"]
    last = e.data[-1]
    col = {c: k for k, c in enumerate(e.columns)}
    t = tr.time
    k = tr.node_ids.tolist().index(drive)
    tail = t >= t[-1] - 1.0
    x = tr.position[tail, k, 0]
    p0 = model.particle_start
    box = model.x0[model.tri_nodes.reshape(-1)]
    moved = res.final_state.state.x
    # the cavity translates rigidly with the structure: shift its box by the structure's mean
    shift = moved[:p0].mean(axis=0) - model.x0[:p0].mean(axis=0)
    lo, hi = box.min(axis=0) + shift, box.max(axis=0) + shift
    xp = moved[p0:]
    inside = bool(np.all((xp >= lo - 1e-9) & (xp <= hi + 1e-9)))
    return {
        "deck": path,
        "usrfrc": list(usrfrc),
        "status": sm["status"],
        "t_end": sm["t_end"],
        "steps": sm["steps"],
        "wall_s": sm["wall_s"],
        "steps_per_s": sm["steps_per_s"],
        "external_work": float(last[col["external_work"]]),
        "dissipated_viscoelastic": float(last[col["dissipated_viscoelastic"]]),
        "dissipated_friction": float(last[col["dissipated_friction"]]),
        "dissipated_dampers": float(last[col["dissipated_dampers"]]),
        "residual_over_scale": float(last[col["residual"]] / scale),
        "max_residual_over_scale": float(np.max(np.abs(e["residual"])) / scale),
        "energy_scale": scale,
        "drive_amplitude_last_s": float(np.ptp(x) / 2.0),
        "particles_inside": inside,
    }


def markdown(rows: list[dict]) -> str:
    head = (
        "| deck | status | t [s] | steps | wall [s] | drive work | dissipated visco / "
        "friction / dampers | residual / scale (end, max) | amplitude, last 1 s [in] | "
        "particles inside |\n|---|---|---:|---:|---:|---:|---|---|---:|---|"
    )
    lines = [head]
    for r in rows:
        lines.append(
            f"| `{r['deck']}` | {r['status']} | {r['t_end']:g} | {r['steps']} | "
            f"{r['wall_s']:.0f} | {r['external_work']:.4g} | "
            f"{r['dissipated_viscoelastic']:.4g} / {r['dissipated_friction']:.4g} / "
            f"{r['dissipated_dampers']:.4g} | {r['residual_over_scale']:.2e}, "
            f"{r['max_residual_over_scale']:.2e} | {r['drive_amplitude_last_s']:.4g} | "
            f"{r['particles_inside']} |"
        )
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("decks", nargs="*", help=f"which decks: {', '.join(CASES)} (default all)")
    ap.add_argument("--tmax", type=float, default=15.0, help="end time [s] (default 15)")
    ap.add_argument("--json", default=None, help="also write the numbers to this JSON file")
    args = ap.parse_args(argv)
    unknown = [d for d in args.decks if d not in CASES]
    if unknown:
        ap.error(f"unknown deck {unknown[0]!r}; choose from {', '.join(CASES)}")
    rows = [long_run(name, args.tmax) for name in (args.decks or list(CASES))]
    print(markdown(rows))
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1) + "\n")
    return 0 if all(r["status"] == "complete" for r in rows) else 3


if __name__ == "__main__":
    sys.exit(main())
