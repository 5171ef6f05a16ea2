"""Instructions per step of the compiled step loop, counted by callgrind (immune to the load of
a shared machine, unlike wall time).

    OPENBLAS_NUM_THREADS=1 valgrind --tool=callgrind --separate-threads=yes \\
        --instr-atstart=no --callgrind-out-file=cg.out \\
        python tools/bench/count_instructions.py SCENE STEPS
    grep totals cg.out-01          # instructions of the main thread in the counted window

Give valgrind the interpreter itself (``python -c "import sys; print(sys.executable)"``), not
a wrapper script such as pyenv's ``python`` shim: valgrind does not follow the shim's ``exec``,
and the count comes out empty.

SCENE is a shipped deck's stem (``beam_64``: its own drive, no trace output), ``benchN``
(tools/bench/scene.py's falling window with N spheres), ``sdof`` (``bench_solver.py --sdof``'s
structure) or one of the settled beds of ``regress.py``: ``settled_512`` (elastic, at rest),
``settled_visco_512`` (E1 = 5e6 psi, at rest), ``shaken_visco_512`` (the same bed in the free
cavity shaken at 2 g, after two drive periods), or the larger elastic beds at rest of
``threads.py``, ``settled_4096`` and ``settled_16384``, or ``mip_N``: the MIP damper of
decks/mip_apparatus_05.inp with N holes at 800 lbf, its spheres in flight (tools/bench/mip_scene.py;
prepared like a bed), or ``shaker_base``: decks/shaker_fig9.inp with its base node driven by a
prescribed motion (``--motion`` :data:`SHAKER_BASE`, the golden case's). The scene is set up
and run 4010 steps (a restored bed 10) outside the count (compiling or loading the loop,
building the lists); then callgrind counts only ``STEPS`` steps of one ``Simulation.advance``
call (instrumentation switched on and off around it with ``callgrind_control``). Compare two
revisions on the same scene and step count.

A settled bed takes 300,000 steps (and the shaken one two drive periods more) to reach, far
too slow under valgrind: ``python tools/bench/count_instructions.py --prepare SCENE`` runs
them natively once and pickles the state into the temporary folder
(``x3dpd-bench-SCENE.pkl``), which the counted run restores. The bed is the same whatever
revision prepared it as long as the revisions agree bit for bit (the column pass does).
"""

from __future__ import annotations

import os
import pickle
import subprocess
import tempfile
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
    subprocess.run(
        ["callgrind_control", "-i", "on" if on else "off", str(os.getpid())],
        capture_output=True,
        check=False,
    )


#: settled beds: name -> bench_solver.settled_simulation arguments (n, accel_g, e1, shaken);
#: the larger elastic beds at rest are tools/bench/threads.py's
BEDS = {
    "settled_512": (512, 0.0, 0.0, False),
    "settled_visco_512": (512, 0.0, 5e6, False),
    "shaken_visco_512": (512, 2.0, 5e6, True),
    "settled_4096": (4096, 0.0, 0.0, False),
    "settled_16384": (16384, 0.0, 0.0, False),
}


#: the base motion of ``shaker_base`` (tests/golden/cases.json's shaker_fig9 case)
SHAKER_BASE = "node=4,dof=2,amp=0.02,hz=36.75"


def _bed_file(scene: str) -> Path:
    return Path(tempfile.gettempdir()) / f"x3dpd-bench-{scene}.pkl"


def prepare_bed(scene: str) -> None:
    """Settle the bed natively (and shake it for two drive periods) and pickle its state; a
    MIP scene runs natively until its spheres fly (tools/bench/mip_scene.py)."""
    from bench_solver import settled_simulation

    if scene.startswith("mip_"):
        from mip_scene import SETTLE, mip_model

        sim = Simulation(mip_model(int(scene[4:])), itrac=10**9)
        sim.advance(round(SETTLE / sim.dt), max_rows=1)
        _bed_file(scene).write_bytes(pickle.dumps((sim.state, 0.0)))
        print(f"{scene}: state at step {sim.state.step} in {_bed_file(scene)}")
        return
    n, accel_g, e1, shaken = BEDS[scene]
    sim, sc = settled_simulation(n, 300_000, accel_g, e1, shaken)
    t0 = sim.time  # the drive's start
    if shaken:
        sim.advance(2 * round(1.0 / (sc["shake_freq_hz"] * sc["dt"])), max_rows=1)
    _bed_file(scene).write_bytes(pickle.dumps((sim.state, t0)))
    print(f"{scene}: state at step {sim.state.step} in {_bed_file(scene)}")


def bed_simulation(scene: str) -> Simulation:
    """The prepared bed, restored into the simulation that shakes it (or not)."""
    from bench_solver import SHAKEN_CAVITY_MASS, G, scene_model

    if scene.startswith("mip_"):
        from mip_scene import mip_model

        sim = Simulation(mip_model(int(scene[4:])), itrac=10**9)
        sim.restore(pickle.loads(_bed_file(scene).read_bytes())[0])
        return sim
    n, accel_g, e1, shaken = BEDS[scene]
    state, t0 = pickle.loads(_bed_file(scene).read_bytes())
    model, sc = scene_model(n, drive=False, e1=e1, free_cavity=shaken)
    usrfrc = ()
    if shaken:
        # the drive as bench_solver.settled_simulation started it (t0: the settling's end)
        usrfrc = (
            f"sine:node=9,dof=1,amp={SHAKEN_CAVITY_MASS * accel_g * G!r},"
            f"hz={sc['shake_freq_hz']!r},phase=90,t0={t0!r}",
        )
    sim = Simulation(model, itrac=10**9, usrfrc=usrfrc)
    sim.restore(state)
    return sim


def main(argv: list[str]) -> int:
    if argv[1] == "--prepare":
        prepare_bed(argv[2])
        return 0
    scene, steps = argv[1], int(argv[2])
    if scene in BEDS or scene.startswith("mip_"):
        sim = bed_simulation(scene)
    elif scene == "sdof":
        from bench_solver import sdof_model

        sim = Simulation(sdof_model(), itrac=10**9)
    elif scene.startswith("bench"):
        from bench_solver import scene_model

        sim = Simulation(scene_model(int(scene[5:]))[0])
    else:
        stem, motion = ("shaker_fig9", (SHAKER_BASE,)) if scene == "shaker_base" else (scene, ())
        deck = read_deck(ROOT / "decks" / f"{stem}.inp")
        deck = replace(deck, parameters=replace(deck.parameters, itrac=10**9))
        sim = Simulation(build_model(deck, motion=motion), motion=motion)
    if scene not in BEDS and not scene.startswith("mip_"):  # a bed is restored, lists built
        sim.advance(4000, max_rows=1)
    sim.advance(10, max_rows=1)
    _instrument(True)
    sim.advance(steps, max_rows=1)
    _instrument(False)
    print(f"{scene}: {steps} steps counted (step {sim.state.step})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
