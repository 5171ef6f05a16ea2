"""The steady state's confidence intervals (x3dpd.analysis.confidence) on series whose answers
are known in closed form: AR(1) cycle-to-cycle correlation, start-up transients, periodic
responses."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.analysis.confidence import (
    assess,
    autocorrelation_time,
    mean_interval,
    mser_truncation,
)


def ar1(rng, n: int, phi: float, sigma: float) -> np.ndarray:
    """A complex AR(1) series of stationary standard deviation ``sigma`` (each part sigma /
    sqrt 2) and lag-1 correlation ``phi``, started in its stationary law."""
    e = (rng.standard_normal(n) + 1j * rng.standard_normal(n)) * sigma / math.sqrt(2.0)
    out = np.empty(n, complex)
    x = e[0]
    for k in range(n):
        x = phi * x + math.sqrt(1.0 - phi * phi) * e[k] if k else x
        out[k] = x
    return out


@pytest.mark.parametrize("phi", [0.0, 0.5, 0.9])
def test_the_autocorrelation_time_of_an_ar1_series(phi):
    """tau = (1/2)(1 + phi)/(1 - phi) for x_k = phi x_{k-1} + e_k: the variance of the mean of
    n values is 2 tau var / n. Over 200,000 values Geyer's estimate has a relative error of
    about sqrt(2 (2 M + 1) / n) ~ 2-7 % (M the window, ~ 10 tau)."""
    rng = np.random.default_rng(7)
    series = ar1(rng, 200_000, phi, 1.0).real
    expected = 0.5 * (1 + phi) / (1 - phi)
    assert autocorrelation_time(series) == pytest.approx(expected, rel=0.1)


def test_a_constant_series_has_no_scatter_and_a_zero_half_width():
    iv = mean_interval(np.full(40, 3.25))
    assert iv.mean == 3.25 and iv.half_width == 0.0


def test_independent_values_get_students_interval():
    """Independent values: tau = 1/2, n_eff = n, the half-width t_{0.975, n-1} s / sqrt(n)."""
    from scipy.stats import t

    rng = np.random.default_rng(3)
    y = 5.0 + rng.standard_normal(400)
    iv = mean_interval(y)
    # Geyer's tau of white noise is 1/2 up to its own noise
    expected = t.ppf(0.975, 399) * np.std(y, ddof=1) / math.sqrt(400)
    assert iv.half_width == pytest.approx(expected, rel=0.15)


def test_a_short_correlated_run_has_no_interval_yet():
    """Fewer than 50 autocorrelation times of cycles: tau itself is not known well enough."""
    rng = np.random.default_rng(4)
    y = ar1(rng, 300, 0.95, 1.0).real  # tau = 19.5: needs ~975 cycles
    assert mean_interval(y).half_width == math.inf


def test_mser_cuts_a_transient_and_waits_while_it_drifts():
    """A jump of 10 noise levels that decays with time constant 20 cycles: while it still drifts
    over the first half of the run MSER says so; later it cuts it off (twice its minimum)."""
    rng = np.random.default_rng(5)
    k = np.arange(400)
    z = 1.0 + 0.02 * rng.standard_normal(400) + 0.2 * np.exp(-k / 20)
    cut, out = mser_truncation(z[:30])
    assert not out
    cut, out = mser_truncation(z)
    assert out
    # the transient is below a tenth of the noise where the cut falls
    assert 0.2 * math.exp(-cut / 20) < 0.002
    assert cut < 200


def test_a_periodic_response_after_its_transient_is_exact():
    """Cycle phasors that reach a fixed value exactly: zero half-widths once the transient is
    out, the mean the fixed value."""
    k = np.arange(120)
    p = np.where(k < 30, 0.5 + 0.01 * k, 1.0) * np.exp(0.7j)
    a = assess(p)
    assert a.settled and a.within(1e-6)
    assert a.interval.amplitude == pytest.approx(1.0, abs=1e-15)
    assert a.interval.amplitude_hw == 0.0


def stopped_coverage(
    phi: float,
    transient: float,
    tol: float,
    runs: int,
    seed: int,
    scatter: float = 0.05,
    most: int = 6000,
    every: int = 5,
) -> tuple:
    """Run the sequential stop on ``runs`` synthetic series (mean phasor e^{0.3i}, amplitude 1;
    AR(1) scatter ``scatter`` of lag-1 correlation ``phi``; plus a start-up transient of
    ``transient`` decaying over 20 cycles), each checked every ``every`` cycles as the monitor
    does, and return (the share whose interval holds the true amplitude 1, the median cycles
    run). tools/study/run_length_coverage.py runs it at other run lengths."""
    rng = np.random.default_rng(seed)
    held, cycles = 0, []
    k = np.arange(most)
    for _ in range(runs):
        z = np.exp(0.3j) + ar1(rng, k.size, phi, scatter) + transient * np.exp(-k / 20 + 1.2j)
        for n in range(15, k.size + 1, every):
            a = assess(z[:n])
            if a.within(tol):
                break
        iv = a.interval
        held += abs(iv.amplitude - 1.0) <= iv.amplitude_hw
        cycles.append(n)
    return held / runs, float(np.median(cycles))


@pytest.mark.parametrize("phi,transient", [(0.0, 0.0), (0.0, 0.5), (0.8, 0.5)])
def test_the_stopped_intervals_hold_the_true_amplitude_95_percent_of_the_time(phi, transient):
    """The intervals a point stops with cover the true amplitude as often as their level says,
    for independent and strongly correlated cycles, with a start-up transient of 10 noise
    levels. Over 150 runs the share of a true 95 % has a standard error of 1.8 %: 0.90 and
    above passes (batch means after a single MSER cut, without the run-length rule, covered
    0.51-0.74 on such series)."""
    share, cycles = stopped_coverage(phi, transient, 0.01, runs=150, seed=11)
    assert share >= 0.90, (share, cycles)
