#!/usr/bin/env python3
"""What a modal structure costs per step: beam_64's cavity and 64 spheres on the SDOF beam
(decks/beam_64.inp) and on a cantilever of N Euler-Bernoulli modes (decks/beam_64_modal.inp
with N modes instead of 3, made by tools/make_modal_decks.py's closed form).

    python tools/bench/bench_modal.py [--modes 20] [--settle 0.05] [--time 0.05] [--repeat 3]

Each scene runs --settle s of simulated time (the spheres fall and settle in contact), then is
timed over --time s, best of --repeat windows; the same for both, so the contacts per sphere are
alike. Prints microseconds per step and the modal scene's cost relative to the SDOF one. Run it
on an idle machine: the VM's timings wander by up to 2x while its host is busy.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / "tools")]

import x3dpd  # noqa: E402
from make_modal_decks import (
    AL_RHO,
    BEAM_B,
    BEAM_H,
    BEAM_L,
    _modal_card,  # noqa: E402
    cantilever_modes,
)
from x3dpd.model.build import build_model  # noqa: E402
from x3dpd.solver.simulation import Simulation  # noqa: E402


def modal_beam(n_modes: int, turning: bool = True):
    """decks/beam_64_modal.inp with its first ``n_modes`` cantilever modes (the deck's modulus
    and damping ratio); ``turning=False`` leaves out the tip's rotation (the cavity translates,
    as beam_64's does)."""
    deck = x3dpd.load_deck(str(ROOT / "decks" / "beam_64_modal.inp"))
    m1 = deck.modal.modes[0]
    # the deck's modulus, from its first frequency: f1 = (b1 L)^2 / (2 pi L^2) sqrt(E I / mu)
    omega1, _, _ = cantilever_modes(1, 1.0, AL_RHO, BEAM_B, BEAM_H, BEAM_L)
    e = (2 * math.pi * m1.freq / omega1[0]) ** 2
    omega, tip, slope = cantilever_modes(n_modes, e, AL_RHO, BEAM_B, BEAM_H, BEAM_L)
    shapes = [(9, 1, list(tip))] + ([(9, 6, list(-slope))] if turning else [])
    card = _modal_card([(k + 1, w / (2 * math.pi), m1.zeta) for k, w in enumerate(omega)], shapes)
    return replace(deck, modal=card)


def time_per_step(deck, settle: float, window: float, repeat: int) -> float:
    model = build_model(deck)
    sim = Simulation(model)
    sim.initialize()
    sim.advance(round(settle / sim.dt))
    steps = round(window / sim.dt)
    best = math.inf
    for _ in range(repeat):
        t = time.perf_counter()
        sim.advance(steps)
        best = min(best, (time.perf_counter() - t) / steps)
    return best


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--modes", type=int, default=20)
    ap.add_argument("--settle", type=float, default=0.05)
    ap.add_argument("--time", type=float, default=0.05)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    sdof = x3dpd.load_deck(str(ROOT / "decks" / "beam_64.inp"))
    a = time_per_step(sdof, args.settle, args.time, args.repeat)
    print(f"beam_64 (SDOF)                         {a * 1e6:8.3f} us/step")
    for turning, what in ((False, "translating cavity"), (True, "cavity turning with the tip")):
        b = time_per_step(modal_beam(args.modes, turning), args.settle, args.time, args.repeat)
        print(
            f"beam_64 on {args.modes:2d} modes, {what:<27} {b * 1e6:8.3f} us/step  "
            f"({(b / a - 1) * 100:+.1f} %)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
