"""The report's undamped beam (Table 4) without particles: a mass on a spring and damper to ground,
driven by F sin(w t) -- against the exact SDOF solution.

m = 1.87646e-4 lbf s^2/in, k = 11.4823 lbf/in, c = 3.08293e-4 lbf s/in, F = 4.84040e-3 lbf
(wn = 247.369 rad/s = 39.37 Hz, zeta = c / (2 sqrt(k m)) = 3.32e-3), driven at Appendix C's
37.21 Hz and at the resonance 39.37 Hz. The steady-state amplitude is
X = F / sqrt((k - m w^2)^2 + (c w)^2) (tests/reference.py: Sdof).
"""

from __future__ import annotations

import math

import numpy as np
import pytest


import reference as ref
from factories import TABLE4_C, TABLE4_DRIVE, TABLE4_K, TABLE4_MASS, sdof_deck

from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation

FREQUENCIES = (37.21, 39.37)
#: The tests start with this small velocity [in/s] (6e-5 of the resonant velocity amplitude) so
#: that the exact solution's v0 term is exercised too; test_starts_from_rest_under_a_drive
#: covers the start from rest.
KICK = 1e-3


def _sdof(hz: float, c: float = TABLE4_C) -> ref.Sdof:
    return ref.Sdof(TABLE4_MASS, TABLE4_K, c, TABLE4_DRIVE, 2 * math.pi * hz)


def _run(hz: float, dt: float, t_end: float, itrac: int, v0: float = KICK, c: float = TABLE4_C):
    sim = Simulation(build_model(sdof_deck(dt=dt, hz=hz, itrac=itrac, v0=v0, c=c)))
    first = sim.snapshot()
    block = sim.advance(round(t_end / dt))
    t = np.concatenate([first.times, block.times])
    x = np.concatenate([first.data, block.data])[:, 0, 0]
    return t, x, sim


def test_table4_parameters():
    s = _sdof(39.37)
    assert s.wn / (2 * math.pi) == pytest.approx(39.37, abs=5e-4)  # report: 247.369 rad/s
    assert s.zeta == pytest.approx(3.3209e-3, rel=1e-4)


@pytest.mark.parametrize("hz", FREQUENCIES)
def test_transient_follows_the_exact_solution(hz):
    """From the exact initial conditions (x = 0, v = KICK) the whole response -- homogeneous plus
    particular -- for 1 s (37-39 cycles, the transient still ~45 % of its start)."""
    s = _sdof(hz)
    dt = 1e-5  # w dt = 2.5e-3
    t, x, _ = _run(hz, dt, 1.0, itrac=1)
    err = np.abs(x - s.response(t, v0=KICK)).max() / s.amplitude
    print(f"\n{hz} Hz: X = {s.amplitude:.6e} in, max |x - exact| = {err:.1e} X")
    # The brief's bound: 0.5 % of the amplitude. Measured 3.5e-4 (37.21 Hz) and 8e-5 (39.37 Hz):
    # the damper sees the half-step velocity v(n+1/2) at t(n+1) (X3D's central difference), an
    # O(c dt) lag that shifts the stiffness by c w^2 dt / 2; it makes the scheme first order in
    # c dt (see test_convergence_order) and dominates this error.
    assert err < 5e-3
    assert err < 1e-3


def test_convergence_order():
    """Without the damper the scheme is second order (spring + drive); the damper's half-step
    velocity makes it first order in c dt. Errors at 37.21 Hz over 0.5 s, dt = 4e-5 .. 5e-6."""
    dts = np.array([4e-5, 2e-5, 1e-5, 5e-6])
    orders = {}
    for c in (0.0, TABLE4_C):
        s = _sdof(37.21, c)
        errs = []
        for dt in dts:
            t, x, _ = _run(37.21, dt, 0.5, itrac=1, c=c)
            errs.append(np.abs(x - s.response(t, v0=KICK)).max() / s.amplitude)
        orders[c] = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    print(f"\nconvergence orders: undamped {orders[0.0]:.2f}, damped {orders[TABLE4_C]:.2f}")
    assert orders[0.0] == pytest.approx(2.0, abs=0.1)  # measured 2.00
    # measured 1.09: first order with a small second-order part; documented, not asserted tight
    assert 0.9 < orders[TABLE4_C] < 1.5


def _fit_amplitude(t, x, w):
    """Least-squares x ~ a sin(w t) + b cos(w t) + c; returns sqrt(a^2 + b^2)."""
    basis = np.stack([np.sin(w * t), np.cos(w * t), np.ones_like(t)], axis=1)
    (a, b, _), *_ = np.linalg.lstsq(basis, x, rcond=None)
    return math.hypot(a, b)


@pytest.mark.parametrize("hz", FREQUENCIES)
def test_steady_state_amplitude(hz):
    """At the report's step (5e-7 s): run until the transient exp(-zeta wn t) has decayed below
    1e-3 (t = ln(1000) / (zeta wn) = 8.41 s, ~17 million steps, ~1.5 s), then fit the amplitude at
    the drive frequency over the next second."""
    s = _sdof(hz)
    dt = 5e-7
    t_decay = s.decay_time(1e-3)
    t, x, _ = _run(hz, dt, t_decay + 1.0, itrac=100)
    window = t >= t_decay
    amp = _fit_amplitude(t[window], x[window], s.omega)
    err = amp / s.amplitude - 1
    print(
        f"\n{hz} Hz: steady amplitude {amp:.6e} in, analytic X = {s.amplitude:.6e} in "
        f"({err:+.1e}); transient decay time to 1e-3: {t_decay:.2f} s"
    )
    # 0.5 % (the brief). Error budget: the leftover transient, <= 1e-3 of its initial amplitude
    # (<= 1.0 X here) and the integrator (~1e-5 at this step); measured < 1e-3 at both.
    assert abs(err) < 5e-3


@pytest.mark.validate
@pytest.mark.parametrize("hz", FREQUENCIES)
def test_steady_state_amplitude_fully_decayed(hz):
    """Long version: transient decayed below 1e-6 (16.8 s, 34 million steps) before a 2 s
    window; the amplitude is then within 1e-4 (integrator error ~1e-5, transient 1e-6)."""
    s = _sdof(hz)
    dt = 5e-7
    t_decay = s.decay_time(1e-6)
    t, x, _ = _run(hz, dt, t_decay + 2.0, itrac=100)
    window = t >= t_decay
    amp = _fit_amplitude(t[window], x[window], s.omega)
    print(f"\n{hz} Hz: {amp / s.amplitude - 1:+.2e}")
    assert amp == pytest.approx(s.amplitude, rel=1e-4)


def test_starts_from_rest_under_a_drive():
    """Regression guard: from rest under a drive, after step 1 the Verlet correction
    dt^2 f^2 / (8 m) equals the kinetic energy m (dt f / 2m)^2 / 2 exactly, and the step-stability
    audit used to stop the run as unstable on that one ledger row (ITRAC = 1, any dt)."""
    s = _sdof(39.37)
    t, x, _ = _run(39.37, 5e-7, 0.01, itrac=1, v0=0.0)
    assert np.abs(x - s.response(t)).max() < 1e-3 * s.amplitude
