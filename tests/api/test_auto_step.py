"""``x3dpd.run(dt="auto")``: the step chosen by accuracy through the run path.

It must reproduce a fine fixed step within the error it claims, see a contact coming (enter a
wall no deeper than a fine fixed step does), keep the energy ledger exact across step changes,
keep the output times of a fixed DTMAX run, and continue from a saved state or a restart dump
bit for bit. The deck's DTMIN < DTMAX makes it the default.

Claimed error: 50 steps per contact, for which velocity Verlet's peak-force error is at most
1.35 % (10/50)^2 = 0.054 % (x3dpd.model.timestep.peak_force_error, re-measured in
tests/model/test_model_timestep.py); restitution and the largest approach err less.
"""

from __future__ import annotations

import json
import math
import pickle
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from factories import (
    BOX_LOOP,
    BOX_VISCO_LOOP,
    FIG30_E0,
    FIG30_E1,
    FIG30_TAU1,
    STEEL_E,
    STEEL_NU,
    floor_deck,
    sdof_deck,
    sphere_mass,
)

import x3dpd
from x3dpd.deck.cards import Usrfrc
from x3dpd.errors import InputError, UnstableRunError
from x3dpd.model.timestep import peak_force_error

R, V, T = 0.03125, 62.8, 8e-5
DTMAX = 2e-6
CLAIM = peak_force_error(50) / 100  # 5.4e-4
VISCO = dict(e0=FIG30_E0, e1=FIG30_E1, tau1=FIG30_TAU1, radius=R)


def lee_radok(dtmin=1e-10, **material):
    """A 0.03125 in sphere 0.003 in above a wall, flying at it at 62.8 in/s (Lee & Radok's
    viscoelastic material: a ~3.8 us contact), a second sphere resting on the floor; DTMAX
    2e-6 s, DTMIN 1e-10 s."""
    deck = floor_deck(dt=DTMAX, height=R + 0.003, velocity=(0.0, -V, 0.0), **(material or VISCO))
    return replace(deck, parameters=replace(deck.parameters, dtmin=dtmin, tmax=T))


@pytest.mark.rides(BOX_VISCO_LOOP)
def test_the_lee_radok_wall_impact_gets_its_restitution_right():
    auto = x3dpd.run(lee_radok())  # DTMIN < DTMAX: auto by default
    assert auto.summary["step"]["mode"] == "auto"
    fine = x3dpd.run(lee_radok(), dt=1e-9, itrac=2000)
    e_auto = auto.trace.velocity[-1, 0, 1] / V
    e_fine = fine.trace.velocity[-1, 0, 1] / V
    assert 0.5 < e_fine < 1.0  # a viscoelastic rebound
    assert e_auto == pytest.approx(e_fine, rel=CLAIM)
    # the same deck at its fixed DTMAX cannot follow a 3.8 us contact: a diagnosed stop
    with pytest.raises(UnstableRunError):
        x3dpd.run(lee_radok(), dt=DTMAX, itrac=1)
    # the steps used: the contact step (<= t_c/50 at twice the speed), never below DTMIN
    st = auto.summary["step"]
    assert 1e-10 <= st["min"] <= 3.8e-6 / 50 and st["max"] <= DTMAX
    assert st["mean"] == pytest.approx(T / auto.summary["steps"])


def hertz_approach(radius, v, e=STEEL_E, nu=STEEL_NU):
    """Largest approach of an elastic sphere hitting a rigid wall: a = (5 m v^2 / 4 K)^(2/5),
    K = 4/3 E/(1-nu^2) sqrt(R) (x3dpd.physics.hertz)."""
    k = 4.0 / 3.0 * e / (1.0 - nu * nu) * math.sqrt(radius)
    return (5.0 * sphere_mass(radius) * v * v / (4.0 * k)) ** 0.4


@pytest.mark.rides(BOX_LOOP)
def test_it_sees_the_wall_coming_no_deeper_than_a_fine_step_and_rebounds_elastically():
    """An elastic sphere (contact 3.4 us) at DTMAX 2e-6 s. The run stops when an approach
    exceeds ``penetration_limit`` x R, checked every step: with the limit at the closed-form
    Hertz approach + 0.1 % (at 50 steps per contact the largest approach errs by 2/3 of the
    peak force's 0.054 %), the fine fixed step and the auto step pass; the fixed DTMAX (1.9
    steps per contact) is a diagnosed stop."""
    limit = hertz_approach(R, V) * 1.001 / R
    deck = lee_radok(radius=R)
    fine = x3dpd.run(deck, dt=1e-9, itrac=2000, penetration_limit=limit)
    auto = x3dpd.run(deck, penetration_limit=limit)
    # elastic: the rebound speed is the approach speed (closed form), within the claim
    for res in (fine, auto):
        assert res.trace.velocity[-1, 0, 1] == pytest.approx(V, rel=CLAIM)
    with pytest.raises(UnstableRunError):
        x3dpd.run(deck, dt=DTMAX, itrac=1, penetration_limit=limit)


