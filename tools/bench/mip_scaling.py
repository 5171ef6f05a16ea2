"""What a multiple individual particle (MIP) damper's step costs against its number of holes,
and against as many free spheres falling in one box (issue 31: at most 2x; linear in the
holes).

    python tools/bench/mip_scaling.py                 # instructions per step (callgrind)
    python tools/bench/mip_scaling.py --wall          # wall time per step: a quiet machine only
    python tools/bench/mip_scaling.py --holes 100 884 # some counts only

The MIP scenes are tools/bench/mip_scene.py's (decks/mip_apparatus_05.inp with N holes at
800 lbf, 128 Hz, the spheres in flight); the falling scene is tools/bench/scene.py's box of
``benchN`` (N free spheres, the falling window). Instructions: each scene is prepared natively
(``count_instructions.py --prepare``), then callgrind counts ``--steps`` steps of the main
thread (``count_instructions.py``), load-immune. Wall time: the same scenes in this process,
the best of ``--repeat`` windows of ``--steps`` steps taken in turn (interleaved).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from mip_scene import HOLE_COUNTS  # noqa: E402

COUNT = HERE / "count_instructions.py"


def instructions(scene: str, steps: int) -> int:
    """Instructions per step of ``scene`` (the main thread), under callgrind."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "cg.out"
        env = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
        subprocess.run(
            [
                "valgrind",
                "--tool=callgrind",
                "--separate-threads=yes",
                "--instr-atstart=no",
                f"--callgrind-out-file={out}",
                sys.executable,
                str(COUNT),
                scene,
                str(steps),
            ],
            check=True,
            capture_output=True,
            env=env,
        )
        text = (Path(tmp) / "cg.out-01").read_text()
    return int(re.search(r"^totals: (\d+)", text, re.M).group(1)) // steps


def prepare(scene: str) -> None:
    subprocess.run(
        [sys.executable, str(COUNT), "--prepare", scene], check=True, capture_output=True
    )


def wall_times(holes, steps: int, repeat: int) -> dict:
    """Seconds per step of every scene, the best of ``repeat`` interleaved windows."""
    from bench_solver import best_seconds_per_step, scene_model
    from count_instructions import bed_simulation

    sims = {}
    for n in holes:
        prepare(f"mip_{n}")
        sims[f"mip_{n}"] = bed_simulation(f"mip_{n}")
        falling = scene_model(n)[0]
        from x3dpd.solver.simulation import Simulation

        sims[f"bench{n}"] = Simulation(falling, itrac=10**9)
        sims[f"bench{n}"].advance(4010, max_rows=1)
    for sim in sims.values():
        sim.advance(10, max_rows=1)
    return best_seconds_per_step(sims, steps, repeat)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--holes", type=int, nargs="+", default=list(HOLE_COUNTS))
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--wall", action="store_true", help="wall time instead of instructions")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    if args.wall:
        t = wall_times(args.holes, args.steps, args.repeat)
        print("| holes | MIP µs/step | µs per hole | falling spheres µs/step | MIP / falling |")
        print("|---:|---:|---:|---:|---:|")
        for n in args.holes:
            m, b = t[f"mip_{n}"] * 1e6, t[f"bench{n}"] * 1e6
            print(f"| {n} | {m:.1f} | {m / n * 1e3:.1f} ns | {b:.1f} | {m / b:.2f} |")
        return 0
    print("| holes | MIP instructions/step | per hole | falling spheres /step | MIP / falling |")
    print("|---:|---:|---:|---:|---:|")
    for n in args.holes:
        prepare(f"mip_{n}")
        m = instructions(f"mip_{n}", args.steps)
        b = instructions(f"bench{n}", args.steps)
        print(f"| {n} | {m:,} | {m / n:.0f} | {b:,} | {m / b:.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
