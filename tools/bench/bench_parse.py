"""Benchmark: parse a deck with N particle nodes (default 100,000) and report the time.

Writes an Appendix-A-like deck scaled up (a box cavity of 12 triangles on a spring-damper, N
particles on a lattice inside, one CONTACT slave set listing all of them, TRACE of 51 nodes) to a
temporary directory and times ``read_deck`` on it (best of ``--repeat`` runs; the first run also
builds the parser). ``--build`` also times ``build_model`` on the parsed deck.

    python tools/bench/bench_parse.py [--particles 100000] [--repeat 3] [--build]

Target: < 2.5 s for 100,000 particles (the whole read + build budget is 5 s).
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
import time

from x3dpd.deck import read_deck
from x3dpd.deck.cards import (
    Body,
    Boundary,
    Contact,
    Deck,
    Element,
    Mass,
    Material,
    Node,
    Parameters,
    Pdmp,
    Rbel,
    SlaveSet,
    Title,
    Trace,
    Triangle,
)
from x3dpd.deck.writer import format_deck


def make_deck(particles: int) -> Deck:
    """An Appendix-A-like deck: a box cavity (nodes 1-8) on master node 9, ``particles`` particles.

    The box fits a cubic lattice of the particles (radius 0.03125 in, a gap of 0.1 R to each
    wall); the cavity rides on a spring-damper to ground, as in Appendix A.
    """
    r = 0.03125
    side = math.ceil(particles ** (1 / 3))
    box = 2 * r * side + 0.2 * r
    corners = [Node(k + 1, box * (k & 1), box * (k >> 1 & 1), box * (k >> 2 & 1)) for k in range(8)]
    faces = [
        (1, 3, 5),
        (3, 7, 5),
        (2, 6, 4),
        (4, 6, 8),
        (1, 5, 2),
        (2, 5, 6),
        (3, 4, 7),
        (4, 8, 7),
        (1, 2, 3),
        (2, 4, 3),
        (5, 7, 6),
        (6, 7, 8),
    ]
    at = [0.1 * r + r * (1 + 2 * i) for i in range(side)]
    parts = [
        Node(10 + k, at[k % side], at[k // side % side], at[k // side // side])
        for k in range(particles)
    ]
    ids = tuple(range(10, 10 + particles))
    return Deck(
        title=Title(f"benchmark: {particles} particles in a {box:.4f} in box"),
        parameters=Parameters(0.0, 15.0, 0.1, 5e-7, 5e-7, 0, 1e9, 0, 5, 0, 2000),
        materials=(
            Material(
                2, 1, 1e-12, 1.0, 11.4882, 1e12, 1e12, 3.08293e-4, (11.4882, 0, 0, 1, 0, 0, 1)
            ),
        ),
        pdmp=(Pdmp(9, r, 7.32971e-4, 0.33, 25.0e6, 10.0e6, 2.0e-6, 0.30),),
        body=Body(0.0, -386.1, 0.0),
        trace=Trace(tuple(range(9, 9 + min(51, particles + 1)))),
        nodes=(*corners, Node(9, box / 2, box / 2, box / 2), *parts),
        elements=(Element(1, 2, (9,)),),
        masses=(Mass(9, 3.002e-3, 1e20, 1e20, 1e20),),
        rbels=(Rbel(9, (1, 2, 3, 4, 5, 6), tuple(range(1, 9))),),
        boundaries=(Boundary(1, 9, 1, (2, 3, 4, 5, 6)),),
        contacts=(Contact(tuple(Triangle(1, f) for f in faces), (SlaveSet(1, ids),)),),
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--build", action="store_true", help="also time x3dpd.model.build_model")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "bench.inp")
        with open(path, "w", encoding="utf-8") as f:
            f.write(format_deck(make_deck(args.particles)))
        size = os.path.getsize(path)
        times = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            deck = read_deck(path)
            times.append(time.perf_counter() - t0)
    print(
        f"read_deck: {args.particles} particles, {len(deck.nodes)} nodes, "
        f"{size / 1e6:.1f} MB: best {min(times):.3f} s, first {times[0]:.3f} s "
        f"(runs: {', '.join(f'{t:.3f}' for t in times)})"
    )
    if args.build:
        from x3dpd.model.build import build_model

        t0 = time.perf_counter()
        build_model(deck)
        print(f"build_model: {time.perf_counter() - t0:.3f} s")


if __name__ == "__main__":
    main()
