"""The predicted start of a sweep point (x3dpd/design/predict.py): the structure put on its
expected steady-state motion, the particles carried along, the energy booked."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from factories import TABLE4_C, TABLE4_DRIVE, TABLE4_K, TABLE4_MASS, sdof_deck

from x3dpd.api import run_config
from x3dpd.deck.parser import read_deck
from x3dpd.design.predict import predicted_start
from x3dpd.design.steady_state import Criterion, SweepPoint, run_point
from x3dpd.model.build import build_model

DECKS = Path(__file__).resolve().parents[2] / "decks"


def exact(hz: float) -> complex:
    """m x'' + c x' + k x = F sin(w t): X = F / (k - m w^2 + i c w) (phase -arg of the
    denominator)."""
    w = 2 * math.pi * hz
    return TABLE4_DRIVE / complex(TABLE4_K - TABLE4_MASS * w * w, -TABLE4_C * w)


@pytest.mark.parametrize("predict", [True, False])
def test_a_linear_structure_starts_on_its_steady_state(predict):
    deck = sdof_deck(dt=1e-5, hz=37.0)
    # no Prony extrapolation: the start alone decides how long the transient lasts (from rest
    # 460 cycles: the drift must die over the run's last two thirds, not only between windows)
    crit = Criterion(tol=1e-3, predict=predict, extrapolate=False, max_cycles=600)
    point = SweepPoint("deck", deck, 38.0, TABLE4_DRIVE, 1, 1, criterion=crit)
    row, state = run_point(point)
    x = exact(38.0)
    assert row["converged"]
    assert row["amplitude"] == pytest.approx(abs(x), rel=2e-3)
    least = crit.min_windows * crit.window
    if predict:
        # already on the closed form: the criterion's minimum, 3 windows of 5 cycles (+1 for a
        # window boundary falling between samples)
        assert row["start"] == "predicted"
        assert row["cycles"] <= least + 1
        # the next point of a chain, from the previous one's state, is predicted as well
        nxt = SweepPoint("deck", deck, 37.0, TABLE4_DRIVE, 1, 1, direction="down", criterion=crit)
        row2, _ = run_point(nxt, (row, state))
        assert row2["start"] == "predicted"
        assert row2["cycles"] <= least + 1
        assert row2["amplitude"] == pytest.approx(abs(exact(37.0)), rel=2e-3)
    else:
        # from rest the transient (tau = 2 m / c = 1.3 s, 50 cycles) must die out
        assert row["start"] == "deck"
        assert row["cycles"] > 2 * least


def test_the_particles_ride_along_and_the_energy_is_booked():
    deck = read_deck(DECKS / "beam_1.inp")
    point = SweepPoint("deck", deck, 36.0, 4.84040e-3, 9, 1)
    spec = f"sine:node=9,dof=1,amp={point.drive!r},hz=36.0,t0=0.0"
    start = predicted_start(point, None, run_config(deck, dt=5e-7, usrfrc=(spec,)), 0.0)
    model = build_model(deck)
    x0 = np.asarray(model.x0)
    state = start.state
    moved = state.x[:, 0] - x0[:, 0]
    i = model.index_of(9)
    # every node free along x moved by the same amount (cavity, master and the sphere)
    free = ~np.asarray(model.fixed[:, 0])
    assert np.allclose(moved[free], moved[i], rtol=0, atol=1e-15)
    assert np.all(moved[~free] == 0.0)
    assert np.all(state.x[:, 1:] == x0[:, 1:])
    # u = |X| sin(phi), u' = |X| w cos(phi) of the added-mass structure
    from x3dpd.design.predict import added_mass_response

    w = 2 * math.pi * 36.0
    x = added_mass_response(deck, 9, 1, point.drive, w)
    assert moved[i] == pytest.approx(abs(x) * math.sin(np.angle(x)), rel=1e-12)
    assert state.vel[i, 0] == pytest.approx(abs(x) * w * math.cos(np.angle(x)), rel=1e-12)
    assert np.all(state.vel[free, 0] == state.vel[i, 0])
    # the ledger's reference moved by the energy added: the spring's 1/2 k u^2 plus the
    # kinetic 1/2 M u'^2 of everything that moves (all start at rest)
    m_all = float(np.sum(np.asarray(model.mass)[free]))
    k = float(model.spring_k[0][0])
    added = 0.5 * k * moved[i] ** 2 + 0.5 * m_all * state.vel[i, 0] ** 2
    rest = predicted_start(
        SweepPoint("deck", deck, 36.0, 0.0, 9, 1),
        None,
        run_config(deck, dt=5e-7, usrfrc=(spec,)),
        0.0,
    ).state.e_ref
    assert state.e_ref - rest == pytest.approx(added, rel=1e-6)


def test_a_chain_builds_its_models_once(monkeypatch):
    # the points of a chain share one deck object: its model and its added-mass structure are
    # built at the first point, not again at every point (the run builds its own)
    import x3dpd.design.predict as predict

    built = []
    real = predict.build
    monkeypatch.setattr(predict, "build", lambda deck: built.append(deck) or real(deck))
    deck = read_deck(DECKS / "beam_1.inp")
    spec = "sine:node=9,dof=1,amp=4.8404e-3,hz=36.0,t0=0.0"
    config = run_config(deck, dt=5e-7, usrfrc=(spec,))
    starts = [
        predicted_start(SweepPoint("deck", deck, hz, 4.8404e-3, 9, 1), None, config, 0.0)
        for hz in (36.0, 37.0, 38.0)
    ]
    assert len(built) == 2  # the deck's model, the added-mass deck's model
    assert built[0] is deck and built[1] is not deck
    # a start computed from the cache is the one computed afresh
    predict._CACHE.clear()
    fresh = predicted_start(SweepPoint("deck", deck, 38.0, 4.8404e-3, 9, 1), None, config, 0.0)
    assert np.array_equal(fresh.state.x, starts[-1].state.x)
    assert np.array_equal(fresh.state.vel, starts[-1].state.vel)
    assert fresh.state.e_ref == starts[-1].state.e_ref
