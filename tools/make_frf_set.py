#!/usr/bin/env python3
"""Write the synthetic impact-test fixture ``tests/fixtures/frf/three_modes.uff``.

    python tools/make_frf_set.py [--out FILE]

A structure of three modes measured at four points (nodes 1-4, along x) with the hammer at
node 1 (the driving point): accelerances per unit force [(m/s^2)/N] from modal superposition,

    H_o(w) = (i w)^2 [ sum_r phi_or phi_1r / (w_r^2 - w^2 + 2 i zeta_r w_r w)
                       + L_o / (i w)^2 + U_o ],

with the frequencies, damping ratios, mass-normalised shapes [1/sqrt(kg)] and residual terms
below, on 801 lines 0-200 Hz (0.25 Hz apart), plus complex Gaussian noise of 1 % of each FRF's
RMS (numpy's default_rng(2033): the same bytes on every machine). Written with
``x3dpd.io.frf_set.write_frf_uff`` (binary datasets 58). docs/testing-like-a-test-engineer.md
fits it (``x3dpd fit ... --modes 3``) and tests/cli/test_modal_fit_cli.py checks that.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

FN = np.array([40.0, 95.0, 150.0])  # Hz
ZETA = np.array([0.01, 0.02, 0.015])
#: phi[o, r]: mode r at node o + 1, along x [1/sqrt(kg)]
PHI = 3.0 * np.array([[1.0, 0.8, 0.5], [0.7, -0.4, -0.9], [0.3, -1.0, 0.6], [-0.5, 0.6, 1.1]])
LOWER = np.array([0.5, 0.3, 0.2, -0.1])  # L_o [1/kg]
UPPER = np.array([2e-6, -1e-6, 5e-7, 1.5e-6])  # U_o [m/N]
FREQUENCY = np.linspace(0.0, 200.0, 801)
NOISE = 0.01
SEED = 2033


def accelerances(frequency=FREQUENCY) -> np.ndarray:
    """The noiseless accelerances (4, N_f) of the module docstring (0 at 0 Hz)."""
    w = 2 * np.pi * np.asarray(frequency)
    wn = 2 * np.pi * FN
    iw2 = (1j * w[:, None]) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        modal = np.einsum(
            "or,r,fr->of",
            PHI,
            PHI[0],
            iw2 / (wn**2 - w[:, None] ** 2 + 2j * ZETA * wn * w[:, None]),
        )
        h = modal + LOWER[:, None] + UPPER[:, None] * iw2[:, 0][None, :]
    h[:, w == 0] = 0.0
    return h


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--out", default=str(ROOT / "tests" / "fixtures" / "frf" / "three_modes.uff")
    )
    args = parser.parse_args(argv)
    from x3dpd.io.frf_set import write_frf_uff

    h = accelerances()
    rng = np.random.default_rng(SEED)
    level = NOISE * np.sqrt(np.mean(np.abs(h) ** 2, axis=1))[:, None] / np.sqrt(2)
    h = h + level * (rng.standard_normal(h.shape) + 1j * rng.standard_normal(h.shape))
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_frf_uff(
        args.out,
        FREQUENCY,
        h,
        responses=[(node, 1) for node in range(1, 5)],
        reference=(1, 1),
        quantity="acceleration",
        label="x3dpd synthetic: 3 modes, 4 points",
    )
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
