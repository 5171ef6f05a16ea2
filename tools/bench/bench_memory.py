"""Memory held by a run's state (what a restart dump saves) for the benchmark scenes.

    python tools/bench/bench_memory.py [--n 4096]

Prints the bytes of every state array after the contact lists have been built and the run has
advanced, plus the constant kernel arrays. The trace is streamed to disk in blocks, so a long run's
memory does not grow with its length (tools: compare ``ru_maxrss`` after 1 and after 4 blocks).
"""

from __future__ import annotations

import argparse
import resource
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402
from bench_solver import scene_model  # noqa: E402

from x3dpd.solver.simulation import Simulation  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=4096)
    ap.add_argument("--steps", type=int, default=4000)
    args = ap.parse_args(argv)
    model, _ = scene_model(args.n)
    sim = Simulation(model, itrac=1000)
    sim.advance(args.steps)
    state = sum(np.asarray(v).nbytes for v in sim.state.to_arrays().values())
    setup = sum(np.asarray(v).nbytes for v in vars(sim.setup).values() if isinstance(v, np.ndarray))
    rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    for _ in range(4):
        sim.advance(args.steps)
    rss2 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(
        f"n={args.n}: state {state / 2**20:.2f} MiB, constant arrays {setup / 2**20:.2f} MiB, "
        f"peak RSS {rss1 / 1024:.0f} MiB after {args.steps} steps, {rss2 / 1024:.0f} MiB after "
        f"{5 * args.steps} (process incl. Python, numpy, numba, LLVM)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
