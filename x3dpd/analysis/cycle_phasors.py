"""What one drive cycle of a sine-driven response measures, and where a geometric transient
goes: the cycle's fundamental phasor (:func:`fit_cycle`) and the limit of a linear response's
cycle phasors (:func:`prony_limit`, Prony's method). x3dpd.analysis.steady_state feeds them.
"""

from __future__ import annotations

import math

import numpy as np

#: Relative changes below this are the cycle fits' floating-point noise: no change at all.
ROUNDOFF = 1e-9

#: Largest relative residual of the Prony recurrence for a response to count as linear.
PRONY_RESIDUAL = 0.01


def prony_limit(phasors) -> tuple[complex, float, float]:
    """Limit of P_k = P_inf + u r^k + v conj(r)^k from its last terms (module docstring).

    Returns (P_inf, relative residual of the recurrence fit, largest |root|); a sequence whose
    differences are round-off returns its last term.
    """
    p = np.asarray(phasors, dtype=complex)
    d = np.diff(p)
    scale = abs(p[-1]) or 1.0
    if np.max(np.abs(d)) < ROUNDOFF * scale:
        return complex(p[-1]), 0.0, 0.0
    a = np.column_stack([d[1:-1], -d[:-2]])
    b = d[2:]
    a_real = np.concatenate([a.real, a.imag])
    b_real = np.concatenate([b.real, b.imag])
    (a1, a2), *_ = np.linalg.lstsq(a_real, b_real, rcond=None)
    residual = float(np.linalg.norm(a_real @ [a1, a2] - b_real) / (np.linalg.norm(b_real) or 1.0))
    r1, r2 = np.roots([1.0, -a1, a2]).astype(complex)
    rmax = float(max(abs(r1), abs(r2)))
    if rmax >= 1.0 or abs(r1 - r2) < 1e-9:
        return complex(p[-1]), residual, max(rmax, 1.0)
    # D_a = u + v, D_b = u r1 + v r2 for the last two differences; the rest sums geometrically
    d_a, d_b = d[-2], d[-1]
    v = (d_b - r1 * d_a) / (r2 - r1)
    u = d_a - v
    rest = u * r1**2 / (1 - r1) + v * r2**2 / (1 - r2)
    return complex(p[-1] + rest), residual, rmax


#: Points per cycle of the uniform resampling the phasor is computed on.
CYCLE_POINTS = 256


def fit_cycle(
    t: np.ndarray, x: np.ndarray, omega: float, t0: float, lo: float
) -> tuple[complex, float]:
    """Fundamental of ``x`` over the drive cycle [lo, lo + T): returns (b + i a, m).

    ``x = m + a cos(w (t - t0)) + b sin(w (t - t0)) + harmonics``. The samples (which need not
    fall on the cycle's ends, and must reach a little past both) are interpolated by a cubic
    spline onto CYCLE_POINTS points spaced uniformly over exactly one period, and a, b, m are
    their discrete Fourier coefficients. Every cycle is thus measured by the same operator --
    which keeps a linear transient's cycle phasors exactly geometric (the extrapolation relies
    on it) -- with an interpolation error of O((w h)^4) for a sample spacing h.
    """
    from scipy.interpolate import CubicSpline

    period = 2.0 * math.pi / omega
    tj = lo + period * np.arange(CYCLE_POINTS) / CYCLE_POINTS
    xj = CubicSpline(t, x)(tj)
    th = omega * (tj - t0)
    a = 2.0 * float(np.mean(xj * np.cos(th)))
    b = 2.0 * float(np.mean(xj * np.sin(th)))
    return complex(b, a), float(np.mean(xj))
