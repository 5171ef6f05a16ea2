"""Check that the pair contacts' law loop (``_pair_response``) is vectorized: its machine code
holds packed square roots and divisions (``vsqrtpd``, ``vdivpd``) for every tangential law,
with Maxwell histories and with the rolling law, and -- when all particles are alike, so
that the loop reads its gathered columns only -- no gather instruction.

    python tools/bench/check_vector.py [--asm]     # exit 1 if a variant's loop is scalar

Each variant's response is compiled afresh from the generated step-loop source (not from the
kernel cache, whose machine code carries no assembly text) with the flags of
``x3dpd._jit.vector_kernel``; a few seconds per variant. ``--asm`` prints the loop's packed
instructions. There is no ``vfmadd``: fastmath stays off (x3dpd._jit), so LLVM may not fuse a
multiply and an add, which would round differently from the scalar code and the goldens.
"""

from __future__ import annotations

import argparse
import collections
import dataclasses
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402
from bench_solver import scene_model  # noqa: E402

from x3dpd._jit import kernel, vector_kernel  # noqa: E402
from x3dpd.solver.simulation import Simulation  # noqa: E402
from x3dpd.solver.variants import make_advance, part_module  # noqa: E402

#: name -> (scene_model keywords, friction law, rolling law, one particle kind)
VARIANTS = {
    "regularized_elastic": ({}, "regularized", "none", True),
    "regularized_visco": ({"e1": 5e6}, "regularized", "none", True),
    "coulomb_visco": ({"e1": 5e6}, "coulomb", "none", True),
    "mindlin_visco": ({"e1": 5e6}, "mindlin", "none", True),
    "mindlin_rolling": ({"e1": 5e6}, "mindlin", "epsd", True),
    "regularized_kinds": ({"e1": 5e6}, "regularized", "none", False),
}
PACKED = re.compile(r"^\s+(v(?:sqrt|div|mul|add|sub|fmadd\d*|gather[dq])p[sd])\s", re.M)


def response_asm(
    scene: dict, friction: str, rolling: str, one_kind: bool, noalias: bool = True
) -> str:
    """Assembly of the variant's ``_pair_response``, compiled afresh for the argument types
    the step loop passes (a 64-sphere bench scene's bundles); ``noalias`` False compiles it
    without vector_kernel's ``noalias`` (then LLVM cannot prove the columns apart and keeps the
    loop scalar: what the check must catch)."""
    model, _ = scene_model(64, **scene)
    if rolling != "none":
        p = model.n_particles
        model = dataclasses.replace(
            model,
            rolling_law=rolling,
            mu_roll=np.full(p, 0.05),
            friction_law=friction,
            mu_kinetic=np.full(p, 0.25),
        )
    sim = Simulation(model, itrac=10**9, friction=friction)
    variant = dataclasses.replace(sim.variant, one_particle_kind=one_kind)
    pairs = part_module(make_advance(variant), "pairs")
    b = sim._bundles()
    pl, particles = b["pairs"], b["particles"]
    if noalias:
        fresh = vector_kernel(pairs._pair_response.py_func, cache=False)
    else:
        fresh = kernel(pairs._pair_response.py_func, cache=False, inline="never", _nrt=False)
    # the first area's columns, as the loop hands them over (x3dpd.solver.contact_lists)
    rows = pl.columns.reshape(-1, pairs.COLUMN_ROW)
    cin = tuple(rows[pairs.C_DX + k] for k in range(len(pairs.PAIR_INPUT_COLUMNS)))
    cout = tuple(rows[k] for k in range(len(pairs.PAIR_OUTPUT_COLUMNS)))
    fresh(0, 0, pl.first_new, pl.first, pl.second, particles, pl.history, sim.dt, cin, cout, sim.dt)
    return fresh.inspect_asm(fresh.signatures[0])


def packed_instructions(asm: str) -> collections.Counter:
    """Packed (xmm/ymm/zmm, ``...pd``) arithmetic and gathers in ``asm``, by mnemonic."""
    return collections.Counter(PACKED.findall(asm))


def verdict(ops: collections.Counter, one_kind: bool) -> str:
    """'' when the loop is vectorized as it should be, else what is missing."""
    missing = [op for op in ("vsqrtpd", "vdivpd") if not ops[op]]
    gathers = sum(v for k, v in ops.items() if k.startswith("vgather"))
    if missing:
        return "no packed " + ", ".join(missing)
    if one_kind and gathers:
        return f"{gathers} gather instructions (the columns should be read contiguously)"
    return ""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--asm", action="store_true", help="print the packed instructions")
    ap.add_argument("--variants", nargs="*", default=list(VARIANTS), choices=list(VARIANTS))
    args = ap.parse_args(argv)
    failed = []
    for name in args.variants:
        scene, friction, rolling, one_kind = VARIANTS[name]
        asm = response_asm(scene, friction, rolling, one_kind)
        ops = packed_instructions(asm)
        why = verdict(ops, one_kind)
        if why:
            failed.append(name)
        print(
            f"{name:20s} {'SCALAR: ' + why if why else 'vectorized'}  "
            + " ".join(f"{k}x{v}" for k, v in sorted(ops.items())),
            flush=True,
        )
        if args.asm:
            print("\n".join(line for line in asm.splitlines() if PACKED.match(line)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
