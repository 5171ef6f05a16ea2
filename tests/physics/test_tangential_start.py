"""A contact that exists at t0 starts from the tangential history it has
(x3dpd.solver.simulation.Simulation.compute_forces: the force evaluation at t0, which velocity
Verlet needs, runs the tangential law at a zero step and commits no history).

The scene: a steel sphere resting on a HOOKE floor under gravity (static approach m g / k_n),
its contact point slipping at u0 = 1e-3 in/s at t0. It sticks (the spring's largest force
k_t u0 / w is 0.48 of mu m g), so the contact point is an oscillator of the spring
k_t = 2(1-nu)/(2-nu) k_n on the tangential mass m_t (1/m_t = 1/m + R^2/I), with the dashpot
c_t = 2 zeta sqrt(m k_t) under e < 1. Velocity Verlet integrates it as
xi_{n+1} = xi_n + v_{n+1/2} dt, F = -k_t xi - c_t v (v the half-step velocity, the full-step
one at t0), which undamped has the closed form v_n = u0 cos(n theta),
cos(theta) = 1 - (w dt)^2 / 2 (x_n = u0 dt sin(n theta)/sin(theta) solves the recurrence
x_{n+1} = 2 x_n - x_{n-1} - (w dt)^2 x_n from x_0 = 0, x_1 = u0 dt). The t0 evaluation used to
add u0 dt to the history, and the first step added it again: the oscillation started a step
late (errors 6 % and 30 % of u0 at 100 and 20 steps per period).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from factories import HOOKE_PLANE_LOOP, STEEL_NU, STEEL_R, floor_deck, sphere_mass

import x3dpd
from x3dpd.deck.cards import Hooke

M = sphere_mass()
INERTIA = 0.4 * M * STEEL_R**2
M_T = 1.0 / (1.0 / M + STEEL_R**2 / INERTIA)  # the contact point's tangential mass
KN = 1.0e4  # HOOKE k_n [lbf/in]
KT = 2.0 * (1.0 - STEEL_NU) / (2.0 - STEEL_NU) * KN
OMEGA = math.sqrt(KT / M_T)
PERIOD = 2.0 * math.pi / OMEGA
G = 386.1
MU = 0.3
U0 = 1.0e-3  # slip speed at t0 [in/s]
LAWS = ["linear_history", "mindlin"]
#: a HOOKE floor without the spectator: the Chung & Ooi decks' loops of these laws
pytestmark = pytest.mark.rides(*(HOOKE_PLANE_LOOP[law] for law in LAWS))


def _deck(e: float, steps_per_period: int):
    deck = floor_deck(
        dt=PERIOD / steps_per_period,
        height=STEEL_R - M * G / KN,
        velocity=(U0, 0.0, 0.0),
        gravity=G,
        mu=MU,
        spectator=False,
    )
    return dataclasses.replace(deck, hooke=(Hooke(deck.pdmp[0].nodlim, KN, e),))


def _slip(law: str, e: float, steps_per_period: int):
    """Step numbers and the contact point's slip v_x + w_z R at every step over two periods."""
    deck = _deck(e, steps_per_period)
    res = x3dpd.run(deck, tmax=2.0 * PERIOD, friction=law)
    slip = res.trace.velocity[:, 0, 0] + res.trace.spin[:, 0, 2] * STEEL_R
    return np.rint(res.trace.time / deck.parameters.dtmax), slip


def _verlet(e: float, steps_per_period: int, n: int) -> np.ndarray:
    """The slow reference: velocity Verlet on the contact point's oscillator with the
    tangential laws' sticking rules (module docstring), from xi = 0, v = u0: v at steps 0..n."""
    le = math.log(e)
    zeta = -le / math.sqrt(math.pi**2 + le * le)
    ct = 2.0 * zeta * math.sqrt(M * KT)
    dt = PERIOD / steps_per_period
    xi, v = 0.0, U0
    f = -ct * v  # at t0: the spring as it is, the dashpot on the full-step velocity
    out = [v]
    for _ in range(n):
        v += 0.5 * dt * f / M_T
        xi += v * dt
        f = -KT * xi - ct * v
        v += 0.5 * dt * f / M_T
        out.append(v)
    return np.array(out)


@pytest.mark.parametrize("steps", [100, 20])
@pytest.mark.parametrize("law", LAWS)
def test_an_undamped_sticking_contact_starts_from_its_history(law, steps):
    """Velocity Verlet's closed form v_n = u0 cos(n theta) to 1e-9 u0 (round-off; measured
    3e-14) at 100 and 20 steps per period; so the continuous oscillator u0 cos(w t) within
    Verlet's phase error, n (theta - w dt) (2.1e-3 and 5.2e-2 after two periods; measured
    1.8e-3 and 4.6e-2)."""
    n, slip = _slip(law, 1.0, steps)
    dt = PERIOD / steps
    theta = math.acos(1.0 - 0.5 * (OMEGA * dt) ** 2)
    scheme = np.abs(slip - U0 * np.cos(n * theta)).max() / U0
    continuous = np.abs(slip - U0 * np.cos(OMEGA * n * dt)).max() / U0
    print(
        f"\n{law} {steps} steps/period: {scheme:.1e} of u0 from the scheme's closed form, "
        f"{continuous:.1e} from the oscillator's"
    )
    assert scheme <= 1e-9
    assert continuous <= n.max() * (theta - OMEGA * dt) + 1e-9


@pytest.mark.parametrize("steps", [100, 20])
@pytest.mark.parametrize("law", LAWS)
def test_a_damped_sticking_contact_starts_from_its_history(law, steps):
    """HOOKE e 0.5: the slow reference's velocities to 1e-9 u0 at 100 and 20 steps per period
    (the dashpot acts at t0 on the full-step velocity, then on the half-step ones)."""
    n, slip = _slip(law, 0.5, steps)
    reference = _verlet(0.5, steps, int(n.max()))[n.astype(int)]
    assert np.abs(slip - reference).max() <= 1e-9 * U0


@pytest.mark.parametrize("law", LAWS)
def test_a_restart_mid_oscillation_does_not_advance_the_history(law, tmp_path):
    """Stopped after 37 steps of the damped oscillation and restarted (the state's forces and
    history come from the dump; no force evaluation): the same trace bytes as straight
    through."""
    deck = _deck(0.5, 100)
    whole, part = tmp_path / "whole.trace.txt", tmp_path / "part.trace.txt"
    x3dpd.run(deck, tmax=PERIOD, friction=law, trace=whole)
    x3dpd.run(deck, tmax=37 * PERIOD / 100, friction=law, trace=part)
    x3dpd.run(deck, tmax=PERIOD, friction=law, trace=part, restart=True)
    assert whole.read_bytes() == part.read_bytes()
