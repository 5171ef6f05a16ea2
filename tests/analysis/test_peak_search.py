"""The peak search of ``--freq auto`` (x3dpd.analysis.peak_search) on responses whose peaks are
known in closed form: a single mode (the fit is exact), two modes (the fit converges), a peak
beyond the band's edge."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.analysis.peak_search import PeakSearch


def sdof(f, fn=37.74, zeta=0.0032):
    """|X| / (F / k) of a force-driven SDOF at f [Hz]."""
    r = f / fn
    return 1.0 / math.hypot(1.0 - r * r, 2.0 * zeta * r)


def two_modes(f):
    """|receptance| of two well separated modes (36 Hz, 2 %; 41 Hz, 1 %, weaker)."""
    w = 2 * math.pi * f
    return abs(
        sum(
            a / ((2 * math.pi * fk) ** 2 - w * w + 2j * z * 2 * math.pi * fk * w)
            for a, fk, z in ((1.0, 36.0, 0.02), (0.6, 41.0, 0.01))
        )
    )


def search(response, lo, hi, resolution, max_points=12):
    s = PeakSearch(lo, hi, resolution, max_points=max_points, tol=1e-4)
    points = []
    while fresh := s.next_frequencies(points):
        points += [(f, response(f), 0.0) for f in fresh]
    return s.peak(points), points


def true_peak(response, lo, hi):
    f = np.linspace(lo, hi, 400_001)
    a = np.array([response(x) for x in f])
    k = int(np.argmax(a))
    return f[k], a[k]


def test_a_single_mode_is_found_exactly_with_one_refinement_point():
    """1/X^2 of one mode is a quadratic in f^2: the coarse pass alone fits it exactly, and the
    point at its peak confirms it (5 points)."""
    peak, points = search(sdof, 35.0, 40.0, 0.001 * 37.74)
    f, a = true_peak(sdof, 35.0, 40.0)
    # the closed form: f_peak = fn sqrt(1 - 2 zeta^2), X = 1 / (2 zeta sqrt(1 - zeta^2))
    assert f == pytest.approx(37.74 * math.sqrt(1 - 2 * 0.0032**2), abs=2e-5)
    assert peak.converged and len(points) == 5
    assert peak.frequency_hz == pytest.approx(f, rel=1e-6)
    assert peak.amplitude == pytest.approx(1 / (2 * 0.0032 * math.sqrt(1 - 0.0032**2)), rel=1e-9)
    # half-power band: f_n sqrt(1 - 2 z^2 -/+ 2 z sqrt(1 - z^2)), about f_n (1 -/+ zeta)
    z = 0.0032
    lo = 37.74 * math.sqrt(1 - 2 * z * z - 2 * z * math.sqrt(1 - z * z))
    hi = 37.74 * math.sqrt(1 - 2 * z * z + 2 * z * math.sqrt(1 - z * z))
    assert (peak.band_lo_hz, peak.band_hi_hz) == pytest.approx((lo, hi), rel=1e-9)


def test_the_larger_of_two_modes_is_found_to_a_tenth_of_a_percent():
    peak, points = search(two_modes, 33.0, 44.0, 0.001 * 36.0)
    f, a = true_peak(two_modes, 33.0, 44.0)
    assert peak.converged and len(points) <= 10
    assert peak.frequency_hz == pytest.approx(f, rel=1e-3)
    assert peak.amplitude == pytest.approx(a, rel=1e-3)


def test_a_peak_beyond_the_band_is_reported_at_its_edge():
    peak, points = search(sdof, 30.0, 36.0, 0.01)
    assert peak.at_edge and not peak.converged
    assert peak.frequency_hz == 36.0
    assert len(points) == 4  # the coarse pass says it: no refinement wasted


def test_the_budget_caps_the_points():
    _, points = search(two_modes, 33.0, 44.0, 1e-6, max_points=6)
    assert len(points) == 6
