"""Where a settled bed's step time goes: the pair-contact pass timed alone, whole and with parts
of its friction code removed.

    python tools/bench/contact_costs.py [--n 512] [--calls 2000]

Settles the benchmark bed (``bench_solver.py --settled``: 300,000 steps at rest), then calls the
scene's compiled ``_pair_contacts`` (the variant's copy of
``x3dpd/solver/_template_pair_passes.py``, running the passes of ``_template_pairs.py``)
``--calls`` times on that frozen state (forces zeroed each
call) and reports microseconds per call for the kernel as compiled and for copies of its source
with one part cut out: the whole friction block, the torques of friction, and its slip-work
bookkeeping. The cut copies compute wrong forces on purpose; they only measure what each part
costs. The difference to the full kernel is that part's cost.
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

from x3dpd._jit import kernel  # noqa: E402
from x3dpd.solver.simulation import Simulation  # noqa: E402
from x3dpd.solver.variants import part_module  # noqa: E402

#: name -> (text in the kernel module, replacement)
CUTS = {
    "friction": (
        "        if HAS_FRICTION:\n            wix = vel[i, 3]",
        "        if HAS_FRICTION and nbusy < 0:\n            wix = vel[i, 3]",
    ),
    "friction torques": (
        "            tx = ny * ftz - nz * fty\n"
        "            ty = nz * ftx - nx * ftz\n"
        "            tz = nx * fty - ny * ftx\n",
        "",
    ),
    "friction slip work": (
        "    lost = -0.5 * ((ftx_old + ftx) * vtx + (fty_old + fty) * vty"
        " + (ftz_old + ftz) * vtz) * dt",
        "    lost = 0.0",
    ),
}


def _load(name: str, path: Path, text: str):
    """Write ``text`` to ``path`` and import it as module ``name``."""
    path.write_text(text)
    spec = importlib.util.spec_from_file_location(name, path)
    sys.modules[name] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(sys.modules[name])
    return sys.modules[name]


def time_pair_pass(pair_pass, sim: Simulation, calls: int) -> float:
    """Microseconds per call of ``pair_pass``: a variant's ``_pair_contacts``
    (x3dpd.solver.variants.part_module(..., "pair_passes")) or a cut copy's."""
    b = sim._bundles()
    busy = np.zeros(b["pairs"].first.shape[0], dtype=np.int64)

    def repeat(k, nodes, particles, pairs, stepping, busy):
        status = 0
        for _ in range(k):
            nodes.force[:, :] = 0.0
            status |= pair_pass(nodes, particles, pairs, stepping, busy)
        return status

    run = kernel(repeat, cache=False)
    args = (b["nodes"], b["particles"], b["pairs"], b["stepping"], busy)
    state0, on0, force0 = b["pairs"].state.copy(), b["pairs"].on.copy(), b["nodes"].force.copy()
    run(1, *args)
    best = float("inf")
    for _ in range(5):
        t = time.perf_counter()
        run(calls, *args)
        best = min(best, (time.perf_counter() - t) / calls)
    b["pairs"].state[:], b["pairs"].on[:], b["nodes"].force[:] = state0, on0, force0
    return best * 1e6


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=512)
    ap.add_argument("--calls", type=int, default=2000)
    args = ap.parse_args()
    model, _ = scene_model(args.n, drive=False)
    sim = Simulation(model, itrac=10**9)
    sim.initialize()
    sim.advance(300_000, max_rows=1)
    st = sim.state
    contacts = int(st.pl_on[: int(st.npl[0])].sum())
    pairs_mod, contact_mod, passes_mod = (
        part_module(sim.kernels, p) for p in ("pairs", "contact", "pair_passes")
    )
    source = Path(pairs_mod.__file__).read_text()  # the variant's pair passes
    contact_source = Path(contact_mod.__file__).read_text()  # friction lives there
    passes_source = Path(passes_mod.__file__).read_text()  # runs them
    full = time_pair_pass(passes_mod._pair_contacts, sim, args.calls)
    print(
        f"settled bed of {args.n}: {contacts} pair contacts; pair-contact pass "
        f"{full:.2f} us/call ({full * 1e3 / max(contacts, 1):.1f} ns per contact)"
    )
    with tempfile.TemporaryDirectory() as tmp:
        for name, (old, new) in CUTS.items():
            stem = f"cut_{name.replace(' ', '_')}"
            cut_pairs = source
            if source.count(old) == 1:
                cut_pairs = source.replace(old, new)
            elif contact_source.count(old) == 1:
                # a cut copy of the shared contact part, imported by a copy of the pair part
                _load(
                    f"{stem}_contact",
                    Path(tmp) / f"{stem}_contact.py",
                    contact_source.replace(old, new),
                )
                cut_pairs = source.replace(
                    f"from {contact_mod.__name__} import", f"from {stem}_contact import"
                )
            else:
                print(f"  {name}: its code was not found in the kernel (changed?)")
                continue
            # the cut pair part, and a copy of the part that runs it importing it
            _load(f"{stem}_pairs", Path(tmp) / f"{stem}_pairs.py", cut_pairs)
            passes = _load(
                f"{stem}_passes",
                Path(tmp) / f"{stem}_passes.py",
                passes_source.replace(
                    f"from {pairs_mod.__name__} import", f"from {stem}_pairs import"
                ),
            )
            cut = time_pair_pass(passes._pair_contacts, sim, args.calls)
            print(f"  {name:20s} costs {full - cut:6.2f} us/call")
    return 0


if __name__ == "__main__":
    sys.exit(main())
