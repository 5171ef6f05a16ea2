#!/usr/bin/env python3
"""What the interval's run-length rule buys: coverage and cycles of the sequential stop on
synthetic series as correlated as a many-particle bed's, at several ``RUN_LENGTH`` values.

    python tools/study/run_length_coverage.py [--phi 0.97] [--scatter 0.0154] [--tol 0.02]
                                              [--runs 100] [--run-length 50 20 10]

Each run is a complex AR(1) series of lag-1 correlation ``phi`` (integrated autocorrelation
time tau = (1 + phi) / (2 (1 - phi)) cycles: 32.8 at 0.97, as beam_512 at 37.5 Hz, where
tools/study/point_series.py measures 31.5) whose amplitude scatters by ``scatter`` from cycle
to cycle around a true amplitude 1, plus a small start-up transient; it stops as a sweep point
does (x3dpd.analysis.confidence.assess every 10 cycles, the half-width within ``tol``). The
share of stopped intervals that hold the true amplitude should be 0.95; docs/performance.md
("Time to answer") quotes the result.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import x3dpd.analysis.confidence as confidence

# the synthetic series of the coverage test (tests/analysis/test_confidence.py)
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "analysis"))
from test_confidence import stopped_coverage  # noqa: E402


def coverage(phi, scatter, tol, runs, seed, run_length):
    """(share of intervals holding the true amplitude, median cycles run) at ``run_length``."""
    confidence.RUN_LENGTH = run_length
    # the amplitude's scatter is the real part's: the complex series' sigma is scatter sqrt 2
    return stopped_coverage(
        phi, 0.1, tol, runs, seed, scatter=scatter * math.sqrt(2.0), most=4000, every=10
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--phi", type=float, default=0.97)
    ap.add_argument("--scatter", type=float, default=0.0154)
    ap.add_argument("--tol", type=float, default=0.02)
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--run-length", type=int, nargs="+", default=[50, 20, 10])
    args = ap.parse_args()
    tau = (1 + args.phi) / (2 * (1 - args.phi))
    print(f"phi {args.phi} (tau {tau:.1f} cycles), scatter {args.scatter:.2%}, tol {args.tol}")
    for run_length in args.run_length:
        share, median = coverage(args.phi, args.scatter, args.tol, args.runs, 5, run_length)
        print(
            f"RUN_LENGTH {run_length:3d}: coverage {share:.2f} over {args.runs} runs, "
            f"median {median:.0f} cycles"
        )


if __name__ == "__main__":
    main()
