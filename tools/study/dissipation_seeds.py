#!/usr/bin/env python3
"""A shaken bed's dissipation per cycle over several particle starts: the long-run statistic
that a change of the force summation order (or any change meant to keep the physics) must
leave unchanged within its standard error.

    python tools/study/dissipation_seeds.py [--deck decks/beam_64.inp] [--hz 37] [--cycles 100]
        [--seeds 4] [--json OUT.json]

Each seed starts the deck's particles a hair apart (x3dpd.design.replicas.jittered, seed 0 the
deck as it is), drives node 9 along x at the 400 mV drive (9.68080e-3 lbf) and measures the
energy the particles and dampers dissipate per drive cycle over the cycles after the first
fifth. Prints each seed's mean, and the seeds' mean and standard error. Run it with two code
trees (``PYTHONPATH=TREE``) and compare: docs/engine.md, "The order of force sums".
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

import x3dpd
from x3dpd.design.replicas import jittered

LOSSES = ("dissipated_viscoelastic", "dissipated_friction", "dissipated_dampers")


def dissipation_per_cycle(deck, hz: float, cycles: int, drive: float) -> float:
    period = 1.0 / hz
    dt = deck.parameters.dtmax
    itrac = max(1, int(round(period / (20 * dt))))
    res = x3dpd.run(
        deck,
        tmax=cycles * period,
        itrac=itrac,
        trace_nodes=(9,),
        usrfrc=(f"sine:node=9,dof=1,amp={drive!r},hz={hz!r}",),
    )
    t = res.energy["time"]
    lost = sum(res.energy[name] for name in LOSSES)
    start = cycles // 5
    at = [np.interp(k * period, t, lost) for k in (start, cycles)]
    return (at[1] - at[0]) / (cycles - start)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--deck", default="decks/beam_64.inp")
    ap.add_argument("--hz", type=float, default=37.0)
    ap.add_argument("--cycles", type=int, default=100)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--drive", type=float, default=9.68080e-3)
    ap.add_argument("--json")
    a = ap.parse_args()
    base = x3dpd.load_deck(a.deck)
    values = []
    for seed in range(a.seeds):
        values.append(dissipation_per_cycle(jittered(base, seed), a.hz, a.cycles, a.drive))
        print(f"seed {seed}: {values[-1]:.6e} per cycle", flush=True)
    mean = float(np.mean(values))
    se = float(np.std(values, ddof=1)) / math.sqrt(len(values)) if len(values) > 1 else math.nan
    print(f"mean {mean:.6e}, standard error {se:.2e} ({se / mean:.2%})")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"values": values, "mean": mean, "se": se, **vars(a)}, f, indent=1)


if __name__ == "__main__":
    main()
