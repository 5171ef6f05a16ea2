"""Step time of settled beds at 1 and 2 threads (the run option ``threads``; docs/engine.md,
"Threads"), the speedup, and what Amdahl's law makes of the part that runs threaded.

    python tools/bench/threads.py                 # 512, 4096 and 16,384 spheres, 1 and 2 threads
    python tools/bench/threads.py --quick         # 512 and 4096, two short windows each
    python tools/bench/threads.py --n 4096 --threads 1 2 4 8   # a machine with more cores

Each bed is ``bench_solver.py --settled``'s elastic bed of N spheres at rest (N falling spheres
settled for 300,000 steps, once: 11 minutes for 4096 spheres on the shared 2-core machine), kept
in the temporary folder (the file of ``count_instructions.py --prepare settled_N``). Both thread
counts restore the same state in this process and are timed in turn, ``--repeat`` windows of
``--steps`` steps each, the best kept (bench_solver's ``best_seconds_per_step``); their final
states must be the same bytes (checked; exit 1 if not). Columns: contacts per sphere (2 x pair +
wall contacts, / N), microseconds per step at each thread count, the speedup over 1 thread, the
threaded share f: the CPU time of the threaded passes (filter and response, ``_pair_chunks``,
called alone on the bed's state at one thread) over a step's at one thread, the apply pass's
share (all three passes' minus f; the rest of the step is walls, integration and lists), and
Amdahl's estimate 1 / ((1 - f) + f / p) for p threads. Wall time: run it on an idle machine (a
busy core stalls every threaded pass).
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import math
import os
import pickle
import sys
import tempfile
import time
from pathlib import Path

# numba reads its thread limit once, at import: room for every count asked for (the bench
# scripts default it to 1)
_ASKED = (
    [int(a) for a in sys.argv[sys.argv.index("--threads") + 1 :] if a.isdigit()]
    if "--threads" in sys.argv
    else [2]
)
os.environ["NUMBA_NUM_THREADS"] = str(max(_ASKED + [2]))

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import numpy as np  # noqa: E402
from bench_solver import best_seconds_per_step, scene_model, settled_simulation  # noqa: E402

from x3dpd._jit import kernel  # noqa: E402
from x3dpd.solver.simulation import Simulation  # noqa: E402
from x3dpd.solver.variants import part_module  # noqa: E402

SIZES = (512, 4096, 16384)
QUICK_SIZES = (512, 4096)
SETTLE_STEPS = 300_000


def bed_state(n: int, settle_steps: int = SETTLE_STEPS):
    """The settled bed's state, from the temporary folder or settled now (and kept there)."""
    path = Path(tempfile.gettempdir()) / f"x3dpd-bench-settled_{n}.pkl"
    if path.exists():
        return pickle.loads(path.read_bytes())[0]
    print(f"settling {n} spheres for {settle_steps} steps (once; kept in {path}) ...", flush=True)
    sim, _ = settled_simulation(n, settle_steps)
    tmp = path.with_suffix(f".tmp{os.getpid()}")
    tmp.write_bytes(pickle.dumps((sim.state, sim.time)))
    os.replace(tmp, path)
    return sim.state


def pass_seconds(sim: Simulation, calls: int, whole: bool) -> float:
    """CPU seconds per call, on ``sim``'s current state in this thread's thread count, of the
    threaded variant's pair passes 1 and 2 (``_pair_chunks``) or (``whole``) of all three
    passes (``_pair_contacts``). The first two write only scratch columns, the third the same
    states again and more force, so repeated calls do the same work."""
    mod = part_module(sim.kernels, "pair_passes")
    chunks, contacts, size = mod._pair_chunks, mod._pair_contacts, mod.PAIR_CHUNK

    def repeat(k, nodes, particles, pairs, stepping):
        npairs = pairs.count[0]
        for _ in range(k):
            c = pairs.columns
            if whole:
                contacts(nodes, particles, pairs, stepping, pairs.first_new)
            else:
                chunks(
                    (npairs + size - 1) // size,
                    npairs,
                    nodes.x,
                    nodes.vel,
                    particles.p0,
                    particles.radius,
                    pairs.first,
                    pairs.second,
                    pairs.on,
                    pairs.state,
                    pairs.first_new,
                    c,
                    pairs.history,
                    pairs.second_new,
                    particles,
                    stepping.dt,
                    stepping.history_dt,
                )

    run = kernel(repeat, cache=False)
    b = sim._bundles()
    args = (b["nodes"], b["particles"], b["pairs"], b["stepping"])
    run(1, *args)
    best = math.inf
    for _ in range(3):
        t = time.process_time()
        run(calls, *args)
        best = min(best, (time.process_time() - t) / calls)
    return best