def spring_under_load():
    """A spring (omega = 10 rad/s) under a constant load from rest, DTMAX = 0.1 s, DTMIN 1e-3 s:
    the structure asks for 0.2 x 2/omega = 0.04 s, so the run switches to DTMAX/4 at t = 0,
    where the load's force makes the Verlet term S = dt^2/8 F^2/m jump by 6 % of the energy
    scale."""
    deck = replace(
        sdof_deck(dt=0.1, hz=1.0, mass=1.0, k=100.0, c=0.0, drive=0.0, itrac=1),
        usrfrc=(Usrfrc(("constant:node=1,dof=1,amp=5.0",)),),
    )
    return replace(deck, parameters=replace(deck.parameters, dtmin=1e-3, tmax=5.0))


def test_the_ledger_stays_exact_and_output_times_are_those_of_a_fixed_dtmax_run():
    """For a linear system the ledger balances to round-off, before and after the switch."""
    res = x3dpd.run(spring_under_load())
    assert res.summary["step"]["min"] == res.summary["step"]["max"] == 0.025
    e = res.energy.data
    assert np.max(np.abs(e[:, 11])) < 1e-12 * np.max(np.abs(e[:, 1:11]))
    times = res.trace.time
    assert np.array_equal(times, np.arange(times.size) * 0.1)  # t0 + n DTMAX, exactly
    # the static deflection F/k = 0.05 is the mean of the undamped oscillation 0 .. 2F/k
    x = res.trace.position[:, 0, 0] - res.trace.position[0, 0, 0]
    assert 0.0 <= x.min() and x.max() <= 0.1 * (1 + 1e-3)


@pytest.mark.rides(BOX_VISCO_LOOP)
def test_a_continued_run_repeats_the_uninterrupted_one_bit_for_bit():
    whole = x3dpd.run(lee_radok())
    half = x3dpd.run(lee_radok(), tmax=T / 2)
    state = pickle.loads(pickle.dumps(half.final_state))
    rest = x3dpd.run(lee_radok(), initial_state=state)
    assert np.array_equal(np.concatenate([half.trace.data, rest.trace.data]), whole.trace.data)
    assert np.array_equal(np.concatenate([half.energy.data, rest.energy.data]), whole.energy.data)
    with pytest.raises(InputError, match="chosen by accuracy"):
        x3dpd.run(lee_radok(), dt=DTMAX, initial_state=state)


@pytest.mark.rides(BOX_VISCO_LOOP)
def test_stopped_then_restarted_writes_the_same_bytes(tmp_path):
    """Stopped through ``stop=`` in the middle (a dump at the driver's level), resumed with
    ``restart=True``: the trace and the energy file equal the uninterrupted run's."""
    deck = lee_radok()
    x3dpd.run(deck, trace=tmp_path / "whole.trace.txt")
    part = tmp_path / "part.trace.txt"
    first = x3dpd.run(deck, trace=part, stop=lambda chunk: chunk.time[-1] >= T / 3)
    assert first.summary["status"] == "stopped" and first.summary["t_end"] < T
    x3dpd.run(deck, trace=part, restart=True)
    for name in ("trace.txt", "energy.csv"):
        assert (tmp_path / f"part.{name}").read_bytes() == (tmp_path / f"whole.{name}").read_bytes()
    side = json.loads((tmp_path / "part.trace.txt.json").read_text())
    assert side["dt"] == "auto" and side["step"]["max"] <= DTMAX
    # the dump is refused by a fixed-step run
    with pytest.raises(InputError, match="the step"):
        x3dpd.run(deck, dt=DTMAX, trace=part, restart=True, overwrite=True)


def test_bad_step_words_are_refused():
    with pytest.raises(InputError, match="'auto'"):
        x3dpd.run(lee_radok(), dt="fast")


def test_no_shipped_deck_changes_behaviour():
    """Every shipped deck has DTMIN = DTMAX, so its runs keep the fixed step DTMAX."""
    from x3dpd.api.stepping import wants_auto

    decks = sorted((Path(__file__).resolve().parents[2] / "decks").glob("*.inp"))
    assert decks
    for path in decks:
        assert not wants_auto(None, x3dpd.load_deck(path).parameters), path.name


def test_a_hooke_contact_is_resolved_by_its_own_half_period():
    """decks/hooke_wall.inp (linear spring-dashpot, k_n = 1e4 lbf/in, e = 0.8, 10 in/s) with
    DTMAX raised to 1e-6 s: the step is chosen from the law's own contact time, half a damped
    period (x3dpd.physics.hooke.contact_time; 0.25 % above the undamped half period
    pi sqrt(m/k_n) checked here), not from a Hertz contact, 50 steps per contact, and the
    sphere leaves at e x 10 in/s (closed form) within 5e-3: the dashpot force is evaluated
    from the half-step
    velocity, a first-order error of order zeta omega dt = 0.071 x pi/50 = 4.5e-3 (central
    differences add (omega dt)^2/24 = 1.6e-4); the Hertz time of a steel sphere (~7 us) would
    ask for a step 4x finer than the half period does."""
    deck = x3dpd.load_deck(Path(__file__).resolve().parents[2] / "decks" / "hooke_wall.inp")
    deck = replace(deck, parameters=replace(deck.parameters, dtmin=1e-10, dtmax=1e-6))
    res = x3dpd.run(deck)
    m = res.model.mass[res.model.particle_start]
    half = math.pi * math.sqrt(m / 1.0e4)
    st = res.summary["step"]
    assert half / 100 < st["min"] <= half / 50 and st["max"] == 1e-6
    assert abs(res.trace.velocity[-1, -1, 0]) == pytest.approx(8.0, rel=5e-3)
