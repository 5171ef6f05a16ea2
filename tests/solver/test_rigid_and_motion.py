"""Solver-level runs of rigid-master rotation and prescribed motion against closed forms.

Everything goes through the public Simulation interface and the traced positions.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.deck.cards import (
    Boundary,
    Deck,
    Element,
    Initial,
    Mass,
    Material,
    Node,
    Rbel,
    Trace,
    Usrfrc,
)
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation

from factories import parameters

I_PERP, I_AXIS = 2.0, 5.0  # body inertias of the master [mass length^2]


def _rigid_deck(*, dt, fixed_rot=(), moment=None, omega0=(0.0, 0.0, 0.0)) -> Deck:
    """A rigid body: master node 1 (mass 1, inertias I_PERP, I_PERP, I_AXIS) at the origin and
    massless slaves 2, 3 at unit distance along x and y; translations fixed."""
    return Deck(
        path="<rigid>",
        parameters=parameters(dt, 1),
        trace=Trace((1, 2, 3)),
        nodes=(Node(1, 0.0, 0.0, 0.0), Node(2, 1.0, 0.0, 0.0), Node(3, 0.0, 1.0, 0.0)),
        masses=(Mass(1, 1.0, I_PERP, I_PERP, I_AXIS),),
        rbels=(Rbel(1, (1, 2, 3, 4, 5, 6), (2, 3)),),
        boundaries=(Boundary(1, 1, 1, (1, 2, 3, *fixed_rot)),),
        initials=(Initial(1, (0.0, 0.0, 0.0, *omega0)),),
        usrfrc=(Usrfrc((moment,)),) if moment else (),
    )


def _run(model, steps, **kw):
    sim = Simulation(model, **kw)
    first = sim.snapshot()
    block = sim.advance(steps)
    t = np.r_[first.times, block.times]
    data = np.concatenate([first.data, block.data])
    return t, data


def test_constant_moment_turns_the_body_as_theta_equals_half_alpha_t2():
    """M about z from rest: theta = M t^2 / (2 I_zz). Velocity Verlet integrates a constant
    angular acceleration exactly, so only rounding remains."""
    dt, moment, steps = 1e-4, 0.3, 5000
    model = build_model(
        _rigid_deck(dt=dt, fixed_rot=(4, 5), moment=f"constant:node=1,dof=6,amp={moment!r}")
    )
    assert "rigid_rotation" in model.effects
    t, data = _run(model, steps)
    theta = 0.5 * moment / I_AXIS * t**2
    # slave 2 (started on +x) goes round the unit circle; 1e-12: rounding of ~5000 rotations
    np.testing.assert_allclose(data[:, 1, 0], np.cos(theta), atol=1e-12)
    np.testing.assert_allclose(data[:, 1, 1], np.sin(theta), atol=1e-12)
    np.testing.assert_allclose(data[:, 0, 8], moment / I_AXIS * t, rtol=1e-12, atol=1e-15)


def _top(dt: float, t_end: float = 0.4, w_perp: float = 0.5, w_axis: float = 3.0):
    """Free symmetric top: (t, body-frame spin, space-frame angular momentum, axis lengths)."""
    # a zero moment: torque-free, and the step loop the constant-moment test compiles
    zero = "constant:node=1,dof=6,amp=0.0"
    model = build_model(_rigid_deck(dt=dt, omega0=(w_perp, 0.0, w_axis), moment=zero))
    t, data = _run(model, int(round(t_end / dt)))
    ex = data[:, 1, :3] - data[:, 0, :3]
    ey = data[:, 2, :3] - data[:, 0, :3]
    rot = np.stack([ex, ey, np.cross(ex, ey)], axis=2)  # body axes in space, as columns
    body = np.einsum("tji,tj->ti", rot, data[:, 0, 6:9])  # R^T omega
    ang_mom = np.einsum("tij,tj->ti", rot, body * [I_PERP, I_PERP, I_AXIS])
    return t, body, ang_mom, np.linalg.norm(ex, axis=1)


def _top_error(dt: float) -> float:
    w_perp, w_axis = 0.5, 3.0
    t, body, _, _ = _top(dt, w_perp=w_perp, w_axis=w_axis)
    lam = (I_AXIS - I_PERP) / I_PERP * w_axis
    return float(np.abs(body[:, 0] - w_perp * np.cos(lam * t)).max())


def test_torque_free_symmetric_top_precesses_at_the_euler_rate():
    """Free rotation of a symmetric body (I1 = I2 = I_PERP, I3 = I_AXIS): in the body frame the
    perpendicular spin turns at lambda = (I3 - I1)/I1 omega_3 (Euler's equations), omega_3 and
    the space-frame angular momentum stay constant."""
    dt, w_perp, w_axis = 2e-5, 0.5, 3.0
    t, body, ang_mom, length = _top(dt, w_perp=w_perp, w_axis=w_axis)
    lam = (I_AXIS - I_PERP) / I_PERP * w_axis
    # second-order integrator (implicit gyroscopic term in the second half kick): the phase
    # error grows as ~ (|omega| dt)^2 |omega| t = (6.1e-5)^2 * 1.2 = 4.5e-9 rad, times
    # w_perp = 2.2e-9; 1e-8 bounds it (the first-order kick this replaced was off by 6e-6, a
    # wrong inertia or a frame mix-up by far more)
    np.testing.assert_allclose(body[:, 0], w_perp * np.cos(lam * t), atol=1e-8)
    np.testing.assert_allclose(body[:, 1], w_perp * np.sin(lam * t), atol=1e-8)
    np.testing.assert_allclose(body[:, 2], w_axis, atol=1e-9)
    # |L| ~ 15: the same relative error, 15 * 4.5e-9 = 7e-8
    np.testing.assert_allclose(ang_mom, ang_mom[:1].repeat(len(t), axis=0), atol=1e-7)
    np.testing.assert_allclose(length, 1.0, atol=1e-12)  # the slaves stay rigid


def test_rigid_rotation_converges_at_second_order():
    """Halving the step quarters the error of a second-order integrator (an explicit gyroscopic
    term in both half kicks only halves it: first order)."""
    assert _top_error(4e-5) / _top_error(2e-5) > 3.5


@pytest.mark.parametrize("hz", [3.0, 11.0])
def test_mass_on_a_spring_driven_by_a_prescribed_base(hz):
    """Node 1 moves as u = A sin(w t) (--motion); node 2 (mass m) hangs on a spring k to it and
    starts at rest: x = A wn^2/(wn^2 - w^2) (sin w t - (w/wn) sin wn t) (undamped)."""
    m, k, amp, dt = 2.0e-3, 20.0, 0.01, 1e-5
    wn = math.sqrt(k / m)  # 100 rad/s = 15.9 Hz
    deck = Deck(
        path="<base>",
        parameters=parameters(dt, 1),
        materials=(Material(1, 1, 0.0, 1.0, k, 0.0, 0.0, 0.0),),
        trace=Trace((1, 2)),
        nodes=(Node(1, 0.0, 0.0, 0.0), Node(2, 1.0, 0.0, 0.0)),
        elements=(Element(1, 1, (1, 2)),),
        masses=(Mass(2, m, 1.0, 1.0, 1.0),),
        boundaries=(Boundary(1, 1, 1, (2, 3, 4, 5, 6)), Boundary(2, 2, 1, (2, 3, 4, 5, 6))),
    )
    motion = [f"node=1,dof=1,amp={amp!r},hz={hz!r}"]
    model = build_model(deck, motion=motion)
    t, data = _run(model, 20000, motion=motion)
    w = 2 * math.pi * hz
    np.testing.assert_allclose(data[:, 0, 0], amp * np.sin(w * t), atol=1e-15)
    want = amp * wn**2 / (wn**2 - w**2) * (np.sin(w * t) - (w / wn) * np.sin(wn * t))
    # velocity Verlet: phase error (wn dt)^2/24 per radian, over wn t = 20 rad ~ 1e-6 of the
    # amplitude (~1e-2): 1e-7 absolute
    np.testing.assert_allclose(data[:, 1, 0] - 1.0, want, atol=1e-7)
