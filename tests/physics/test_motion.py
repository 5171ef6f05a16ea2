"""Prescribed sinusoidal motion (x3dpd.physics.motion) against its closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.errors import UsrfrcError
from x3dpd.physics.motion import (
    _apply_motion,
    apply_motion,
    motion_history,
    motion_table,
    prescribed_mask,
)

IDS = np.array([3, 10, 25, 40], dtype=np.int64)
X0 = np.arange(12, dtype=np.float64).reshape(4, 3) * 0.1


def test_table_layout():
    table = motion_table(
        [
            "node=25,dof=1,amp=0.01,hz=37.21",
            "sine:node=40,dof=3,amp=-2e-3,omega=100,phase=90,t0=0.5",
            "node=3,dof=5,amp=0.1,hz=2,phase=0.25rad,ramp=0.3",
        ],
        IDS,
        x0=X0,
    )
    np.testing.assert_allclose(
        table,
        [
            [2, 0, 0.01, 2 * math.pi * 37.21, 0.0, 0.0, X0[2, 0], 0.0],
            [3, 2, -2e-3, 100.0, math.pi / 2, 0.5, X0[3, 2], 0.0],
            [0, 4, 0.1, 4 * math.pi, 0.25, 0.0, 0.0, 0.3],
        ],
        rtol=1e-15,
    )
    assert motion_table(["node=25,dof=2,amp=1,hz=1"], IDS)[0, 6] == 0.0  # no x0 given
    assert motion_table([], IDS).shape == (0, 8)

    class FakeModel:
        node_ids = IDS
        x0 = X0

    assert motion_table(["node=40,dof=2,amp=1,hz=1"], FakeModel())[0, 6] == X0[3, 1]


@pytest.mark.parametrize(
    "spec, words",
    [
        ("node=25,dof=1,hz=3", ["missing", "amp"]),
        ("node=25,dof=1,amp=1,hz=3,law=log", ["unknown key", "'law'"]),
        ("node=24,dof=1,amp=1,hz=3", ["node=24", "not defined"]),
        # a motion's DOFs are displacements and rotations, not forces and moments
        ("node=25,dof=9,amp=1,hz=3", ["dof=", "1..6 (1-3 displacements along x, y, z; 4-6 rot"]),
        ("node=25,dof=1,amp=1,hz=-3", ["hz=", "positive"]),
        ("node=25,dof=1,amp=1", ["hz=", "omega="]),
        ("node=25,dof=1,amp=inf,hz=3", ["amp=", "finite"]),
    ],
)
def test_bad_motion_specs(spec, words):
    with pytest.raises(UsrfrcError) as err:
        motion_table([spec], IDS)
    assert repr(spec) in str(err.value)
    for word in words:
        assert word in str(err.value)


def test_a_dof_cannot_be_driven_twice():
    with pytest.raises(UsrfrcError, match="already driven"):
        motion_table(["node=25,dof=1,amp=1,hz=3", "node=25,dof=1,amp=2,hz=4"], IDS)


@pytest.mark.parametrize(
    "phase, phi", [("", 0.0), (",phase=45", math.pi / 4), (",phase=-1rad", -1.0)]
)
@pytest.mark.parametrize("t0", [0.0, 0.2])
def test_history_closed_form_and_derivatives(phase, phi, t0):
    amp, hz = 0.01, 37.21
    w = 2 * math.pi * hz
    table = motion_table([f"node=25,dof=1,amp={amp},hz={hz},t0={t0}{phase}"], IDS)
    t = np.linspace(0.0, 1.0, 200001)
    u, v, a = (c[:, 0] for c in motion_history(t, table))
    arg = w * (t - t0) + phi
    on = t >= t0
    np.testing.assert_allclose(
        u, np.where(on, amp * np.sin(arg), amp * math.sin(phi)), rtol=0, atol=1e-15
    )
    np.testing.assert_allclose(
        v, np.where(on, amp * w * np.cos(arg), 0.0), rtol=0, atol=1e-13 * amp * w
    )
    np.testing.assert_allclose(
        a, np.where(on, -amp * w * w * np.sin(arg), 0.0), rtol=0, atol=1e-12 * amp * w * w
    )
    # velocity and acceleration are the time derivatives (central differences, away from t0)
    h = t[1] - t[0]
    inner = np.abs(t[1:-1] - t0) > 2 * h
    du = (u[2:] - u[:-2]) / (2 * h)
    dv = (v[2:] - v[:-2]) / (2 * h)
    np.testing.assert_allclose(du[inner], v[1:-1][inner], rtol=0, atol=2e-4 * amp * w)
    np.testing.assert_allclose(dv[inner], a[1:-1][inner], rtol=0, atol=2e-4 * amp * w * w)


def test_apply_motion_sets_only_the_driven_dofs():
    table = motion_table(
        [
            "node=25,dof=2,amp=0.01,hz=5",
            "node=40,dof=6,amp=0.2,hz=3,phase=30",  # rotational: velocity only
            "node=3,dof=3,amp=-0.5,omega=7,t0=1",
        ],
        IDS,
        x0=X0,
    )
    rng = np.random.default_rng(3)
    x, vel = rng.normal(size=(4, 3)), rng.normal(size=(4, 6))
    x_before, vel_before = x.copy(), vel.copy()
    t = 0.37
    apply_motion(t, table, X0, x, vel)
    w1, w2 = 2 * math.pi * 5, 2 * math.pi * 3
    expect_x, expect_v = x_before.copy(), vel_before.copy()
    expect_x[2, 1] = X0[2, 1] + 0.01 * math.sin(w1 * t)
    expect_v[2, 1] = 0.01 * w1 * math.cos(w1 * t)
    expect_v[3, 5] = 0.2 * w2 * math.cos(w2 * t + math.pi / 6)
    expect_x[0, 2] = X0[0, 2]  # before its t0: rests at x0 + amp sin(0)
    expect_v[0, 2] = 0.0
    np.testing.assert_allclose(x, expect_x, rtol=1e-15, atol=1e-17)
    np.testing.assert_allclose(vel, expect_v, rtol=1e-15, atol=1e-17)

    _apply_motion(1.5, table, X0, x, vel)  # the raw kernel, as the solver calls it
    assert x[0, 2] == pytest.approx(X0[0, 2] - 0.5 * math.sin(7 * 0.5), rel=1e-15)
    assert vel[0, 2] == pytest.approx(-0.5 * 7 * math.cos(7 * 0.5), rel=1e-15)

    with pytest.raises(ValueError):
        apply_motion(0.0, table, X0, x[:2], vel[:2])


def test_prescribed_mask():
    table = motion_table(["node=25,dof=2,amp=1,hz=5", "node=40,dof=6,amp=1,hz=3"], IDS)
    mask = prescribed_mask(table, 4)
    assert mask.dtype == bool and mask.sum() == 2 and mask[2, 1] and mask[3, 5]


def test_ramp_starts_smoothly_and_reaches_the_sine():
    """ramp=TR: u = h A sin(w tau), h = (1 - cos(pi tau / TR)) / 2 (computed here); u and u'
    are 0 at t0 (no velocity jump) and the plain sine from t0 + TR on."""
    amp, hz, tr, t0 = 0.01, 37.21, 0.05, 0.02
    w = 2 * math.pi * hz
    table = motion_table([f"node=25,dof=1,amp={amp},hz={hz},t0={t0},ramp={tr},phase=30"], IDS)
    t = np.linspace(0.0, 0.2, 400001)
    u, v, a = (c[:, 0] for c in motion_history(t, table))
    tau = t - t0
    h = np.where(tau < 0, 0.0, np.where(tau < tr, 0.5 * (1 - np.cos(np.pi * tau / tr)), 1.0))
    np.testing.assert_allclose(u, h * amp * np.sin(w * tau + math.pi / 6), rtol=0, atol=1e-15)
    assert u[t < t0].max() == 0.0 and v[t < t0].max() == 0.0
    # u and u' continuous everywhere (central differences of u match u' across t0 and
    # t0 + TR); u'' is continuous but at those two instants, where h'' jumps by pi^2/(2 TR^2)
    dt = t[1] - t[0]
    du = (u[2:] - u[:-2]) / (2 * dt)
    dv = (v[2:] - v[:-2]) / (2 * dt)
    np.testing.assert_allclose(du, v[1:-1], rtol=0, atol=2e-4 * amp * w)
    inner = (np.abs(t[1:-1] - t0) > 2 * dt) & (np.abs(t[1:-1] - t0 - tr) > 2 * dt)
    np.testing.assert_allclose(dv[inner], a[1:-1][inner], rtol=0, atol=5e-4 * amp * w * w)
    with pytest.raises(UsrfrcError, match="ramp="):
        motion_table(["node=25,dof=1,amp=1,hz=3,ramp=-1"], IDS)
