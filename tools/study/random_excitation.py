"""What the ``random:`` force law costs and delivers (docs/usrfrc.md, "random").

    python tools/study/random_excitation.py

1. The step cost of the Table 4 SDOF (no particles, 5e-7 s) driven by the built-in ``sine`` and
   by ``random`` (band 10-150 Hz, the default 16 s period: 19,200 knots), the fastest of three
   windows of 2,000,000 steps each, after a warm-up.
2. The realised PSD of a ``random`` spec over one period, per third-octave band of its band,
   over the requested level (sampled at 4 kHz; a rectangular window over whole periods puts
   every line on a bin).
3. The interpolation's error: a random motion of one line (a band holding one grid line, HI) against
   its closed form A sin, A w cos, -A w^2 sin, as a fraction of A, A w, A w^2 (the largest over
   20,000 times in a period).
"""

from __future__ import annotations

import math
import time

import numpy as np

from x3dpd.deck.cards import Boundary, Deck, Element, Mass, Material, Node, Parameters
from x3dpd.model.build import build_model
from x3dpd.physics.motion import motion_history, motion_table
from x3dpd.physics.usrfrc import force_table, force_values
from x3dpd.solver.simulation import Simulation

DRIVES = {
    "sine": "sine:node=1,dof=1,amp=4.84040e-3,hz=37.21",
    "random": "random:node=1,dof=1,rms=4.84040e-3,band=10:150,seed=1",
}


def sdof() -> Deck:
    return Deck(
        parameters=Parameters(0.0, 1.0, 0.0, 5e-7, 5e-7, 0, 1e9, 0, 5, 0, 10**9),
        materials=(Material(2, 1, 1e-12, 1.0, 11.4823, 0.0, 0.0, 3.08293e-4),),
        nodes=(Node(1, 0.0, 0.0, 0.0),),
        elements=(Element(1, 2, (1,)),),
        masses=(Mass(1, 1.87646e-4, 0.0, 0.0, 0.0),),
        boundaries=(Boundary(1, 1, 1, (2, 3, 4, 5, 6)),),
    )


def step_cost(spec: str, steps: int = 2_000_000, repeat: int = 3) -> float:
    sim = Simulation(build_model(sdof()), usrfrc=[spec], itrac=10**9)
    sim.initialize()
    sim.advance(10_000, max_rows=1)
    best = math.inf
    for _ in range(repeat):
        t = time.perf_counter()
        sim.advance(steps, max_rows=1)
        best = min(best, (time.perf_counter() - t) / steps)
    return best


def third_octaves(spec: str, lo: float, hi: float, period: float, fs: float = 4000.0):
    n = int(round(period * fs))
    x = force_values(np.arange(n) / fs, force_table([spec], [1]))[:, 0]
    g = 2.0 * np.abs(np.fft.rfft(x)) ** 2 / (n * fs)
    f = np.fft.rfftfreq(n, 1.0 / fs)
    for k in range(-20, 10):
        centre = 1000.0 * 10 ** (k / 10)
        a, b = centre * 10**-0.05, centre * 10**0.05
        if a >= lo and b <= hi:
            yield centre, float(g[(f >= a) & (f < b)].mean())


def one_line_errors(hi: float = 150.0, period: float = 4.0) -> tuple[float, float, float]:
    """Max error of u, u', u'' of a one-line random motion at ``hi`` over its amplitudes."""
    spec = f"random:node=1,dof=1,rms=1,band={hi - 0.1}:{hi},seed=3,period={period}"
    t = np.linspace(0.0, period, 20001)
    u, v, a = (c[:, 0] for c in motion_history(t, motion_table([spec], [1])))
    w = 2 * np.pi * hi
    phase = 2 * np.pi * np.random.default_rng(3).random(1)[0]
    amp = math.sqrt(2.0)  # unit RMS acceleration
    return (
        float(np.max(np.abs(u + amp / w**2 * np.sin(w * t + phase)))) / (amp / w**2),
        float(np.max(np.abs(v + amp / w * np.cos(w * t + phase)))) / (amp / w),
        float(np.max(np.abs(a - amp * np.sin(w * t + phase)))) / amp,
    )


def main() -> None:
    for name, spec in DRIVES.items():
        print(f"{name:>6}: {step_cost(spec) * 1e9:6.1f} ns/step  ({spec})")
    spec = "random:node=1,dof=1,psd=1e-6,band=20:1000,seed=7,period=4"
    ratios = [level / 1e-6 for _, level in third_octaves(spec, 20.0, 1000.0, 4.0)]
    for (centre, _level), r in zip(third_octaves(spec, 20.0, 1000.0, 4.0), ratios):
        print(f"  {centre:7.1f} Hz  PSD / requested = {r:.5f}")
    print(
        f"{spec}: {len(ratios)} third-octave bands, PSD / requested "
        f"{min(ratios):.5f} .. {max(ratios):.5f}"
    )
    eu, ev, ea = one_line_errors()
    print(
        f"one line at HI, 8 knots per period: errors {eu:.1e} (value), {ev:.1e} (slope), "
        f"{ea:.1e} (curvature) of the line's amplitude"
    )


if __name__ == "__main__":
    main()
