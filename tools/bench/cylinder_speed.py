"""decks/cylinder_64.inp as shipped (analytic CYLINDER) against the same cavity made of 128
triangulated facets: wall time per step, the best of three interleaved windows of 20 000 steps
after 0.1 s of simulated time (the spheres have settled into the trough).

    python tools/bench/cylinder_speed.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "tools"), str(ROOT / "tools" / "bench")]

import make_decks as md  # noqa: E402
from bench_solver import best_seconds_per_step  # noqa: E402

from x3dpd.deck import read_deck  # noqa: E402
from x3dpd.deck.generate import CYL_B, cylinder_cavity_deck  # noqa: E402
from x3dpd.model.build import build_model  # noqa: E402
from x3dpd.solver.simulation import Simulation  # noqa: E402

FACETS = 128


def main() -> int:
    shipped = read_deck(ROOT / "decks" / "cylinder_64.inp")
    pos = np.array([[n.x, n.y, n.z] for n in shipped.nodes if n.nid > CYL_B])
    radius = shipped.pdmp[0].rzero
    sims = {}
    for facets in (None, FACETS):
        deck = cylinder_cavity_deck(
            length=md.CYL_LENGTH,
            cavity_radius=md.CYL_RADIUS,
            particles=pos,
            radius=radius,
            material=md.STEEL,
            structure_mass=md.BEAM_MASS,
            stiffness=md.BEAM_K,
            damping=md.BEAM_C,
            gravity=(0.0, -md.G, 0.0),
            dt=md.DT,
            itrac=10**9,
            usrfrc=(md.CYL_DRIVE,),
            facets=facets,
        )
        sims[facets] = Simulation(build_model(deck))
        sims[facets].advance(200_000, max_rows=1)
    best = best_seconds_per_step(sims, 20_000)
    print(
        f"analytic cylinder {best[None] * 1e6:.2f} us/step, {FACETS} facets "
        f"{best[FACETS] * 1e6:.2f} us/step: {best[FACETS] / best[None]:.2f}x"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
