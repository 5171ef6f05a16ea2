"""The beam of decks/beam_64.inp under random drive, with and without its 64 spheres: FRFs overlaid
as in the report's Figures 59-63 (docs/testing-like-a-test-engineer.md).

    python tools/study/random_beam.py --out out/random_beam [--rms 9.68e-3] [--periods 3]

Both runs are driven on node 9 along x by ``random:`` over 30-45 Hz with one seed and an 8 s
period, for ``--periods`` periods; only node 9 is traced (every 1 ms). The FRF averages the
periods after the first (whose start transient it skips), one period per segment with a
rectangular window (periodic random: every line of the band on a bin, no leakage). The undamped
beam repeats itself period after period (coherence 1); the particles do not (their coherence
shows how far the damped beam is from a linear system at this level). Writes OUT/undamped.trace.txt,
OUT/beam_64.trace.txt and OUT/frf/frf.csv, frf.png; prints the peak of each FRF.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from x3dpd.api import load_deck, run
from x3dpd.design.baselines import without_particles
from x3dpd.design.frf import frf_command

ROOT = Path(__file__).resolve().parents[2]
PERIOD = 8.0


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--rms", type=float, default=9.68e-3, help="drive RMS over the band [lbf]")
    ap.add_argument("--periods", type=int, default=3)
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    spec = f"random:node=9,dof=1,rms={args.rms!r},band=30:45,seed=1,period={PERIOD:g}"
    deck = load_deck(ROOT / "decks" / "beam_64.inp")
    traces = []
    for name, d in (("undamped", without_particles(deck)), ("beam_64", deck)):
        path = out / f"{name}.trace.txt"
        t = time.perf_counter()
        run(d, tmax=args.periods * PERIOD, usrfrc=[spec], trace=path, trace_nodes=(9,),
            overwrite=True)
        print(f"{name}: {args.periods * PERIOD:g} s simulated in {time.perf_counter() - t:.0f} s")
        traces.append(str(path))
    rows = frf_command(traces, drive="9:1", responses=["9:1"], out=str(out / "frf"),
                       quantity="displacement", window="boxcar", segment=PERIOD, overlap=0.0,
                       band="30:45", t_from=PERIOD, overwrite=True)
    for run_name in dict.fromkeys(r["run"] for r in rows):
        mine = [r for r in rows if r["run"] == run_name]
        peak = max(mine, key=lambda r: r["h1_mag"])
        coh = min(r["coherence"] for r in mine)
        print(f"{run_name}: peak |H1| {peak['h1_mag']:.4g} in/lbf at {peak['frequency_hz']:g} Hz"
              f" ({20 * np.log10(peak['h1_mag']):.1f} dB), coherence >= {coh:.3f}")


if __name__ == "__main__":
    main()
