"""Steady-state detection and amplitude/phase measurement on signals with exact answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.analysis.steady_state import SteadyStateMonitor

F, M, K = 4.84040e-3, 2.04213e-4, 11.4823  # Table 4 drive [lbf], mass, stiffness


def sdof_from_rest(hz: float, zeta: float, t: np.ndarray):
    """x, v of m x'' + c x' + k x = F sin(w t) released at rest at t = 0 (exact).

    Steady part X sin(w t + phi), X = F / sqrt((k - m w^2)^2 + (c w)^2),
    phi = -atan2(c w, k - m w^2); free part exp(-zeta wn t)(C1 cos wd t + C2 sin wd t) with
    C1, C2 from x(0) = v(0) = 0.
    """
    w, wn = 2 * math.pi * hz, math.sqrt(K / M)
    c = 2 * zeta * math.sqrt(K * M)
    wd = wn * math.sqrt(1 - zeta**2)
    amp = F / math.hypot(K - M * w**2, c * w)
    phi = -math.atan2(c * w, K - M * w**2)
    c1 = -amp * math.sin(phi)
    c2 = (zeta * wn * c1 - amp * w * math.cos(phi)) / wd
    s = zeta * wn
    decay = np.exp(-s * t)
    x = amp * np.sin(w * t + phi) + decay * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    v = amp * w * np.cos(w * t + phi) + decay * (
        (-s * c1 + wd * c2) * np.cos(wd * t) + (-s * c2 - wd * c1) * np.sin(wd * t)
    )
    return x, v, amp, phi


def feed_in_chunks(mon: SteadyStateMonitor, t, x, v, chunk: int = 1237, ledger=None):
    for i in range(0, t.size, chunk):
        sl = slice(i, i + chunk)
        led = {k: val[sl] for k, val in ledger.items()} if ledger else None
        if mon.feed(t[sl], x[sl], v[sl], led):
            break
    return mon.result()


def test_a_pure_sinusoid_is_measured_exactly_and_converges_at_once():
    hz, amp, phi = 37.21, 0.0123, -1.1
    w = 2 * math.pi * hz
    t = np.arange(0, 2.0, 1.0 / (hz * 237.3))  # samples not aligned with the cycles
    x = 0.5 + amp * np.sin(w * (t - 0.1) + phi)
    v = amp * w * np.cos(w * (t - 0.1) + phi)
    mon = SteadyStateMonitor(w, t0=0.1, t_start=0.0, window=4, min_windows=3)
    # a dissipated energy growing 2e-5 per cycle
    res = feed_in_chunks(mon, t, x, v, ledger={"dissipated": 2e-5 * t * hz})
    assert res.converged and not res.irregular
    assert res.cycles == 12  # three windows of four: the least the criterion accepts
    # the cycles are resampled by a cubic spline: error <= (5/384) (w h)^4 of the amplitude,
    # with w h = 2 pi / 237.3 here, 6e-9
    rel = 5 / 384 * (2 * math.pi / 237.3) ** 4
    assert res.amplitude == pytest.approx(amp, rel=rel)
    assert res.velocity == pytest.approx(amp * w, rel=rel)
    assert res.acceleration == pytest.approx(amp * w * w, rel=rel)
    assert math.radians(res.phase_deg) == pytest.approx(phi, abs=rel)
    assert res.mean == pytest.approx(0.5, abs=rel * amp)
    assert res.spread < rel
    # the peak comes from samples: within (w dt)^2 / 8 of the amplitude
    assert res.peak == pytest.approx(amp, rel=(2 * math.pi / 237.3) ** 2 / 8)
    assert res.dissipated_per_cycle["dissipated"] == pytest.approx(2e-5, rel=1e-9)


@pytest.mark.parametrize("zeta", [0.003, 0.02])
@pytest.mark.parametrize("hz", [35.0, 38.5, 39.37, 40.0])
def test_linear_sdof_from_rest_stops_within_tolerance_of_its_steady_state(hz, zeta):
    tol = 0.01
    t = np.arange(0, 8.0, 1.0 / (hz * 200))
    x, v, amp, phi = sdof_from_rest(hz, zeta, t)
    mon = SteadyStateMonitor(2 * math.pi * hz, t0=0.0, t_start=0.0, window=5, tol=tol)
    res = feed_in_chunks(mon, t, x, v)
    assert res.converged and res.extrapolated and not res.irregular
    # the criterion promises the limit is within tol: the amplitude is within tol of the exact
    # steady state, the phase within tol radians
    assert res.amplitude == pytest.approx(amp, rel=tol)
    assert math.radians(res.phase_deg) == pytest.approx(phi, abs=tol)
    # long before the transient is gone by itself (exp(-zeta wn t) = tol): a linear response's
    # cycle phasors are exactly geometric, so the limit comes from a few windows
    decay = math.log(1 / tol) / (zeta * math.sqrt(K / M))
    assert res.t_end < min(2.0, decay)


def test_without_extrapolation_it_waits_for_the_transient():
    hz, zeta, tol = 38.5, 0.02, 0.01
    t = np.arange(0, 8.0, 1.0 / (hz * 200))
    x, v, amp, _ = sdof_from_rest(hz, zeta, t)
    mon = SteadyStateMonitor(
        2 * math.pi * hz,
        t0=0.0,
        t_start=0.0,
        window=5,
        tol=tol,
        extrapolate=False,
        deterministic=True,  # a particle-free structure: window by window
    )
    res = feed_in_chunks(mon, t, x, v)
    assert res.converged and not res.extrapolated
    assert res.amplitude == pytest.approx(amp, rel=tol)
    # stops once the measured windows settle: the transient exp(-zeta wn t) is near tol
    assert res.t_end > 0.5 * math.log(1 / tol) / (zeta * math.sqrt(K / M))


def test_an_irregular_response_is_flagged_with_its_spread_and_its_interval():
    """10 % independent scatter per cycle: the point stops once the 95 % half-width of the mean
    amplitude is within tol of it -- about (1.96 x 0.1 / tol)^2 = 96 cycles for tol = 2 % --
    and its interval holds the true amplitude."""
    hz, tol = 37.0, 0.02
    w = 2 * math.pi * hz
    rng = np.random.default_rng(1)
    t = np.arange(0, 10.0, 1.0 / (hz * 200))
    k = np.floor(t * hz).astype(int)
    jitter = 1.0 + 0.1 * rng.standard_normal(k.max() + 1)  # 10 % per-cycle amplitude scatter
    x = 0.01 * jitter[k] * np.sin(w * t)
    mon = SteadyStateMonitor(w, t0=0.0, t_start=0.0, window=8, tol=tol)
    res = feed_in_chunks(mon, t, x, x)
    assert res.converged and res.irregular and not res.extrapolated
    assert res.method == "interval"
    assert 0.05 < res.spread < 0.15
    assert res.amplitude_hw <= tol * res.amplitude
    assert abs(res.amplitude - 0.01) <= res.amplitude_hw
    # the interval is that of independent cycles: t s / sqrt(n), s = 0.1 x 0.01
    assert res.amplitude_hw == pytest.approx(1.96 * 1e-3 / math.sqrt(res.kept), rel=0.2)
    assert 60 < res.cycles < 200


def test_a_growing_response_stops_at_the_cap_unconverged():
    hz = 37.0
    w = 2 * math.pi * hz
    t = np.arange(0, 3.0, 1.0 / (hz * 200))
    x = 0.01 * t * np.sin(w * t)  # resonance without damping: grows linearly
    mon = SteadyStateMonitor(w, t0=0.0, t_start=0.0, window=5, max_cycles=50)
    res = feed_in_chunks(mon, t, x, x)
    assert not res.converged and res.cycles == 50


def test_a_capped_correlated_response_says_its_autocorrelation_time():
    """Amplitudes of AR(1) correlation 0.9 from cycle to cycle (integrated autocorrelation time
    (1 + 0.9) / (2 (1 - 0.9)) = 9.5 cycles), capped at 150 cycles, short of the 50 tau an
    interval needs: not converged, no interval, and tau estimated -- what the sweep's line
    tells the user the interval would need. A response still growing at its cap has none."""
    hz, phi = 37.0, 0.9
    w = 2 * math.pi * hz
    rng = np.random.default_rng(3)
    t = np.arange(0, 4.2, 1.0 / (hz * 200))
    k = np.floor(t * hz).astype(int)
    e = np.zeros(k.max() + 1)
    for c in range(1, e.size):
        e[c] = phi * e[c - 1] + math.sqrt(1 - phi**2) * 0.02 * rng.standard_normal()
    x = 0.01 * (1.0 + e[k]) * np.sin(w * t)
    mon = SteadyStateMonitor(w, t0=0.0, t_start=0.0, window=8, tol=0.002, max_cycles=150)
    res = feed_in_chunks(mon, t, x, x)
    assert not res.converged and res.cycles == 150 and res.amplitude_hw == math.inf
    assert 3.0 < res.tau < 30.0  # 9.5, estimated from ~150 cycles
    growing = SteadyStateMonitor(w, t0=0.0, t_start=0.0, window=5, max_cycles=50)
    assert math.isnan(feed_in_chunks(growing, t, 0.01 * t * np.sin(w * t), x).tau)


def test_a_pause_on_the_way_is_not_taken_for_the_steady_state():
    """A response that climbs from amplitude 0.5 to 0.9 over 60 cycles, pauses there for 15
    -- three identical windows, which the window-to-window test alone accepted -- and then
    approaches its steady amplitude 1 as 1 - 0.1 exp(-k / 20). The state must have held over
    the run's last two thirds: the monitor waits for the amplitude 1."""
    hz, n = 37.0, 400
    w = 2 * math.pi * hz
    amps = np.concatenate(
        [np.linspace(0.5, 0.9, 60), np.full(15, 0.9), 1 - 0.1 * np.exp(-np.arange(n - 75) / 20)]
    )
    t = np.arange(n * 200 + 1) / (200 * hz)
    x = amps[np.minimum((t * hz).astype(int), n - 1)] * np.sin(w * t)
    mon = SteadyStateMonitor(
        w,
        t0=0.0,
        t_start=0.0,
        window=5,
        tol=0.01,
        max_cycles=n,
        extrapolate=False,
        deterministic=True,
    )
    res = feed_in_chunks(mon, t, x, x)
    assert res.converged and res.cycles > 75
    assert res.amplitude == pytest.approx(1.0, rel=0.01)
