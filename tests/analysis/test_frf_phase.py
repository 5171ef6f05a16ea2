"""The FRF figure's phase (issue 33, item 26): unwrapped, so a phase that passes +/-180 deg
(an accelerance below resonance, a measured FRF with a sensor's delay) does not jump from one
edge of the plot to the other."""

from __future__ import annotations

import numpy as np

from x3dpd.analysis.frf_plots import phase_degrees


def test_a_phase_through_180_degrees_is_continuous():
    # a receptance measured through a 10 ms delay: -w tau - the SDOF's lag, past -180 deg
    m, k = 1.0, (2 * np.pi * 37.7) ** 2
    c = 2 * 0.003 * np.sqrt(k * m)
    w = 2 * np.pi * np.linspace(30.0, 45.0, 601)
    h = np.exp(-1j * w * 0.010) / (k - m * w**2 + 1j * c * w)
    raw = np.degrees(np.angle(h))
    assert np.max(np.abs(np.diff(raw))) > 300  # numpy's angle jumps from -180 to +180
    phase = phase_degrees(h)
    assert np.max(np.abs(np.diff(phase))) < 20  # resonance turns it by 180 over several lines
    # in all: the delay's -w tau plus the resonance's -180 deg
    expected = -np.degrees((w[-1] - w[0]) * 0.010) - 180.0
    assert abs((phase[-1] - phase[0]) - expected) < 2.0
    assert -180 < np.mean(phase) <= 180
    np.testing.assert_allclose(np.exp(1j * np.radians(phase)), h / np.abs(h), atol=1e-12)
