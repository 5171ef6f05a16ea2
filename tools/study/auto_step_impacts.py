"""The step chosen by accuracy on two wall impacts, against fixed steps (docs/running.md).

    python tools/study/auto_step_impacts.py

1. Lee & Radok's viscoelastic 0.03125 in sphere at 62.8 in/s into a wall (a 3.8 us contact)
   beside a resting one, DTMAX 2e-6 s, DTMIN 1e-10 s, 8e-5 s: restitution with ``dt="auto"``,
   with a fixed 1e-9 s step, and whether the fixed DTMAX runs at all.
2. The same sphere alone, elastic, 1.6e-4 s: the steps ``auto`` takes against a fixed 1e-9 s.

The decks are the test suite's (tests/factories.py; tests/api/test_auto_step.py checks both).
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import x3dpd  # noqa: E402
from factories import FIG30_E0, FIG30_E1, FIG30_TAU1, floor_deck  # noqa: E402

R, V = 0.03125, 62.8


def deck(t_end, *, spectator=True, **material):
    d = floor_deck(
        dt=2e-6,
        height=R + 0.003,
        velocity=(0.0, -V, 0.0),
        spectator=spectator,
        radius=R,
        **material,
    )
    return replace(d, parameters=replace(d.parameters, dtmin=1e-10, tmax=t_end))


def main() -> None:
    visco = deck(8e-5, e0=FIG30_E0, e1=FIG30_E1, tau1=FIG30_TAU1)
    auto = x3dpd.run(visco)
    fine = x3dpd.run(visco, dt=1e-9, itrac=2000)
    e_auto = auto.trace.velocity[-1, 0, 1] / V
    e_fine = fine.trace.velocity[-1, 0, 1] / V
    st = auto.summary["step"]
    print(
        f"Lee & Radok impact: restitution auto {e_auto:.5f} ({auto.summary['steps']} steps, "
        f"{st['min']:.3g} .. {st['max']:.3g} s), fixed 1e-9 s {e_fine:.5f} "
        f"({fine.summary['steps']} steps); relative difference "
        f"{abs(e_auto - e_fine) / e_fine:.1e}"
    )
    try:
        x3dpd.run(visco, dt=2e-6, itrac=1)
        print("fixed 2e-6 s: ran")
    except x3dpd.UnstableRunError as exc:
        print(f"fixed 2e-6 s: diagnosed stop ({str(exc)[:80]}...)")
    lone = deck(1.6e-4, spectator=False)
    auto = x3dpd.run(lone)
    fine = x3dpd.run(lone, dt=1e-9, itrac=2000)
    print(
        f"lone elastic sphere: auto {auto.summary['steps']} steps, rebound "
        f"{auto.trace.velocity[-1, 0, 1]:.6f} in/s; fixed 1e-9 s {fine.summary['steps']} "
        f"steps, rebound {fine.trace.velocity[-1, 0, 1]:.6f} in/s"
    )


if __name__ == "__main__":
    main()
