"""Run x3dpd and LAMMPS on the same scenes, one after the other, and print the comparison table.

    python tools/bench/run_all.py [--n 50 64 512 4096] [--steps 20000] [--repeat 3] [--json F]
                                  [--settled-n 512] [--style classic|granular]

Each measurement runs in its own process on one core (OMP/NUMBA threads = 1). x3dpd solves the
force-driven spring-mounted cavity; LAMMPS the same particles in a box on a prescribed path, in
its fastest form (``--style classic``: gran/hertz/history pair and wall styles). Two tables:
the falling window (the scene's start), and the settled beds (``--settled-n``, default 512
spheres, settled for 300,000 steps; 0 skips them): at rest elastic, at rest viscoelastic, and
the viscoelastic bed shaken at 2 g (``BEDS``), with the contacts per sphere of both codes.
Also reported: compile time with a cold and a warm numba cache, and the structure-only (SDOF)
step rate. LAMMPS rows are skipped when `lammps` is not installed.
Both codes time the same window ``--repeat`` times from scratch (default 3) and
report their fastest, so a stray background process cannot tilt the ratio either way.
Run it on an idle machine: another busy process on the same cores distorts every number.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ENV = {**os.environ, "OMP_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1"}


def _json_run(cmd: list[str], env=None) -> list | dict | None:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "r.json"
        proc = subprocess.run(
            cmd + ["--json", str(out)], env=env or ENV, capture_output=True, text=True
        )
        if proc.returncode != 0 or not out.exists():
            sys.stderr.write(proc.stdout + proc.stderr)
            return None
        return json.loads(out.read_text())


def x3dpd_step(n: int, steps: int, warmup: int, repeat: int) -> float | None:
    r = _json_run(
        [
            sys.executable,
            str(HERE / "bench_solver.py"),
            "--n",
            str(n),
            "--steps",
            str(steps),
            "--warmup",
            str(warmup),
            "--repeat",
            str(repeat),
        ]
    )
    return r[0]["us_per_step"] if r else None


def lammps_step(
    n: int, steps: int, warmup: int, repeat: int, style: str = "classic", settled: bool = False
) -> dict | None:
    r = _json_run(
        [
            sys.executable,
            str(HERE / "lammps_peer.py"),
            "--n",
            str(n),
            "--steps",
            str(steps),
            "--warmup",
            str(warmup),
            "--repeat",
            str(repeat),
            "--style",
            style,
        ]
        + (["--settled"] if settled else [])
    )
    if not r or "us_per_step" not in r:
        return None
    return r


#: The settled beds of 512 (bench_solver.py and lammps_peer.py arguments): at rest elastic,
#: at rest viscoelastic (E1 = 5e6 psi; LAMMPS damped to its restitution), and that bed in the
#: free cavity shaken at 2 g (LAMMPS: all six walls on x = A (1 - cos wt))
BEDS = {
    "at rest, elastic": (["--settled"], ["--settled"]),
    "at rest, E1 5e6 psi": (["--settled", "--e1", "5e6"], ["--settled", "--e1", "5e6"]),
    "shaken 2 g, E1 5e6 psi": (["--shaken", "--e1", "5e6"], ["--shaken", "--e1", "5e6"]),
}


def bed_row(name: str, n: int, steps: int, repeat: int, style: str) -> dict:
    """One bed, both codes, one after the other: us/step and contacts per sphere (sphere-sphere
    and wall)."""
    ours_args, theirs_args = BEDS[name]
    ours = _json_run(
        [
            sys.executable,
            str(HERE / "bench_solver.py"),
            *ours_args,
            "--n",
            str(n),
            "--steps",
            str(steps),
            "--repeat",
            str(repeat),
        ]
    )
    theirs = (
        _json_run(
            [
                sys.executable,
                str(HERE / "lammps_peer.py"),
                *theirs_args,
                "--n",
                str(n),
                "--steps",
                str(steps),
                "--style",
                style,
            ]
        )
        if repeat
        else None
    )
    o = ours[0] if ours else None
    t = theirs if theirs and "us_per_step" in theirs else None
    return {
        "bed": name,
        "n": n,
        "x3dpd_us": o["us_per_step"] if o else None,
        "x3dpd_pair_per_sphere": o["pair_contacts_per_sphere"] if o else None,
        "x3dpd_wall_per_sphere": o["wall_contacts_per_sphere"] if o else None,
        "lammps_us": t["us_per_step"] if t else None,
        "lammps_pair_per_sphere": t.get("pair_contacts_per_sphere") if t else None,
        "lammps_wall_per_sphere": t.get("wall_contacts_per_sphere") if t else None,
        "speedup": (t["us_per_step"] / o["us_per_step"]) if o and t else None,
    }


def compile_times(n: int = 64) -> tuple[float, float]:
    """Seconds to build and compile the scene's kernels: cold cache, then warm."""
    code = (
        f"import sys, time; sys.path.insert(0, {str(HERE)!r}); t = time.perf_counter(); "
        f"from bench_solver import scene_model; "
        f"from x3dpd.solver.simulation import Simulation; "
        f"s = Simulation(scene_model({n})[0]); s.initialize(); s.advance(10); "
        f"print(time.perf_counter() - t)"
    )
    with tempfile.TemporaryDirectory() as cache:
        env = {**ENV, "X3DPD_CACHE_DIR": cache}
        times = []
        for _ in range(2):
            t = time.perf_counter()
            subprocess.run([sys.executable, "-c", code], env=env, check=True, capture_output=True)
            times.append(time.perf_counter() - t)
    return times[0], times[1]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="*", default=[50, 64, 512, 4096])
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--warmup", type=int, default=2000)
    ap.add_argument(
        "--repeat",
        type=int,
        default=3,
        help="time each window this many times (fresh runs), keep the fastest",
    )
    ap.add_argument("--json")
    ap.add_argument(
        "--style",
        choices=("classic", "granular"),
        default="classic",
        help="LAMMPS's pair/wall styles (classic: gran/hertz/history, its fastest)",
    )
    ap.add_argument(
        "--settled-n",
        type=int,
        default=512,
        help="particles of the settled beds (0: skip that table)",
    )
    args = ap.parse_args(argv)
    rows = []
    for n in args.n:
        steps = args.steps if n < 4096 else max(args.steps // 10, 1000)
        ours = x3dpd_step(n, steps, args.warmup, args.repeat)
        lam = lammps_step(n, steps, args.warmup, args.repeat, args.style)
        theirs = lam["us_per_step"] if lam else None
        rows.append(
            {
                "n": n,
                "steps": steps,
                "x3dpd_us": ours,
                "lammps_us": theirs,
                "speedup": (theirs / ours) if ours and theirs else None,
            }
        )
        print(rows[-1], flush=True)
    beds = (
        [bed_row(name, args.settled_n, args.steps // 2, args.repeat, args.style) for name in BEDS]
        if args.settled_n
        else []
    )
    sdof = _json_run([sys.executable, str(HERE / "bench_solver.py"), "--sdof"])
    cold, warm = compile_times()
    print()
    print("| particles | x3dpd µs/step | LAMMPS µs/step | LAMMPS / x3dpd |")
    print("|---:|---:|---:|---:|")
    for r in rows:
        lam = f"{r['lammps_us']:.2f}" if r["lammps_us"] else "not installed"
        ratio = f"{r['speedup']:.1f}×" if r["speedup"] else "–"
        print(f"| {r['n']} | {r['x3dpd_us']:.2f} | {lam} | {ratio} |")
    if beds:
        print(
            f"\nSettled beds of {args.settled_n} (LAMMPS --style {args.style}); contacts per "
            f"sphere: sphere-sphere + wall:"
        )
        print(
            "| bed | x3dpd µs/step | contacts/sphere | LAMMPS µs/step | contacts/sphere | "
            "LAMMPS / x3dpd |"
        )
        print("|---|---:|---:|---:|---:|---:|")

        def f(v, d=2):
            return f"{v:.{d}f}" if v is not None else "–"

        for b in beds:
            print(
                f"| {b['bed']} | {f(b['x3dpd_us'])} | {f(b['x3dpd_pair_per_sphere'])} + "
                f"{f(b['x3dpd_wall_per_sphere'])} | {f(b['lammps_us'])} | "
                f"{f(b['lammps_pair_per_sphere'])} + {f(b['lammps_wall_per_sphere'])} | "
                f"{f(b['speedup'], 1)}{'×' if b['speedup'] else ''} |"
            )
    if sdof:
        print(f"\nSDOF only (structure, no particles): {sdof[0]['steps_per_second']:.3g} steps/s")
    print(f"Start-up incl. compile, n = 64: cold cache {cold:.1f} s, warm cache {warm:.1f} s")
    if args.json:
        Path(args.json).write_text(
            json.dumps(
                {
                    "rows": rows,
                    "beds": beds,
                    "sdof": sdof,
                    "compile_cold_s": cold,
                    "compile_warm_s": warm,
                    "lammps_style": args.style,
                },
                indent=2,
            )
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
