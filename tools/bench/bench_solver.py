"""Per-step wall time of x3dpd on the shared benchmark scene (tools/bench/scene.py).

x3dpd solves the force-driven, spring-mounted cavity (report Table 4 structure, drive chosen for a
3 g cavity acceleration at 37.21 Hz), the harder form of the scene LAMMPS runs on a prescribed
path. Times are after compilation, on one core; compile (cold) and cache-load (warm) times are
reported separately.

    python tools/bench/bench_solver.py --n 50 64 512 4096 [--steps 20000] [--repeat 5]
                                       [--json out.json]
    python tools/bench/bench_solver.py --effects --n 64   # cost of each effect's code
    python tools/bench/bench_solver.py --sdof             # structure only: steps per second
    python tools/bench/bench_solver.py --settled          # a settled 512-particle bed at rest
    python tools/bench/bench_solver.py --effects --settled --n 512   # effects, settled bed
    python tools/bench/bench_solver.py --shaken --e1 5e6  # the settled bed shaken at 2 g
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("NUMBA_NUM_THREADS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402
from scene import G, bench_scene  # noqa: E402

from x3dpd.deck.generate import Material3, box_cavity_deck  # noqa: E402
from x3dpd.model.build import build_model  # noqa: E402
from x3dpd.solver.simulation import Simulation  # noqa: E402


#: The shaken bed's cavity: a free rigid body of this mass [lbf s^2/in] (no spring), about 1000
#: times the 512 spheres' mass, so that the force M a g cos(wt) moves it on x = A (1 - cos wt)
#: (A = a g / w^2) as LAMMPS moves its walls
SHAKEN_CAVITY_MASS = 0.05


def scene_model(
    n: int,
    *,
    e1: float = 0.0,
    mu: float | None = None,
    seed: int = 0,
    gravity: bool = True,
    drive: bool = True,
    free_cavity: bool = False,
):
    """The benchmark scene as an x3dpd model: box cavity on the Table 4 spring, force-driven;
    with ``free_cavity`` a free rigid cavity of SHAKEN_CAVITY_MASS (no spring, no damper)."""
    sc = bench_scene(n, seed=seed)
    if free_cavity:
        sc = {**sc, "structure_mass": SHAKEN_CAVITY_MASS, "structure_k": 0.0, "structure_c": 0.0}
    mat = Material3(sc["E0"], e1, 2e-6, sc["nu"], sc["mu"] if mu is None else mu, sc["density"])
    spec = f"sine:node=9,dof=1,amp={sc['drive_force']!r},hz={sc['shake_freq_hz']!r}"
    deck = box_cavity_deck(
        size=sc["box_hi"] - sc["box_lo"],
        particles=sc["positions"],
        radius=sc["radius"],
        material=mat,
        structure_mass=sc["structure_mass"],
        stiffness=sc["structure_k"],
        damping=sc["structure_c"],
        gravity=tuple(sc["gravity"]) if gravity else (0.0, 0.0, 0.0),
        dt=sc["dt"],
        itrac=10**9,
        usrfrc=(spec,) if drive else (),
    )
    return build_model(deck), sc


def sdof_model():
    """The structure alone (``--sdof``): the Table 4 SDOF driven at 37.21 Hz, no particles."""
    from x3dpd.deck.cards import Boundary, Deck, Element, Mass, Material, Node, Parameters, Usrfrc

    deck = Deck(
        parameters=Parameters(0.0, 1.0, 0.0, 5e-7, 5e-7, 0, 1e9, 0, 5, 0, 10**9),
        materials=(Material(2, 1, 1e-12, 1.0, 11.4823, 0.0, 0.0, 3.08293e-4),),
        nodes=(Node(1, 0.0, 0.0, 0.0),),
        elements=(Element(1, 2, (1,)),),
        masses=(Mass(1, 1.87646e-4, 0.0, 0.0, 0.0),),
        usrfrc=(Usrfrc(("sine:node=1,dof=1,amp=4.84040e-3,hz=37.21",)),),
    )
    deck = Deck(**{**deck.__dict__, "boundaries": (Boundary(1, 1, 1, (2, 3, 4, 5, 6)),)})
    return build_model(deck)


def best_seconds_per_step(sims: dict, steps: int, repeats: int = 3) -> dict:
    """Seconds per step of each simulation in ``sims``, the best of ``repeats`` windows of
    ``steps`` steps taken in turn (interleaved, so that outside load hits all alike; the best
    filters it out)."""
    best = {key: math.inf for key in sims}
    for _ in range(repeats):
        for key, sim in sims.items():
            t = time.perf_counter()
            sim.advance(steps, max_rows=1)
            best[key] = min(best[key], (time.perf_counter() - t) / steps)
    return best


def time_steps(sim: Simulation, warmup: int, steps: int) -> float:
    """Seconds per step over ``steps`` steps after ``warmup`` steps (one advance call each)."""
    sim.advance(warmup, max_rows=1)
    t = time.perf_counter()
    sim.advance(steps, max_rows=1)
    return (time.perf_counter() - t) / steps


def bench_n(n: int, warmup: int, steps: int, repeat: int = 1, **kw) -> dict:
    """Time the same window ``repeat`` times, each from a fresh simulation of the same model
    (runs are deterministic, so every repeat does identical work); keep the fastest."""
    model, sc = scene_model(n, **kw)
    best = math.inf
    for rep in range(repeat):
        t = time.perf_counter()
        sim = Simulation(model, itrac=10**9)
        sim.initialize()
        if rep == 0:
            ready = time.perf_counter() - t
        best = min(best, time_steps(sim, warmup, steps))
    return {
        "n": n,
        "us_per_step": best * 1e6,
        "steps": steps,
        "warmup": warmup,
        "repeats": repeat,
        "setup_and_compile_s": ready,
        "effects": sorted(sim.effects),
        "neighbour_rebuilds": int(sim.state.nbr[2]),
    }


def settled_bed(
    n: int,
    settle_steps: int,
    steps: int,
    repeat: int,
    accel_g: float = 0.0,
    warmup: int | None = None,
    e1: float = 0.0,
    shaken: bool = False,
) -> dict:
    """Per-step time of a settled bed: the scene without drive (particles fall, pile up
    and come to rest on the floor under gravity) for ``settle_steps`` steps, then ``warmup``
    steps (default 2000) before ``repeat`` consecutive timed windows. Every particle has lasting
    contacts, the costly case of the contact law (and where a damper spends its life); LAMMPS's
    side is ``lammps_peer.py --settled``, the same bed at rest. Contacts are counted at the end
    of every timed window and averaged.

    ``shaken``: the cavity is a free rigid body of SHAKEN_CAVITY_MASS (no spring), and after
    settling a force F = M a g cos(omega (t - t_s)) (a = ``accel_g``, default 2; 37.21 Hz)
    pushes it along x, so that it moves on x = A (1 - cos omega (t - t_s)), A = a g / omega^2,
    as LAMMPS's walls do (``lammps_peer.py --shaken``); warm-up two drive periods by default.
    With ``e1`` = 5e6 (the beam decks' spheres) the bed stays a bed at 2 g: about 4.5
    sphere-sphere and 0.34 wall contacts per sphere in both codes.

    ``accel_g`` > 0 without ``shaken`` moves the cavity on a prescribed path along x after
    settling, ``u = h(t) A sin(omega (t - t_s))`` with peak acceleration ``A omega^2 = accel_g`` g
    at 37.21 Hz, started smoothly over one period (``--motion ... ramp=``), and warms up for one
    more period by default. The scene's particles are elastic (no normal damping): shaken at
    0.25 g it keeps 0.9 contacts per sphere, at 2 g a few per hundred spheres: it is no longer a
    settled bed. ``e1`` > 0 makes the spheres viscoelastic (one Maxwell term, E1 with
    tau1 = 2e-6 s, as in decks/beam_*.inp)."""
    sim, sc = settled_simulation(n, settle_steps, accel_g, e1, shaken)
    omega = 2.0 * math.pi * sc["shake_freq_hz"]
    period = 2.0 * math.pi / omega
    if warmup is None:
        warmup = 2 * round(period / sc["dt"]) if (accel_g or shaken) else 2000
    sim.advance(warmup, max_rows=1)
    best = math.inf
    pair_on = wall_on = 0
    rebuilds = int(sim.state.nbr[2])
    for _ in range(repeat):  # consecutive windows of the bed
        t = time.perf_counter()
        sim.advance(steps, max_rows=1)
        best = min(best, (time.perf_counter() - t) / steps)
        st = sim.state
        pair_on += int(st.pl_on[: int(st.npl[0])].sum())
        wall_on += int(st.wl_on[: int(st.nwl[0])].sum())
    pair_on, wall_on = pair_on / repeat, wall_on / repeat
    return {
        "case": "shaken" if shaken else "settled",
        "n": n,
        "settle_steps": settle_steps,
        "accel_g": accel_g if (accel_g or not shaken) else 2.0,
        "e1": e1,
        "warmup_steps": warmup,
        "us_per_step": best * 1e6,
        "pair_contacts": pair_on,
        "wall_contacts": wall_on,
        "contacts_per_sphere": (2 * pair_on + wall_on) / n,
        "pair_contacts_per_sphere": 2 * pair_on / n,
        "wall_contacts_per_sphere": wall_on / n,
        "list_rebuilds_per_1000_steps": 1000.0
        * (int(sim.state.nbr[2]) - rebuilds)
        / (repeat * steps),
        "ns_per_contact": best * 1e9 / max(pair_on + wall_on, 1),
    }


def settled_simulation(
    n: int, settle_steps: int, accel_g: float = 0.0, e1: float = 0.0, shaken: bool = False
):
    """``(Simulation, scene)``: the bed of ``settled_bed`` after ``settle_steps`` steps at rest,
    with the shake (``shaken`` or ``accel_g``) started at that time and no step of it taken."""
    model, sc = scene_model(n, drive=False, e1=e1, free_cavity=shaken)
    sim = Simulation(model, itrac=10**9)
    sim.initialize()
    sim.advance(settle_steps, max_rows=1)
    omega = 2.0 * math.pi * sc["shake_freq_hz"]
    period = 2.0 * math.pi / omega
    if shaken:
        force = SHAKEN_CAVITY_MASS * (accel_g or 2.0) * G
        spec = (
            f"sine:node=9,dof=1,amp={force!r},hz={sc['shake_freq_hz']!r},phase=90,t0={sim.time!r}"
        )
        driven = Simulation(model, itrac=10**9, usrfrc=(spec,))
        driven.restore(sim.state)
        sim = driven
    elif accel_g:
        amp = accel_g * G / omega**2
        spec = (
            f"node=9,dof=1,amp={amp!r},hz={sc['shake_freq_hz']!r},t0={sim.time!r},ramp={period!r}"
        )
        shaken_sim = Simulation(model, itrac=10**9, motion=(spec,))
        shaken_sim.restore(sim.state)
        sim = shaken_sim
    return sim, sc


def effect_costs(
    n: int, warmup: int, steps: int, repeat: int = 1, settled: bool = False
) -> list[dict]:
    """Cost of each effect's code: a scene where the effect is physically absent, run with the
    variant the factory picks (effect compiled out) and with the effect forced in at zero
    strength (friction with mu = 0, a Maxwell term with E1 = 0, gravity 0). Both give identical
    trajectories, so the time difference is the code alone. Each timing is the fastest of
    ``repeat`` fresh runs. With ``settled`` the scene runs without drive and is timed after
    300,000 steps, once the particles rest on each other: contact laws then run every step."""
    import dataclasses

    from x3dpd.solver.variants import make_advance

    cases = [
        ("friction", {"mu": 0.0}, {"friction": True}),
        ("viscoelastic", {"e1": 0.0}, {"viscoelastic": True, "n_maxwell": 1}),
        ("gravity", {"gravity": False}, {"gravity": True}),
    ]
    if settled:
        # a bed settles only with gravity and some dissipation: frictionless particles get a
        # Maxwell term (E1 = 10e6 psi, tau1 = 2 us, as in the report's Appendix A material)
        cases = [("friction", {"mu": 0.0, "e1": 10e6}, {"friction": True}), cases[1]]
    out = []
    for name, scene_kw, forced in cases:
        model, _ = scene_model(n, drive=not settled, **scene_kw)
        times = {}
        finals = {}
        for label in ("out", "in"):
            if label == "in" and name == "viscoelastic":
                # an elastic model stores E0 only; give the forced Maxwell term a real column
                # (E1 = 0, tau1 = 2e-6 s) to read
                p = model.n_particles
                model = dataclasses.replace(
                    model,
                    moduli=np.hstack([model.moduli, np.zeros((p, 1))]),
                    taus=np.hstack([model.taus, np.full((p, 1), 2e-6)]),
                )
            times[label] = math.inf
            for _rep in range(1 if settled else repeat):
                sim = Simulation(model, itrac=10**9)
                if label == "in":
                    sim.variant = dataclasses.replace(sim.variant, **forced)
                    sim.kernels = make_advance(sim.variant)
                sim.initialize()
                if settled:
                    sim.advance(300_000, max_rows=1)
                    for _ in range(repeat):  # consecutive windows of the resting bed
                        times[label] = min(times[label], time_steps(sim, 0, steps) * 1e6)
                else:
                    times[label] = min(times[label], time_steps(sim, warmup, steps) * 1e6)
            finals[label] = sim.state.x.copy()
        out.append(
            {
                "n": n,
                "effect": name,
                "us_out": times["out"],
                "us_in": times["in"],
                "identical": bool(np.array_equal(finals["out"], finals["in"])),
            }
        )
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="*", default=[50, 64, 512, 4096])
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument(
        "--warmup",
        type=int,
        default=None,
        help="untimed steps first (default 2000; --settled: one drive period)",
    )
    ap.add_argument(
        "--repeat",
        type=int,
        default=1,
        help="time the same window this many times; report the fastest",
    )
    ap.add_argument("--json")
    ap.add_argument(
        "--effects",
        action="store_true",
        help="cost of each effect's code (compiled in at zero strength vs out)",
    )
    ap.add_argument("--sdof", action="store_true", help="structure-only steps per second")
    ap.add_argument(
        "--settled",
        action="store_true",
        help="a settled bed of --n particles (default 512) after 300000 steps "
        "(at rest, or shaken at --accel-g)",
    )
    ap.add_argument(
        "--shaken",
        action="store_true",
        help="the settled bed (--n, default 512) in a free rigid cavity then pushed "
        "by M a g cos(wt) at --accel-g (default 2) g, 37.21 Hz",
    )
    ap.add_argument(
        "--e1",
        type=float,
        default=0.0,
        help="with --settled/--shaken: Maxwell modulus E1 [psi] of the spheres "
        "(default 0: elastic; decks/beam_*.inp have 5e6)",
    )
    ap.add_argument(
        "--accel-g",
        type=float,
        default=0.0,
        help="with --settled: peak acceleration of the cavity's prescribed motion "
        "in g (default 0: the bed at rest)",
    )
    args = ap.parse_args(argv)
    args.warmup_given = args.warmup is not None
    if args.warmup is None:
        args.warmup = 2000
    results = []
    if args.sdof:
        sim = Simulation(sdof_model(), itrac=10**9)
        per = time_steps(sim, 10000, 2_000_000)
        results.append({"case": "sdof", "steps_per_second": 1.0 / per, "us_per_step": per * 1e6})
        print(f"x3dpd sdof steps_per_second={1.0 / per:.3e}")
    elif (args.settled or args.shaken) and not args.effects:
        ns = args.n if args.n != [50, 64, 512, 4096] else [512]
        for n in ns:
            r = settled_bed(
                n,
                300_000,
                args.steps,
                max(args.repeat, 3),
                args.accel_g,
                args.warmup if args.warmup_given else None,
                args.e1,
                args.shaken,
            )
            results.append(r)
            print(
                f"x3dpd {r['case']} n={n} us_per_step={r['us_per_step']:.2f} "
                f"({r['pair_contacts']:.0f} pair + {r['wall_contacts']:.0f} wall contacts, "
                f"{r['pair_contacts_per_sphere']:.2f} + {r['wall_contacts_per_sphere']:.2f} "
                f"per sphere, {r['ns_per_contact']:.0f} ns per contact, "
                f"{r['list_rebuilds_per_1000_steps']:.2f} list rebuilds per 1000 steps, "
                f"{r['accel_g']:g} g, E1 {args.e1:g})"
            )
    elif args.effects:
        for n in args.n:
            for r in effect_costs(n, args.warmup, args.steps, args.repeat, args.settled):
                results.append(r)
                print(
                    f"x3dpd n={n} {r['effect']:13s} compiled out {r['us_out']:7.3f} us/step, "
                    f"compiled in with zero parameters {r['us_in']:7.3f} us/step "
                    f"(identical trajectories: {r['identical']})"
                )
    else:
        for n in args.n:
            r = bench_n(
                n, args.warmup, args.steps if n < 4096 else max(args.steps // 10, 1000), args.repeat
            )
            results.append(r)
            print(
                f"x3dpd n={n} us_per_step={r['us_per_step']:.3f} "
                f"(best of {r['repeats']}, setup+compile/load {r['setup_and_compile_s']:.2f} s, "
                f"{r['neighbour_rebuilds']} list rebuilds)"
            )
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
