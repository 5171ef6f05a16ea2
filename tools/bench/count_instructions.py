"""Instructions per step of the compiled step loop, counted by callgrind (immune to the load of
a shared machine, unlike wall time).

    OPENBLAS_NUM_THREADS=1 valgrind --tool=callgrind --separate-threads=yes \\
        --instr-atstart=no --callgrind-out-file=cg.out \\
        python tools/bench/count_instructions.py SCENE STEPS
    grep totals cg.out-01          # instructions of the main thread in the counted window

SCENE is a shipped deck's stem (``beam_64``: its own drive, no trace output) or ``benchN``
(tools/bench/scene.py's falling window with N spheres). The scene is set up and run 4010 steps
outside the count (compiling or loading the loop, building the lists); then callgrind counts
only ``STEPS`` steps of one ``Simulation.advance`` call (instrumentation switched on and off
around it with ``callgrind_control``). Compare two revisions on the same scene and step count.
"""

from __future__ import annotations

import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "bench"))

from x3dpd.deck import read_deck  # noqa: E402
from x3dpd.model.build import build_model  # noqa: E402
from x3dpd.solver.simulation import Simulation  # noqa: E402


def _instrument(on: bool) -> None:
    subprocess.run(["callgrind_control", "-i", "on" if on else "off", str(os.getpid())],
                   capture_output=True, check=False)


def main(argv: list[str]) -> int:
    scene, steps = argv[1], int(argv[2])
    if scene.startswith("bench"):
        from bench_solver import scene_model
        model, _ = scene_model(int(scene[5:]))
    else:
        deck = read_deck(ROOT / "decks" / f"{scene}.inp")
        model = build_model(replace(deck, parameters=replace(deck.parameters, itrac=10**9)))
    sim = Simulation(model)
    sim.advance(4000, max_rows=1)
    sim.advance(10, max_rows=1)
    _instrument(True)
    sim.advance(steps, max_rows=1)
    _instrument(False)
    print(f"{scene}: {steps} steps counted (step {sim.state.step})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
