#!/usr/bin/env python3
"""How a sweep point's answer wanders: run one point of a deck for many drive cycles and print
its cycle-to-cycle scatter, the scatter of means over longer batches, and what the steady-state
criterion (x3dpd.analysis.confidence) makes of the first n cycles.

    python tools/study/point_series.py DECK HZ CYCLES [--drive F] [--node N] [--dof D]

From the predicted start, as a sweep point starts (x3dpd.design.predict). docs/design-guide.md,
"Steady state", quotes decks/beam_64.inp at 37 Hz for 800 cycles.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import x3dpd
from x3dpd.analysis.confidence import assess, autocorrelation_time
from x3dpd.analysis.steady_state import SteadyStateMonitor
from x3dpd.design.predict import predicted_start
from x3dpd.design.steady_state import SweepPoint


def cycle_phasors(deck_path: str, hz: float, cycles: int, drive: float, node: int, dof: int):
    deck = x3dpd.load_deck(deck_path)
    dt = deck.parameters.dtmax
    period = 1.0 / hz
    itrac = max(1, int(period / (200 * dt)))
    point = SweepPoint(config="deck", deck=deck, frequency_hz=hz, drive=drive, node=node, dof=dof)
    usrfrc = (f"sine:node={node},dof={dof},amp={drive!r},hz={hz!r},t0=0.0",)
    monitor = SteadyStateMonitor(
        2 * math.pi * hz, t0=0.0, t_start=0.0, tol=1e-12, max_cycles=cycles + 10
    )

    def feed(block) -> bool:
        monitor.feed(block.time, block.position[:, 0, dof - 1], block.velocity[:, 0, dof - 1])
        return False

    config = x3dpd.run_config(
        deck,
        tmax=cycles * period,
        dt=dt,
        itrac=itrac,
        trace_nodes=(node,),
        usrfrc=usrfrc,
        keep_trace=False,
        stop=feed,
        stop_every=200,
    )
    x3dpd.run(config.starting_from(predicted_start(point, None, config, 0.0)))
    return np.asarray(monitor.phasors)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("deck")
    ap.add_argument("hz", type=float)
    ap.add_argument("cycles", type=int)
    ap.add_argument("--drive", type=float, default=4.84040e-3)
    ap.add_argument("--node", type=int, default=9)
    ap.add_argument("--dof", type=int, default=1)
    a = ap.parse_args()
    z = cycle_phasors(a.deck, a.hz, a.cycles, a.drive, a.node, a.dof)
    cut = assess(z).truncation
    kept = z[cut:]
    mean = kept.mean()
    u = (kept * np.conj(mean) / abs(mean)).real / abs(mean)
    print(f"{z.size} cycles, the last {kept.size} kept: amplitude {abs(mean):.5e}")
    tau = autocorrelation_time(u)
    print(f"cycle-to-cycle scatter {u.std():.2%}, autocorrelation time {tau:.1f}")
    for b in (10, 25, 50, 100):
        if u.size >= 3 * b:
            means = u[: u.size // b * b].reshape(-1, b).mean(axis=1)
            spread = means.std(ddof=1)
            print(f"means of {b:3d} cycles scatter by {spread:.2%} ({means.size} of them)")
    for n in range(100, z.size + 1, 100):
        s = assess(z[:n])
        iv = s.interval
        print(
            f"after {n:4d} cycles: transient out {s.settled!s:5}, kept {n - s.truncation:4d}, "
            f"amplitude {iv.amplitude:.5e} +/- {iv.amplitude_hw / iv.amplitude:.2%}"
        )


if __name__ == "__main__":
    main()
