"""Gravity as an effect unit compiled into every loop (x3dpd.physics.gravity, ``runtime``).

Closed forms computed here: a sphere released at rest under g falls y(t) = y0 - g t^2 / 2 with
v(t) = -g t -- velocity Verlet integrates a constant acceleration exactly, so the only error is
rounding (~1e-16 per step over 2000 steps: 1e-12 of the fall is a 10^4-fold margin); the
ledger's U_grav is -sum m g . (x - x0) over the final state's nodes, and the ledger balances.
Without the BODY card the same scene compiles the same loop, U_grav stays 0 and the sphere stays
put. The registry refuses a unit that is both flagged and runtime.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import x3dpd
from factories import BOX_LOOP, floor_deck
from x3dpd.model.build import build_model
from x3dpd.physics import effect_units, gravity
from x3dpd.physics.effect_unit import EffectUnit
from x3dpd.solver.simulation import Simulation
from x3dpd.solver.unit_slots import units_source
from x3dpd.solver.variants import Variant

#: the report's decks' g [in/s^2]
G = 386.1
DT = 1e-5
TMAX = 0.02
Y0 = 0.5  # the sphere's start height [in], well above the floor (it lands at t ~ 0.048 s)


def _fall(g: float):
    deck = floor_deck(dt=DT, height=Y0, velocity=(0.0, 0.0, 0.0), gravity=g)
    return deck, x3dpd.run(deck, tmax=TMAX)


@pytest.mark.rides(BOX_LOOP)
def test_a_released_sphere_falls_as_the_closed_form_and_the_ledger_books_its_potential():
    deck, res = _fall(G)
    t = res.trace.times
    y = res.trace.position[:, 0, 1]
    vy = res.trace.velocity[:, 0, 1]
    assert t[-1] == pytest.approx(TMAX)
    fall = 0.5 * G * t**2
    np.testing.assert_allclose(Y0 - y, fall, rtol=0.0, atol=1e-12 * fall[-1])
    np.testing.assert_allclose(vy, -G * t, rtol=0.0, atol=1e-12 * G * TMAX)
    # U_grav = -sum m g . (x - x0), g = (0, -G, 0), over every node (the spectator sphere
    # settling on the floor too), from the final state
    model = res.model
    x = res.final_state.state.x
    u_expected = float(np.sum(model.mass * G * (x[:, 1] - model.x0[:, 1])))
    u_grav = res.energy["gravity_potential"]
    assert u_grav[-1] == pytest.approx(u_expected, rel=1e-12)
    # the faller's share dominates: m g^2 t^2 / 2 lost to kinetic energy
    m = model.mass[model.particle_start]
    assert u_grav[-1] == pytest.approx(-0.5 * m * (G * TMAX) ** 2, rel=1e-3)
    assert res.summary["relative_residual"] < 1e-9


@pytest.mark.rides(BOX_LOOP)
def test_without_the_body_card_the_same_loop_runs_and_nothing_falls():
    deck, res = _fall(0.0)
    assert deck.body is None
    assert np.all(res.energy["gravity_potential"] == 0.0)
    assert np.all(res.trace.position[:, 0, 1] == Y0)
    with_g = floor_deck(dt=DT, height=Y0, velocity=(0.0, 0.0, 0.0), gravity=G)
    loops = {Simulation(build_model(d)).variant.label() for d in (deck, with_g)}
    assert loops == {BOX_LOOP}


def test_gravity_is_compiled_into_every_loop_without_a_variant_flag():
    unit = effect_units.BY_UNIT_NAME["gravity"]
    assert unit.runtime and unit.flag == ""
    assert "gravity" not in {f.name for f in dataclasses.fields(Variant)}
    assert effect_units.units_of(Variant()) == (unit,)
    source = units_source(Variant(springs=True))
    assert "from x3dpd.physics.gravity import Gravity as _UNIT_1_BUNDLE" in source
    assert "shadow += _UNIT_1_ENERGY(units[1], nodes, en)" in source


def test_the_registry_refuses_a_unit_both_flagged_and_runtime():
    class Module:
        __name__ = "x3dpd.physics.fake_gravity"
        energy_hook = gravity.energy_hook

    for changes in ({"flag": "gravity"}, {"runtime": False}):
        Module.UNIT = EffectUnit(**{**gravity.UNIT.__dict__, **changes})
        with pytest.raises(ValueError, match="a flag or is compiled into every loop"):
            effect_units._register(Module)
