"""Benchmark: parse a deck with N particle nodes (default 100,000) and report the time.

Writes an Appendix-A-like deck scaled up (24 cavity nodes, master node 25, N particles on a
lattice, one CONTACT slave set listing all of them, TRACE of 51 nodes) to a temporary directory
and times ``read_deck`` on it (best of ``--repeat`` runs; the first run also builds the parser).

    python tools/bench/bench_parse.py [--particles 100000] [--repeat 3]

Target: < 2.5 s for 100,000 particles (the whole read + build budget is 5 s).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

from x3dpd.deck import read_deck
from x3dpd.deck.cards import (Body, Boundary, Contact, Deck, Element, Mass, Material, Node,
                              Parameters, Pdmp, Rbel, SlaveSet, Title, Trace, Triangle)
from x3dpd.deck.writer import format_deck


def make_deck(particles: int) -> Deck:
    """An Appendix-A-like deck with ``particles`` particle nodes (ids 26 ...)."""
    cavity = [Node(i + 1, 0.25 * (i % 2), 0.25 * ((i // 2) % 2), 0.25 * (i // 4 % 2))
              for i in range(24)]
    side = max(1, round(particles ** (1 / 3)))
    r = 0.03125
    parts = [Node(26 + k, r * (1 + 2 * (k % side)), r * (1 + 2 * (k // side % side)),
                  r * (1 + 2 * (k // side // side))) for k in range(particles)]
    ids = tuple(range(26, 26 + particles))
    return Deck(
        title=Title(f"benchmark: {particles} particles"),
        parameters=Parameters(0.0, 15.0, 0.1, 5e-7, 5e-7, 0, 1e9, 0, 5, 0, 2000),
        materials=(Material(2, 1, 1e-12, 1.0, 11.4882, 1e12, 1e12, 3.08293e-4,
                            (11.4882, 0, 0, 1, 0, 0, 1)),),
        pdmp=(Pdmp(25, r, 7.32971e-4, 0.33, 25.0e6, 10.0e6, 2.0e-6, 0.30),),
        body=Body(0.0, -386.1, 0.0),
        trace=Trace(tuple(range(25, 76))),
        nodes=(*cavity, Node(25, 0.0, 0.0, 0.0), *parts),
        elements=(Element(1, 2, (25,)),),
        masses=(Mass(25, 3.002e-3, 1e20, 1e20, 1e20),),
        rbels=(Rbel(25, (1, 2, 3, 4, 5, 6), tuple(range(1, 25))),),
        boundaries=(Boundary(1, 25, 1, (2, 3, 4, 5, 6)),),
        contacts=(Contact(tuple(Triangle(1, (1, 2, 4)) for _ in range(12)),
                          (SlaveSet(1, ids),)),),
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=3)
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
    print(f"read_deck: {args.particles} particles, {len(deck.nodes)} nodes, "
          f"{size / 1e6:.1f} MB: best {min(times):.3f} s, first {times[0]:.3f} s "
          f"(runs: {', '.join(f'{t:.3f}' for t in times)})")


if __name__ == "__main__":
    main()
