"""Fail when a change makes any benchmark row more than 10 % slower than the baseline revision,
both measured on this machine in the same run.

    python tools/bench/regress.py [--base REV] [--rounds 2] [--tolerance 0.10] [--rows ...]

The baseline revision is ``tools/bench/baseline.json``'s ``commit`` unless ``--base`` names
another. It is checked out into a temporary git worktree; each row's benchmark
(``bench_solver.py``) then runs alternately in the baseline tree and in this tree, ``--rounds``
times each, every run in its own process on one core, and the fastest of each side is kept.
Alternating and taking the fastest cancels most of the drift of a shared machine; run it on an
idle machine all the same. Exit status 0 when every row is within the tolerance, 1 when one is
not (the table says which), 2 on a usage error. A row the baseline's ``bench_solver.py`` cannot
run (an option added later) is shown as n/a; ``--harness this`` times the baseline's x3dpd with
this tree's script instead.

``baseline.json`` also records the numbers measured when the baseline was taken (``rows``), for
reference: the verdict compares against the baseline tree measured now, never against numbers
from another day.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
ENV = {**os.environ, "OMP_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1"}

#: name -> bench_solver.py arguments; each row prints one us_per_step
ROWS = {
    "falling_50": ["--n", "50", "--steps", "20000", "--repeat", "3"],
    "falling_64": ["--n", "64", "--steps", "20000", "--repeat", "3"],
    "falling_512": ["--n", "512", "--steps", "20000", "--repeat", "3"],
    "settled_512": [
        "--settled",
        "--n",
        "512",
        "--steps",
        "10000",
        "--repeat",
        "3",
        "--accel-g",
        "0",
    ],
    "settled_visco_512": [
        "--settled",
        "--n",
        "512",
        "--steps",
        "10000",
        "--repeat",
        "3",
        "--e1",
        "5e6",
    ],
    "shaken_visco_512": [
        "--shaken",
        "--n",
        "512",
        "--steps",
        "10000",
        "--repeat",
        "3",
        "--e1",
        "5e6",
    ],
    "sdof": ["--sdof"],
}


def measure(tree: Path, args: list[str], harness: Path | None = None) -> float:
    """us per step of one bench_solver.py run with ``tree``'s x3dpd on PYTHONPATH; the script
    is ``tree``'s own unless ``harness`` (a tools/bench folder) names another."""
    script = (harness or tree / "tools" / "bench") / "bench_solver.py"
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "r.json"
        env = {**ENV, "PYTHONPATH": str(tree)}
        proc = subprocess.run(
            [sys.executable, str(script), *args, "--json", str(out)],
            env=env,
            capture_output=True,
            text=True,
            cwd=tree,
        )
        if proc.returncode != 0 or not out.exists():
            raise RuntimeError(
                f"bench_solver.py {' '.join(args)} failed in {tree}:\n{proc.stdout}{proc.stderr}"
            )
        return float(json.loads(out.read_text())[0]["us_per_step"])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", help="baseline revision [default: baseline.json's commit]")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--tolerance", type=float, default=0.10)
    ap.add_argument("--rows", nargs="*", default=list(ROWS), choices=list(ROWS))
    ap.add_argument(
        "--harness",
        choices=("own", "this"),
        default="own",
        help="which bench_solver.py times the baseline: its own (default) or this "
        "tree's (for rows whose options the baseline's script lacks)",
    )
    args = ap.parse_args(argv)
    recorded = json.loads((HERE / "baseline.json").read_text())
    base = args.base or recorded["commit"]
    failed = []
    with tempfile.TemporaryDirectory() as tmp:
        tree = Path(tmp) / "base"
        subprocess.run(
            ["git", "worktree", "add", "--detach", "-q", str(tree), base], cwd=ROOT, check=True
        )
        try:
            print(
                f"| row | baseline {base[:10]} µs/step | this tree µs/step | change | "
                f"recorded {recorded.get('date', '')} |"
            )
            print("|---|---:|---:|---:|---:|")
            harness = HERE if args.harness == "this" else None
            for name in args.rows:
                best = {"base": float("inf"), "this": float("inf")}
                for _ in range(args.rounds):
                    try:
                        best["base"] = min(best["base"], measure(tree, ROWS[name], harness))
                    except RuntimeError as exc:
                        # a row the baseline cannot run (an option its script lacks): no verdict
                        print(
                            f"| {name} | n/a | - | - | baseline cannot run it: "
                            f"{str(exc).splitlines()[-1][:80]} |",
                            flush=True,
                        )
                        break
                    best["this"] = min(best["this"], measure(ROOT, ROWS[name]))
                if best["this"] == float("inf"):
                    continue
                change = best["this"] / best["base"] - 1.0
                if change > args.tolerance:
                    failed.append(name)
                rec = recorded.get("rows", {}).get(name)
                print(
                    f"| {name} | {best['base']:.3f} | {best['this']:.3f} | {change:+.1%}"
                    f"{' SLOWER' if name in failed else ''} | "
                    f"{rec if rec is not None else '-'} |",
                    flush=True,
                )
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT)
    if failed:
        print(
            f"regression: {', '.join(failed)} more than {args.tolerance:.0%} slower than "
            f"{base[:10]}",
            file=sys.stderr,
        )
        return 1
    print(f"no row more than {args.tolerance:.0%} slower than {base[:10]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
