"""Rolling resistance (x3dpd.physics.epsd, FRICTION card ROLL epsd): a steel sphere rolling
without slip on a flat floor under gravity decelerates at the closed-form rate.

Rigid-body mechanics: the constant torque mu_r R m g opposes the rolling; with the contact
sticking (friction F at the contact point), m dv/dt = F and I dw/dt = -F R - mu_r R m g with
v = w R give (m + I/R^2) dv/dt = -mu_r m g, i.e. dv/dt = -5/7 mu_r g for a solid sphere
(I = 2/5 m R^2). The sphere starts on the floor at the Hertz static overlap (as in
test_friction.py), so the normal force is m g throughout.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest


import reference as ref
from factories import STEEL_E, STEEL_NU, STEEL_R, G, floor_deck, sphere_mass

import x3dpd
from x3dpd.api.traces import ENERGY_COLUMNS
from x3dpd.deck.cards import Friction

M = sphere_mass()
K = ref.hertz_k(STEEL_E / (1 - STEEL_NU**2), STEEL_R)
DELTA = (M * G / K) ** (2.0 / 3.0)
#: 50 steps per period of the resting contact's vertical vibration (as test_friction.py)
DT = 2 * math.pi / math.sqrt(1.5 * K * math.sqrt(DELTA) / M) / 50
MU_R = 0.01
V0 = 1.0


@pytest.mark.parametrize("law", ["regularized", "mindlin"])
def test_a_rolling_sphere_decelerates_at_five_sevenths_mu_r_g(law):
    deck = floor_deck(
        dt=DT,
        height=STEEL_R - DELTA,
        velocity=(V0, 0.0, 0.0),
        omega=(0.0, 0.0, -V0 / STEEL_R),
        gravity=G,
        mu=0.3,
        spectator=False,
    )
    deck = dataclasses.replace(deck, friction=(Friction(4, law, 0.3, 0.3, "epsd", MU_R),))
    t_end = 0.05
    res = x3dpd.run(deck, tmax=t_end)
    t = res.trace.time
    v = res.trace.velocity[:, 0, 0]
    w = res.trace.spin[:, 0, 2]
    slope, _ = np.polyfit(t[t > 0.005], v[t > 0.005], 1)
    expected = -5.0 / 7.0 * MU_R * G
    print(f"\n{law}: dv/dt = {slope:.6f} in/s^2, closed form {expected:.6f}")
    assert slope == pytest.approx(expected, rel=1e-3)
    # it rolls: the contact point's slip stays far below the speed
    assert np.abs(v + w * STEEL_R).max() < 1e-4 * V0
    # the ledger books the rolling loss in its own column: the torque's work mu_r R m g times
    # the angle rolled, i.e. mu_r m g times the distance, to 1e-3; it is the kinetic energy
    # lost (friction's column stays at the rolling contact's tiny slip), and the ledger closes
    e = res.energy
    ke = e["kinetic_translation"] + e["kinetic_rotation"]
    distance = res.trace.position[-1, 0, 0] - res.trace.position[0, 0, 0]
    rolled = e["dissipated_rolling"]
    assert rolled[-1] == pytest.approx(MU_R * M * G * distance, rel=1e-3)
    assert rolled[-1] == pytest.approx(ke[0] - ke[-1], rel=1e-3)
    assert abs(e["dissipated_friction"][-1]) < 1e-3 * rolled[-1]
    assert np.abs(e["residual"]).max() < 1e-6 * ke[0]


def test_the_rolling_column_is_there_only_with_a_rolling_law():
    """A scene without a rolling law keeps the ledger's twelve columns (its energy files and
    goldens are unchanged); with one, ``dissipated_rolling`` follows ``residual``."""
    deck = floor_deck(
        dt=DT,
        height=STEEL_R - DELTA,
        velocity=(V0, 0.0, 0.0),
        omega=(0.0, 0.0, -V0 / STEEL_R),
        gravity=G,
        mu=0.3,
        spectator=False,
    )
    plain = x3dpd.run(deck, tmax=20 * DT)
    assert plain.energy.columns == ENERGY_COLUMNS
    rolling = dataclasses.replace(
        deck, friction=(Friction(4, "regularized", 0.3, 0.3, "epsd", MU_R),)
    )
    res = x3dpd.run(rolling, tmax=20 * DT)
    assert res.energy.columns == (*ENERGY_COLUMNS, "dissipated_rolling")
