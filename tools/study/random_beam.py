"""The beam of decks/beam_64.inp under random drive with its 64 spheres, its H1 overlaid on the
closed-form FRFs of its baselines (the beam without the spheres, and with their mass added
rigidly), as in the report's Figures 59-63 (docs/testing-like-a-test-engineer.md).

    python tools/study/random_beam.py --out out/random_beam [--rms 9.68e-3] [--periods 3]

The run is driven on node 9 along x by ``random:`` over 30-45 Hz with one seed and an 8 s
period, for ``--periods`` periods; only node 9 is traced (every 1 ms). The FRF averages the
periods after the first (whose start transient it skips), one period per segment with a
rectangular window (periodic random: every line of the band on a bin, no leakage). The
baselines come from ``x3dpd frf --baseline undamped,added-mass`` (closed form, from the deck the
run read). Writes OUT/beam_64.trace.txt and OUT/frf/frf.csv, baselines.csv, frf.png; prints the
peak of each FRF, the attenuation against each baseline, and the run's CPU time.
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np

from x3dpd.api import run
from x3dpd.testlab.frf import frf_command

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
    path = out / "beam_64.trace.txt"
    cpu = time.process_time()
    run(
        ROOT / "decks" / "beam_64.inp",
        tmax=args.periods * PERIOD,
        usrfrc=[spec],
        trace=path,
        trace_nodes=(9,),
        overwrite=True,
    )
    print(
        f"beam_64: {args.periods * PERIOD:g} s simulated in {time.process_time() - cpu:.0f} s "
        "of CPU time"
    )
    rows = frf_command(
        [str(path)],
        drive="9:1",
        responses=["9:1"],
        out=str(out / "frf"),
        quantity="displacement",
        window="boxcar",
        segment=PERIOD,
        overlap=0.0,
        band="30:45",
        t_from=PERIOD,
        baselines=("undamped", "added-mass"),
        overwrite=True,
    )
    peaks = {"beam_64": max(rows, key=lambda r: r["h1_mag"])["h1_mag"]}
    coherence = min(r["coherence"] for r in rows)
    with open(out / "frf" / "baselines.csv") as f:
        for row in csv.DictReader(line for line in f if not line.startswith("#")):
            peaks[row["baseline"]] = max(peaks.get(row["baseline"], 0.0), float(row["mag"]))
    for name, peak in peaks.items():
        print(
            f"{name}: peak |H| {peak:.4g} in/lbf ({20 * np.log10(peak):.1f} dB re 1 in/lbf)"
            + (
                ""
                if name == "beam_64"
                else f"; beam_64 {20 * np.log10(peaks['beam_64'] / peak):+.1f} dB against it"
            )
        )
    print(f"beam_64: coherence >= {coherence:.3f}")


if __name__ == "__main__":
    main()
