#!/usr/bin/env python3
"""What the cantilever's modes 2-3 change in beam_64's response near 37 Hz, and what they cost.

    python tools/study/modal_beam.py --out modal_beam [--workers 2]

Sweeps, at Table 4's 200 mV drive (4.84040e-3 lbf) down 38.5 -> 36.5 Hz in one chain each:

* ``decks/beam_64_modal.inp`` (three Euler-Bernoulli modes, the cavity turning with the tip),
* the same deck with mode 1 only (its MODE 2, 3 records and their shape values dropped: the
  same coupled first mode, written to OUT/beam_64_mode1.inp),
* ``decks/beam_64.inp`` (the report's SDOF),

each with its closed-form undamped and added-mass baselines, then prints per frequency the tip
amplitude of each and, from the closed forms, what modes 2-3 change in the particle-free beam;
writes OUT/modal_beam.png, OUT/modal_beam.json and every sweep's folder. The sweeps' own rows
give each point's steps and wall time, so the cost per step of each structure is measured on
the same points.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from x3dpd.deck.modal_card import parse_modal  # noqa: E402
from x3dpd.deck.parser import read_deck  # noqa: E402
from x3dpd.deck.writer import write_deck  # noqa: E402
from x3dpd.design.baselines import linear_structure, without_particles  # noqa: E402
from x3dpd.design.commands import sweep_command  # noqa: E402
from x3dpd.errors import NOWHERE  # noqa: E402
from x3dpd.model.build import build_model  # noqa: E402

DRIVE = 4.84040e-3
FREQ = "36.5:38.5:0.5"


def first_mode_only(deck):
    """The deck with its MODAL card cut to mode 1 (its MODE record, its first shape values)."""
    lines = []
    for line in deck.modal.lines:
        words = line.split()
        if words[0].upper() == "MODE" and words[1] != "1":
            continue
        if words[0].upper() == "SHAPE":
            line = " ".join(words[:4])
        lines.append(line)
    return replace(deck, modal=parse_modal(NOWHERE, [(x, 0, 1) for x in lines]))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    three = ROOT / "decks" / "beam_64_modal.inp"
    one = out / "beam_64_mode1.inp"
    write_deck(first_mode_only(read_deck(three)), one)
    decks = {"3 modes": three, "mode 1 only": one, "SDOF (beam_64)": ROOT / "decks" / "beam_64.inp"}
    result = {}
    for name, path in decks.items():
        t = time.perf_counter()
        rows = sweep_command(
            str(path),
            freq=FREQ,
            amps=[repr(DRIVE)],
            node=9,
            dof=1,
            direction="down",
            baselines=["undamped", "added-mass"],
            out=str(out / Path(path).stem),
            workers=args.workers,
            echo=lambda s: None,
        )
        sim = [r for r in rows if r["config"] == "deck"]
        result[name] = {
            "frequency_hz": [r["frequency_hz"] for r in sim],
            "amplitude": [r["amplitude"] for r in sim],
            "undamped": [r["amplitude"] for r in rows if r["config"] == "undamped"],
            "steps": sum(r["steps"] for r in sim),
            "wall_s": sum(r["wall_s"] for r in sim),
            "us_per_step": 1e6 * sum(r["wall_s"] for r in sim) / sum(r["steps"] for r in sim),
            "sweep_s": time.perf_counter() - t,
        }
    # modes 2-3 in the particle-free beam, in closed form
    bare3 = build_model(without_particles(read_deck(three)))
    bare1 = build_model(without_particles(read_deck(one)))
    f = np.array(result["3 modes"]["frequency_hz"])
    x3 = np.array([linear_structure(bare3, 9, 1).response(DRIVE, 2 * math.pi * x)[0] for x in f])
    x1 = np.array([linear_structure(bare1, 9, 1).response(DRIVE, 2 * math.pi * x)[0] for x in f])
    result["closed_form_modes_2_3_change"] = list((x3 / x1 - 1.0))
    (out / "modal_beam.json").write_text(json.dumps(result, indent=1))
    print(f"{'Hz':>6} " + " ".join(f"{n:>16}" for n in decks) + "   modes 2-3, no particles")
    for k, fk in enumerate(f):
        print(
            f"{fk:6.2f} "
            + " ".join(f"{result[n]['amplitude'][k]:16.5e}" for n in decks)
            + f"   {100 * result['closed_form_modes_2_3_change'][k]:+.4f} %"
        )
    for n in decks:
        r = result[n]
        print(
            f"{n:>16}: {r['steps']} steps, {r['us_per_step']:.2f} us/step "
            f"(sweep {r['sweep_s']:.0f} s)"
        )
    _plot(out / "modal_beam.png", result, decks)
    print(f"wrote {out / 'modal_beam.json'} and {out / 'modal_beam.png'}")
    return 0


def _plot(png, result, decks) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for k, name in enumerate(decks):
        r = result[name]
        ax.plot(r["frequency_hz"], r["amplitude"], marker="ov^"[k], label=f"{name}, particles")
        ax.plot(
            r["frequency_hz"],
            r["undamped"],
            ls="--",
            color=f"C{k}",
            lw=0.8,
            label=f"{name}, undamped",
        )
    ax.set_yscale("log")
    ax.set_xlabel("drive frequency [Hz]")
    ax.set_ylabel("tip displacement amplitude [in]")
    ax.set_title("beam_64: 3 modes, mode 1 only, SDOF (200 mV)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=90)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
