"""What a settled bed's contacts do per step: how many are open, how many open and close (churn),
how many slide, how often the candidate lists are rebuilt -- the counts behind a bed's step
time (tools/bench/README.md, "The shaken bed").

    python tools/bench/bed_stats.py BED [--steps 4000] [--every 1] [--from-start] [--series]

BED is one of count_instructions.py's beds (``settled_512``, ``settled_visco_512``,
``shaken_visco_512``), prepared once with ``count_instructions.py --prepare BED``. The bed is
restored and advanced ``--every`` steps at a time; after each call the pair and wall lists are
read: contacts open (state approach > 0 or a force), contacts that opened or closed since the
last look (pairs matched by their particles across list rebuilds), and the pair contacts that
slide, |F_t| >= 0.999 mu F_N (the regularised law's Coulomb branch; mu = 0.3 for every
sphere). First the same window is run in one call and its CPU time per step measured
(``time.process_time``), then the bed is restored and looked at. Prints the means per step
(per look when ``--every`` > 1) and per sphere;
``--series`` also each look's contacts per sphere. ``--from-start`` settles the bed afresh and
starts at the beginning of its shake (the prepared shaken bed is two periods into it):
``bed_stats.py shaken_visco_512 --from-start --every 4000 --steps 108000 --series`` is the
README's table of the bed loosening.
"""

from __future__ import annotations

import argparse
import copy
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from count_instructions import BEDS, bed_simulation  # noqa: E402

from x3dpd.solver.contact_lists import S_A, S_FN, S_FT  # noqa: E402

MU = 0.3


def _open_pairs(st) -> set:
    n = int(st.npl[0])
    on = st.pl_on[:n] != 0
    return set(zip(st.pl_i[:n][on].tolist(), st.pl_j[:n][on].tolist()))


def _open_walls(st) -> set:
    n = int(st.nwl[0])
    on = st.wl_on[:n] != 0
    return set(zip(st.wl_p[:n][on].tolist(), st.wl_f[:n][on].tolist()))


def bed_stats(
    bed: str, steps: int, every: int = 1, from_start: bool = False, series: bool = False
) -> dict:
    """Means per look over ``steps`` steps of the prepared ``bed`` (module docstring)."""
    if from_start:
        from bench_solver import settled_simulation

        sim, sc = settled_simulation(*BEDS[bed][:1], 300_000, *BEDS[bed][1:])
        period = 1.0 / (sc["shake_freq_hz"] * sc["dt"])
    else:
        sim = bed_simulation(bed)
    # CPU time per step of one advance call over the window, before the looks (the process's
    # own CPU time: less sensitive to other processes than wall time, not immune to them)
    snapshot = copy.deepcopy(sim.state)
    cpu = time.process_time()
    sim.advance(steps, max_rows=1)
    cpu_us = (time.process_time() - cpu) / steps * 1e6
    sim.restore(snapshot)
    st = sim.state
    step0 = st.step
    pairs, walls = _open_pairs(st), _open_walls(st)
    rebuilds0 = int(st.nbr[2])
    looks = steps // every
    acc = {
        k: 0.0
        for k in (
            "pair_open",
            "wall_open",
            "pair_opened",
            "pair_closed",
            "wall_opened",
            "wall_closed",
            "pair_sliding",
        )
    }
    for _ in range(looks):
        sim.advance(every, max_rows=1)
        st = sim.state
        new_pairs, new_walls = _open_pairs(st), _open_walls(st)
        acc["pair_open"] += len(new_pairs)
        acc["wall_open"] += len(new_walls)
        acc["pair_opened"] += len(new_pairs - pairs)
        acc["pair_closed"] += len(pairs - new_pairs)
        acc["wall_opened"] += len(new_walls - walls)
        acc["wall_closed"] += len(walls - new_walls)
        n = int(st.npl[0])
        ps = st.ps[:n][(st.pl_on[:n] != 0) & (st.ps[:n, S_A] > 0.0)]
        ft = np.sqrt((ps[:, S_FT : S_FT + 3] ** 2).sum(axis=1))
        acc["pair_sliding"] += int((ft >= 0.999 * MU * ps[:, S_FN]).sum())
        pairs, walls = new_pairs, new_walls
        if series:
            n_sph = sim.model.n_particles
            t = f"t/T {(st.step - step0) / period:5.2f} " if from_start else ""
            print(
                f"step {st.step - step0:7d} {t}sphere-sphere {2 * len(new_pairs) / n_sph:.2f} "
                f"wall {len(new_walls) / n_sph:.2f}",
                flush=True,
            )
    out = {k: v / looks for k, v in acc.items()}
    n_spheres = sim.model.n_particles
    out.update(
        bed=bed,
        steps=looks * every,
        every=every,
        pair_per_sphere=2 * out["pair_open"] / n_spheres,
        wall_per_sphere=out["wall_open"] / n_spheres,
        sliding_fraction=out["pair_sliding"] / max(out["pair_open"], 1e-300),
        rebuilds_per_1000_steps=1000.0 * (int(st.nbr[2]) - rebuilds0) / (looks * every),
        cpu_us_per_step=cpu_us,
    )
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bed", choices=list(BEDS))
    ap.add_argument("--steps", type=int, default=4000)
    ap.add_argument("--every", type=int, default=1)
    ap.add_argument(
        "--from-start",
        action="store_true",
        help="settle afresh and start at the beginning of the shake",
    )
    ap.add_argument("--series", action="store_true", help="print every look's contacts")
    args = ap.parse_args(argv)
    r = bed_stats(args.bed, args.steps, args.every, args.from_start, args.series)
    print(
        f"{r['bed']}: {r['steps']} steps, per {'step' if r['every'] == 1 else 'look'}: "
        f"{r['pair_open']:.1f} pair + {r['wall_open']:.1f} wall contacts open "
        f"({r['pair_per_sphere']:.2f} + {r['wall_per_sphere']:.2f} per sphere); "
        f"pairs opened {r['pair_opened']:.2f}, closed {r['pair_closed']:.2f}; walls opened "
        f"{r['wall_opened']:.2f}, closed {r['wall_closed']:.2f}; sliding pairs "
        f"{r['pair_sliding']:.1f} ({100 * r['sliding_fraction']:.0f} %); list rebuilds "
        f"{r['rebuilds_per_1000_steps']:.2f} per 1000 steps; CPU time "
        f"{r['cpu_us_per_step']:.1f} us per step"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