def same_bytes(a, b) -> bool:
    return all(
        np.array_equal(getattr(a, f.name), getattr(b, f.name))
        for f in dataclasses.fields(a)
        if isinstance(getattr(a, f.name), np.ndarray)
    )


def measure(n: int, counts, steps: int, repeat: int) -> dict:
    state = bed_state(n)
    model, _ = scene_model(n, drive=False)
    sims = {}
    for p in counts:
        sim = Simulation(model, itrac=10**9, threads=p)
        sim.restore(copy.deepcopy(state))
        sim.advance(20, max_rows=1)  # compile or load, lists in place
        sims[p] = sim
    best = best_seconds_per_step(sims, steps, repeat)
    st = sims[counts[0]].state
    pairs_on = int(st.pl_on[: int(st.npl[0])].sum())
    walls_on = int(st.wl_on[: int(st.nwl[0])].sum())
    identical = all(same_bytes(st, sims[p].state) for p in counts[1:])
    # the threaded share of a step, in CPU time at one thread (load inflates both alike)
    threaded = next((sims[p] for p in counts if p > 1), None)
    f = apply = math.nan
    if threaded is not None and threaded.variant.threaded:
        from x3dpd.solver.threads import use_threads

        # the threaded loop in one thread (a Simulation asks for its own count at every call)
        asked, threaded.threads = threaded.threads, 1
        use_threads(1)
        step_cpu = math.inf
        for _ in range(3):  # the best of three windows, as for the passes alone
            t = time.process_time()
            threaded.advance(steps, max_rows=1)
            step_cpu = min(step_cpu, (time.process_time() - t) / steps)
        threaded.threads = asked
        snapshot = copy.deepcopy(threaded.state)
        f = pass_seconds(threaded, steps, whole=False) / step_cpu
        apply = pass_seconds(threaded, steps, whole=True) / step_cpu - f
        threaded.restore(snapshot)
    return {
        "n": n,
        "contacts_per_sphere": (2 * pairs_on + walls_on) / n,
        "candidates": int(st.npl[0]),
        "us": {p: best[p] * 1e6 for p in counts},
        "identical": identical,
        "threaded_share": f,
        "apply_share": apply,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", help=f"bed sizes [default: {SIZES}]")
    ap.add_argument(
        "--threads",
        type=int,
        nargs="+",
        default=[1, 2],
        help="thread counts to time (the first is the reference) [default: 1 2]",
    )
    ap.add_argument("--steps", type=int, default=500, help="steps per timed window")
    ap.add_argument("--repeat", type=int, default=3, help="windows per thread count")
    ap.add_argument(
        "--quick",
        action="store_true",
        help=f"beds {QUICK_SIZES}, 2 windows of 100 steps: proves the tool works, "
        "measures little (the beds are settled fully, once)",
    )
    args = ap.parse_args(argv)
    sizes = args.n or (QUICK_SIZES if args.quick else SIZES)
    steps, repeat = (100, 2) if args.quick else (args.steps, args.repeat)
    counts = args.threads
    head = (
        f"{'spheres':>8} {'contacts/sphere':>15} "
        + " ".join(f"{f'{p} thr us/step':>14}" for p in counts)
        + " "
        + " ".join(f"{f'speedup {p}':>10}" for p in counts[1:])
        + f" {'threaded f':>10} {'apply':>6} {'Amdahl 4/8/16':>16}  same bytes"
    )
    print(head)
    status = 0
    for n in sizes:
        r = measure(n, counts, steps, repeat)
        us = r["us"]
        f = r["threaded_share"]
        amdahl = (
            "/".join(f"{1.0 / ((1.0 - f) + f / p):.2f}" for p in (4, 8, 16))
            if math.isfinite(f)
            else "-"
        )
        print(
            f"{n:>8} {r['contacts_per_sphere']:>15.2f} "
            + " ".join(f"{us[p]:>14.1f}" for p in counts)
            + " "
            + " ".join(f"{us[counts[0]] / us[p]:>10.2f}" for p in counts[1:])
            + f" {f:>10.2f} {r['apply_share']:>6.2f} {amdahl:>16}  "
            f"{'yes' if r['identical'] else 'NO'}",
            flush=True,
        )
        if not r["identical"]:
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
