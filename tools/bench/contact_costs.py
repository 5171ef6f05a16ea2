"""Where a settled bed's step time goes: the whole step, the part outside the contact passes,
and the contact passes timed alone on the frozen state, whole and with parts cut out.

    python tools/bench/contact_costs.py [--bed settled_512] [--n 512] [--calls 2000]

Takes the benchmark bed at rest (``--bed``: a bed prepared by ``count_instructions.py
--prepare``, restored; without it ``bench_solver.py --settled``'s bed of ``--n`` spheres,
settled here for 300,000 steps) and reports microseconds of this process's CPU time
(``time.process_time``: on a machine others share, wall time counts their work too),
each the best of five windows:

- the whole step (``Simulation.advance`` from the bed's state), and the step of a copy of the
  scene's loop without its two contact passes (integration, the rigid cavity, the list check:
  the particles then fall freely, which costs these parts no more);
- the wall contacts' pass (``_template_walls.py``) and the pair contacts' passes
  (``_template_pair_passes.py``), called ``--calls`` times on the frozen state; for the pairs
  also copies of their source cut after the filter, before the apply pass, and without the
  apply pass's force and moment updates (the list-order scatter): a part's cost is the
  difference.

The frozen state is the step's only where the contacts' histories do not drift from call to
call: an elastic bed's (the default). A viscoelastic bed's Maxwell terms step on from each call's
outputs when the apply pass stores them and stand still when it is cut, so there the parts need
not add up. Cutting a contact pass out of the running step would not measure it either: without
its forces the bed unloads within a contact time and the other pass's contacts open. The cut
copies compute wrong forces on purpose; a cut whose code is no longer in the source stops the
tool (exit 1) rather than report a wrong cost.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import numpy as np  # noqa: E402
from bench_solver import scene_model  # noqa: E402
from count_instructions import BEDS, bed_simulation  # noqa: E402

from x3dpd._jit import kernel  # noqa: E402
from x3dpd.solver.simulation import Simulation  # noqa: E402
from x3dpd.solver.variants import part_module  # noqa: E402

#: the step loop without its wall and pair contact passes: (text, replacement) in the loop's
#: module (the variant's copy of ``_advance_template.py``)
NO_CONTACTS = (
    (
        "        status |= _wall_contacts(nodes, particles, faces, walls, stepping,",
        "        if t < 0.0:  # never: the cut\n"
        "            status |= _wall_contacts(nodes, particles, faces, walls, stepping,",
    ),
    (
        "        status |= _pair_contacts(nodes, particles, pairs, stepping, pairs.first_new)",
        "        if t < 0.0:  # never: the cut\n"
        "            status |= _pair_contacts(nodes, particles, pairs, stepping, pairs.first_new)",
    ),
)
#: the pair apply pass without its force and moment updates: (text, replacement) in the pair
#: part (``_template_pairs.py``); the forces and moments go into a sum the pass returns, so
#: that the compiler keeps reading them
NO_SCATTER = (
    (
        "            force[i, 3] -= c[_entry(C_TIX, e)]\n"
        "            force[i, 4] -= c[_entry(C_TIY, e)]\n"
        "            force[i, 5] -= c[_entry(C_TIZ, e)]\n"
        "            force[j, 3] -= c[_entry(C_TJX, e)]\n"
        "            force[j, 4] -= c[_entry(C_TJY, e)]\n"
        "            force[j, 5] -= c[_entry(C_TJZ, e)]\n",
        "            w_roll += c[_entry(C_TIX, e)] + c[_entry(C_TIY, e)] + c[_entry(C_TIZ, e)]\n"
        "            w_roll += c[_entry(C_TJX, e)] + c[_entry(C_TJY, e)] + c[_entry(C_TJZ, e)]\n",
    ),
    (
        "        force[j, 0] += fx\n"
        "        force[j, 1] += fy\n"
        "        force[j, 2] += fz\n"
        "        force[i, 0] -= fx\n"
        "        force[i, 1] -= fy\n"
        "        force[i, 2] -= fz\n",
        "        w_roll += fx + fy + fz + float(i + j)\n",
    ),
)
#: the pair passes with the filter alone, and with the filter and the response: (text,
#: replacement) in the part that runs them (``_template_pair_passes.py``)
FILTER_ONLY = (
    (
        "        # pass 2: the contact response, from columns into columns",
        "        continue  # the cut\n"
        "        # pass 2: the contact response, from columns into columns",
    ),
)
NO_APPLY = (
    (
        "        # pass 3: states, forces and the ledger, the sums chained through the blocks",
        "        continue  # the cut\n"
        "        # pass 3: states, forces and the ledger, the sums chained through the blocks",
    ),
)


def _cut(source: str, cuts, what: str) -> str:
    for old, new in cuts:
        if source.count(old) != 1:
            raise SystemExit(
                f"contact_costs: the code the cut '{what}' removes was not found "
                "(changed?); update the cut"
            )
        source = source.replace(old, new)
    return source


def _load(name: str, path: Path, text: str):
    """Write ``text`` to ``path`` and import it as module ``name``."""
    path.write_text(text)
    spec = importlib.util.spec_from_file_location(name, path)
    sys.modules[name] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(sys.modules[name])
    return sys.modules[name]


def _best_per_call(run, calls: int, *args) -> float:
    """Microseconds per call of ``run(k, *args)`` (k calls): the best of five windows."""
    run(1, *args)
    best = float("inf")
    for _ in range(5):
        t = time.process_time()
        run(calls, *args)
        best = min(best, (time.process_time() - t) / calls)
    return best * 1e6


def step_time(sim: Simulation, steps: int) -> float:
    """Microseconds per step of ``sim`` from its state: the best of five windows, each from the
    same state (put back afterwards)."""
    state = sim.state.copy()
    best = float("inf")
    for _ in range(5):
        sim.restore(state.copy())
        t = time.process_time()
        sim.advance(steps, max_rows=1)
        best = min(best, (time.process_time() - t) / steps)
    sim.restore(state)
    return best * 1e6


def cut_modules(sim: Simulation, tmp: Path, tag: str, cuts: dict) -> dict:
    """Copies of the scene's kernel modules with ``cuts`` = {part: ((text, replacement), ...)}
    applied to its parts ("pairs", "pair_passes") or to the loop itself ("loop"): each cut part
    is loaded as a module of its own, and the parts that import it (up to the loop) as copies
    importing the cut one. Returns {part: module} of the copies."""
    chain = ("pairs", "pair_passes", "loop")
    modules = {p: part_module(sim.kernels, p) for p in chain[:2]}
    modules["loop"] = sim.kernels
    renamed, out = {}, {}
    for part in chain[min(chain.index(p) for p in cuts) :]:
        source = Path(modules[part].__file__).read_text()
        if part in cuts:
            source = _cut(source, cuts[part], f"{tag}: {part}")
        for old, new in renamed.items():
            source = source.replace(f"from {old} import", f"from {new} import")
        name = f"cut_{tag}_{part}"
        renamed[modules[part].__name__] = name
        out[part] = _load(name, tmp / f"{name}.py", source)
    return out


def frozen_times(sim: Simulation, pair_pass, wall_pass, calls: int) -> tuple[float, float]:
    """Microseconds per call of a pair-contact pass ``pair_pass`` (a ``_pair_contacts``) and of
    the wall pass ``wall_pass`` on the frozen state (contact states, open flags and forces put
    back afterwards). Compiled like the loop: without reference counting."""
    b = sim._bundles()
    nodes, particles, pairs, walls, faces, stepping = (
        b[k] for k in ("nodes", "particles", "pairs", "walls", "faces", "stepping")
    )
    busy = np.zeros(pairs.first.shape[0], dtype=np.int64)

    def pair_calls(k, nodes, particles, pairs, stepping, busy):
        status = 0
        for _ in range(k):
            status |= pair_pass(nodes, particles, pairs, stepping, busy)
        return status

    def wall_calls(k, nodes, particles, faces, walls, stepping):
        status = 0
        for _ in range(k):
            status |= wall_pass(
                nodes, particles, faces, walls, stepping, stepping.small[6:9], walls.first_new
            )
        return status

    kept = [a.copy() for a in (pairs.state, pairs.on, walls.state, walls.on, nodes.force)]
    pair_us = _best_per_call(
        kernel(pair_calls, cache=False, _nrt=False), calls, nodes, particles, pairs, stepping, busy
    )
    wall_us = _best_per_call(
        kernel(wall_calls, cache=False, _nrt=False), calls, nodes, particles, faces, walls, stepping
    )
    for a, keep in zip((pairs.state, pairs.on, walls.state, walls.on, nodes.force), kept):
        a[...] = keep
    return pair_us, wall_us


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=512)
    ap.add_argument("--bed", choices=sorted(BEDS), help="a prepared bed (count_instructions.py)")
    ap.add_argument("--calls", type=int, default=2000, help="pass calls per timed window")
    ap.add_argument("--steps", type=int, default=4000, help="steps per timed window")
    args = ap.parse_args()
    if args.bed:
        sim = bed_simulation(args.bed)
        sim.advance(10, max_rows=1)
    else:
        model, _ = scene_model(args.n, drive=False)
        sim = Simulation(model, itrac=10**9)
        sim.initialize()
        sim.advance(300_000, max_rows=1)
    st = sim.state
    pair_on = int(st.pl_on[: int(st.npl[0])].sum())
    wall_on = int(st.wl_on[: int(st.nwl[0])].sum())
    walls = part_module(sim.kernels, "walls")._wall_contacts
    t = {"step": step_time(sim, args.steps)}
    t["pairs"], t["walls"] = frozen_times(
        sim, part_module(sim.kernels, "pair_passes")._pair_contacts, walls, args.calls
    )
    cuts = {
        "filter": {"pair_passes": FILTER_ONLY},
        "no_apply": {"pair_passes": NO_APPLY},
        "no_scatter": {"pairs": NO_SCATTER},
    }
    loop = sim.kernels
    with tempfile.TemporaryDirectory() as tmp:
        for tag, cut in cuts.items():
            copies = cut_modules(sim, Path(tmp), tag, cut)
            t[tag] = frozen_times(sim, copies["pair_passes"]._pair_contacts, walls, args.calls)[0]
        sim.kernels = cut_modules(sim, Path(tmp), "no_contacts", {"loop": NO_CONTACTS})["loop"]
        t["no_contacts"] = step_time(sim, args.steps)
        sim.kernels = loop
    # (name, microseconds, per what count, note)
    rows = (
        ("whole step", t["step"], 0, ""),
        (
            "  outside the contact passes",
            t["no_contacts"],
            0,
            "integration, rigid cavity, list check",
        ),
        ("pair contacts, the three passes", t["pairs"], pair_on, f"{int(st.npl[0])} candidates"),
        ("  filter", t["filter"], pair_on, "gathers the columns"),
        ("  response", t["no_apply"] - t["filter"], pair_on, "vectorized"),
        ("  apply", t["pairs"] - t["no_apply"], pair_on, "states, forces, ledger"),
        (
            "    of which the force scatter",
            t["pairs"] - t["no_scatter"],
            pair_on,
            "12 read-modify-writes per contact",
        ),
        ("wall contacts", t["walls"], wall_on, ""),
    )
    print(
        f"settled bed ({args.bed or f'n={args.n}'}): {pair_on} pair and {wall_on} wall "
        "contacts; best of five windows"
    )
    for name, us, count, note in rows:
        per = f"{us * 1e3 / count:6.1f} ns per contact" if count else ""
        print(f"  {name:32s} {us:8.2f} us  {per:22s} {note}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
