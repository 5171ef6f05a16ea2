"""Cycles a sweep point needs with and without the predicted start (docs/design-guide.md).

    python tools/study/predict_check.py [--tol 0.02]

For beam_1 and beam_64 at 200 mV: the 36 Hz point from the deck's initial state, then the next
point of a down-chain at 35.5 Hz from its final state, once with the structure put on its
predicted steady-state motion (x3dpd/design/predict.py) and once without. Prints amplitude,
cycles and wall time of each.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from x3dpd.deck.parser import read_deck
from x3dpd.design.steady_state import Criterion, SweepPoint, run_point

ROOT = Path(__file__).resolve().parents[2]
DRIVE = 4.84040e-3  # 200 mV (Table 4)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tol", type=float, default=0.02)
    ap.add_argument("--decks", nargs="*", default=["beam_1.inp", "beam_64.inp"])
    args = ap.parse_args()
    for name in args.decks:
        deck = read_deck(ROOT / "decks" / name)
        for predict in (True, False):
            crit = Criterion(tol=args.tol, predict=predict)
            previous = None
            for hz, direction in ((36.0, ""), (35.5, "down")):
                t = time.perf_counter()
                point = SweepPoint(
                    "deck", deck, hz, DRIVE, 9, 1, direction=direction, criterion=crit
                )
                previous = run_point(point, previous)
                row = previous[0]
                print(
                    f"{name} predict={predict!s:5} {hz:5.1f} Hz start={row['start']:9} "
                    f"X={row['amplitude']:.4e} cycles={row['cycles']:4d} "
                    f"converged={row['converged']} wall={time.perf_counter() - t:.1f} s",
                    flush=True,
                )


if __name__ == "__main__":
    main()
