"""Ring-down damping extraction on signals with exact answers, generated here from formulas."""

from __future__ import annotations

import numpy as np
import pytest

from x3dpd.analysis.ringdown import G_IN_S2, damping_vs_amplitude
from x3dpd.errors import InputError

WN = 2.0 * np.pi * 39.37  # the report's beam, 39.37 Hz [rad/s]


def linear_ringdown(zeta: float, a0: float = 0.05, cycles: float = 60.0, per_cycle: int = 200):
    """x = A0 exp(-zeta wn t) cos(wd t): the free linear SDOF ring-down."""
    wd = WN * np.sqrt(1.0 - zeta**2)
    t = np.arange(int(cycles * per_cycle)) * (2.0 * np.pi / wd) / per_cycle
    return t, a0 * np.exp(-zeta * WN * t) * np.cos(wd * t)


def coulomb_ringdown(a0: float, delta: float, per_cycle: int = 200):
    """x'' + wn^2 x = -wn^2 delta sign(x'), released from x = a0 at rest.

    Half cycle j (t_j = j pi / wn) oscillates about (-1)^j delta with amplitude a_j - delta,
    a_j = a0 - 2 j delta: x = (-1)^j (delta + (a_j - delta) cos(wn (t - t_j))). The peaks fall on
    the straight line a(t) = a0 - 2 delta wn t / pi; it sticks once a_j <= delta.
    """
    n_half = int((a0 - delta) / (2.0 * delta))
    t = np.arange(n_half * per_cycle // 2) * (2.0 * np.pi / WN) / per_cycle
    j = np.floor(t * WN / np.pi).astype(int)
    a_j = a0 - 2.0 * j * delta
    x = (-1.0) ** j * (delta + (a_j - delta) * np.cos(WN * t - j * np.pi))
    return t, x


@pytest.mark.parametrize("zeta", [0.003, 0.02, 0.05])
def test_linear_ringdown_gives_its_exact_zeta(zeta):
    t, x = linear_ringdown(zeta, cycles=min(60.0, 3.0 / zeta / (2 * np.pi)) + 20)
    rd = damping_vs_amplitude(t, x)
    # The record, extended on both sides as a two-sided ring-down, transforms almost exactly;
    # what remains is the O(zeta^2) difference between the Hilbert envelope of a damped cosine
    # and exp(-zeta wn t) and the spline's fit of the ends: 0.2 % of zeta, 1e-4 of amplitude.
    np.testing.assert_allclose(rd.zeta, zeta, rtol=2e-3)
    exact = 0.05 * np.exp(-zeta * WN * rd.time)
    np.testing.assert_allclose(rd.amplitude, exact, rtol=1e-4)
    np.testing.assert_allclose(rd.frequency_hz, WN * np.sqrt(1 - zeta**2) / (2 * np.pi), rtol=1e-3)
    # dB re 1 g of the acceleration amplitude wd^2 A
    wd = WN * np.sqrt(1 - zeta**2)
    np.testing.assert_allclose(rd.amplitude_db, 20 * np.log10(wd**2 * exact / G_IN_S2), atol=0.03)


def test_coulomb_ringdown_gives_its_linear_envelope():
    a0, delta = 0.05, 2.5e-4
    t, x = coulomb_ringdown(a0, delta)
    rd = damping_vs_amplitude(t, x, floor=20 * delta)
    # x = delta sign(sin wn t) + (a_j - delta) cos wn t: a cosine whose staircase amplitude
    # a_j - delta averages to the peak line a(t), plus a square wave in quadrature whose
    # fundamental 4 delta / pi adds (8/pi^2)(delta/a)^2 < 0.2 % and whose odd harmonics ripple
    # by ~ delta / a < 5 % within a cycle, averaged out by the 4-cycle spline pieces: 0.5 %.
    line = a0 - 2.0 * delta * WN * rd.time / np.pi
    np.testing.assert_allclose(rd.amplitude, line, rtol=5e-3)
    # equivalent viscous ratio of a linear decay: zeta = -(dA/dt) / (wn A) = 2 delta / (pi A);
    # the slope of the fit carries the ripple's residue, twice the envelope's: 1 %.
    zeta_exact = 2.0 * delta / (np.pi * line)
    np.testing.assert_allclose(rd.zeta, zeta_exact, rtol=0.01)
    # zeta grows as the amplitude falls: the friction-damper signature
    assert np.all(np.diff(rd.zeta) > 0)


def test_too_short_a_record_is_refused():
    t, x = linear_ringdown(0.02, cycles=5)
    with pytest.raises(InputError, match="cycles"):
        damping_vs_amplitude(t, x)


def test_each_levels_interval_holds_the_true_zeta_95_percent_of_the_time():
    """A linear ring-down (zeta 2 %) measured with white noise of 0.2 % of its start amplitude:
    over 80 noisy records, the share of levels whose 95 % interval holds the true zeta is about
    0.95 (0.88 and above passes: the levels of one record are correlated, so the share scatters
    more than 80 independent draws would), and the intervals shrink to nothing without noise."""
    zeta = 0.02
    t, x = linear_ringdown(zeta, cycles=40.0)
    clean = damping_vs_amplitude(t, x)
    assert np.all(clean.zeta_ci < 1e-3 * zeta)
    rng = np.random.default_rng(12)
    held, total = 0, 0
    for _ in range(80):
        rd = damping_vs_amplitude(t, x + 0.002 * 0.05 * rng.standard_normal(t.size))
        # the middle level of each record (one draw per record: independent across records)
        k = rd.zeta.size // 2
        held += abs(rd.zeta[k] - clean.zeta[k]) <= rd.zeta_ci[k]
        total += 1
    assert held / total >= 0.88, held / total
