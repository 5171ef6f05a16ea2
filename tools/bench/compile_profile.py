"""Where a cold compile of a scene's step loop goes: CPU seconds per numba pass and LLVM stage.

    python tools/bench/compile_profile.py decks/beam_64.inp [--tmax 0.002] [--fresh]
        [--by-function] [--threads N] [--motion SPEC]

Runs the deck for ``--tmax`` with an empty kernel cache (a temporary ``X3DPD_CACHE_DIR``; the
small kernels cached beside x3dpd's sources stay warm, as after any first run) and prints the
total CPU time (``--fresh``: the small kernels' cache empty too, as in a fresh clone) and, per
numba compiler pass and per LLVM optimisation stage, the CPU seconds spent in it exclusive of
nested compiles (``--by-function``: per compiled function and per LLVM code library; ``--threads
2``: the threaded loop variant, docs/engine.md "Threads"; ``--motion``: a prescribed motion,
as the run's, repeatable). CPU time (``time.process_time``)
rather than wall time, so that a loaded machine still gives comparable numbers.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import tempfile
import time


def _exclusive_timer(acc: dict, stack: list, name: str, fn):
    def timed(*args, **kwargs):
        t = time.process_time()
        stack.append(0.0)
        try:
            return fn(*args, **kwargs)
        finally:
            elapsed = time.process_time() - t
            acc[name] += elapsed - stack.pop()
            if stack:
                stack[-1] += elapsed

    return timed


def _time_by_stage(acc, stack, codegen, machinery) -> None:
    run_pass = machinery.PassManager._runPass

    def timed_pass(self, index, pss, state):
        return _exclusive_timer(
            acc, stack, "numba pass " + pss.name(), lambda: run_pass(self, index, pss, state)
        )()

    machinery.PassManager._runPass = timed_pass
    for stage in ("_optimize_functions", "_optimize_final_module", "_finalize_final_module"):
        setattr(
            codegen.CPUCodeLibrary,
            stage,
            _exclusive_timer(acc, stack, "LLVM " + stage, getattr(codegen.CPUCodeLibrary, stage)),
        )


def _time_by_function(acc, stack, codegen, dispatcher) -> None:
    compile_core = dispatcher._FunctionCompiler._compile_core
    optimize = codegen.CPUCodeLibrary._optimize_functions
    finalize = codegen.CPUCodeLibrary.finalize

    def timed_compile(self, args, return_type):
        name = f"numba {self.py_func.__module__.rpartition('__')[2]}.{self.py_func.__qualname__}"
        return _exclusive_timer(acc, stack, name, compile_core)(self, args, return_type)

    def timed_optimize(self, module):
        return _exclusive_timer(acc, stack, f"LLVM {self.name}", optimize)(self, module)

    def timed_finalize(self):
        return _exclusive_timer(acc, stack, f"LLVM {self.name}", finalize)(self)

    dispatcher._FunctionCompiler._compile_core = timed_compile
    codegen.CPUCodeLibrary._optimize_functions = timed_optimize
    codegen.CPUCodeLibrary.finalize = timed_finalize


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("deck")
    ap.add_argument("--tmax", type=float, default=0.002)
    ap.add_argument(
        "--fresh",
        action="store_true",
        help="also an empty numba cache for the kernels beside x3dpd's sources "
        "(NUMBA_CACHE_DIR), as in a fresh clone",
    )
    ap.add_argument(
        "--by-function",
        action="store_true",
        help="CPU seconds per compiled function (numba's passes) and per code "
        "library (LLVM) instead of per pass and stage",
    )
    ap.add_argument(
        "--threads",
        default="1",
        help="the run's thread count (more than 1: the threaded loop variant)",
    )
    ap.add_argument(
        "--motion",
        action="append",
        default=[],
        help="a prescribed motion (docs/usrfrc.md), as the run's --motion; repeatable",
    )
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as cache:
        os.environ["X3DPD_CACHE_DIR"] = cache
        if args.fresh:
            os.environ["NUMBA_CACHE_DIR"] = os.path.join(cache, "numba")
        from numba.core import codegen, dispatcher
        from numba.core import compiler_machinery as machinery

        acc: dict = collections.defaultdict(float)
        stack: list = []
        if args.by_function:
            _time_by_function(acc, stack, codegen, dispatcher)
        else:
            _time_by_stage(acc, stack, codegen, machinery)
        import x3dpd

        t0 = time.process_time()
        # writes nothing
        x3dpd.run(args.deck, tmax=args.tmax, threads=args.threads, motion=args.motion)
        total = time.process_time() - t0
    print(f"{args.deck}: {total:.1f} CPU s to compile and run {args.tmax:g} s")
    for name, seconds in sorted(acc.items(), key=lambda kv: -kv[1]):
        if seconds >= 0.1:
            print(f"  {seconds:6.2f}  {name}")


if __name__ == "__main__":
    sys.exit(main())
