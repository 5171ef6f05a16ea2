#!/usr/bin/env python3
"""The report's Section 11.2 stall on the jet-engine mode, with and without the MIP damper:
decks/mip_engine.inp (600 lb at 146 Hz, zeta 0.067, the 0.5 in damper with 0.009 in of free
length) driven by its stall ramp (0.4 -> 3.0 ips rms in 5 s, then held for 0.5 s), and the same
deck without its spheres; the mode's velocity (rms over each drive cycle) against time.

    python tools/study/mip_engine.py --out mip_engine          # the full 884 holes (minutes)
    python tools/study/mip_engine.py --out mip_engine --lumped # one hole per plate (seconds)

Writes OUT/engine_velocity.png and OUT/engine_velocity.csv (time, rms velocity without and with
the damper [in/s]) and prints the rms velocity at the end of the ramp and the reduction.
docs/report-studies.md shows the figure and the numbers.
"""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path

import numpy as np

import x3dpd
from x3dpd.deck import parse_deck
from x3dpd.design.baselines import without_particles

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "decks" / "mip_engine.inp"
HZ = 146.0


def cycle_rms(t: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(cycle mid-times, rms of v over each whole drive cycle)."""
    k = np.floor(t * HZ).astype(int)
    mids, rms = [], []
    for c in range(k.min(), k.max()):
        mine = k == c
        if mine.sum() > 8:
            mids.append((c + 0.5) / HZ)
            rms.append(math.sqrt(float(np.mean(v[mine] ** 2))))
    return np.array(mids), np.array(rms)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument(
        "--lumped",
        action="store_true",
        help="one hole per plate (exact for "
        "alike holes started alike: docs/deck-reference.md, PLATES)",
    )
    ap.add_argument("--tmax", type=float, default=None, help="default: the deck's 5.5 s")
    args = ap.parse_args(argv)
    text = DECK.read_text()
    if args.lumped:
        text = re.sub(r"(axis=y)\n", r"\1 lumped=yes\n", text)
        text = re.sub(r"\nTRACE\n[^E]*END", "\nTRACE\n   1\nEND", text)  # the spheres' ids move
    deck = parse_deck(text, str(DECK))
    itrac = round(1.0 / (HZ * 40 * deck.parameters.dtmax))  # 40 samples per cycle
    args.out.mkdir(parents=True, exist_ok=True)
    series = {}
    for name, d in (("without", without_particles(deck)), ("with", deck)):
        res = x3dpd.run(d, tmax=args.tmax, itrac=itrac, trace_nodes=(1,))
        t, v = res.trace.time, res.trace.velocity[:, 0, 1]
        series[name] = cycle_rms(t, v)
        print(f"{name} the damper: {res.summary['steps']} steps in {res.summary['wall_s']:.0f} s")
    t_mid, bare = series["without"]
    _, damped = series["with"]
    n = min(bare.size, damped.size)
    t_mid, bare, damped = t_mid[:n], bare[:n], damped[:n]
    np.savetxt(
        args.out / "engine_velocity.csv",
        np.column_stack([t_mid, bare, damped]),
        delimiter=",",
        header="time_s,rms_velocity_without,rms_velocity_with",
        comments="",
    )
    end = (t_mid > 4.9) & (t_mid < 5.0)
    held = t_mid > 5.1
    for label, mask in (("end of the ramp (4.9-5.0 s)", end), ("held at 3.0 ips (5.1 s on)", held)):
        if mask.any():
            b, d = bare[mask].mean(), damped[mask].mean()
            print(f"{label}: {b:.3f} -> {d:.3f} in/s rms ({100 * (1 - d / b):.1f} % less)")
    _plot(args.out / "engine_velocity.png", t_mid, bare, damped, args.lumped)
    print(f"wrote {args.out / 'engine_velocity.csv'} and {args.out / 'engine_velocity.png'}")
    return 0


def _plot(path, t, bare, damped, lumped) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    ax.plot(t, bare, "k--", lw=1.2, label="without the damper")
    ax.plot(
        t,
        damped,
        "C3",
        lw=1.4,
        label="with the 0.5 in MIP damper" + (" (lumped plates)" if lumped else ""),
    )
    ax.axhline(3.0, color="0.6", lw=0.8)
    ax.axhline(0.4, color="0.6", lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("velocity, rms over each cycle [in/s]")
    ax.set_title("Sec. 11.2 stall on the 146 Hz engine mode (decks/mip_engine.inp)")
    ax.legend(loc="upper left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
