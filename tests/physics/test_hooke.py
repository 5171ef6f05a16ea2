"""The hooke normal law (x3dpd.physics.hooke) against its closed form, run by the solver.

A sphere hits a rigid flat wall head-on (decks/hooke_wall.inp). The law is a linear
spring-dashpot, F = k_n a + c_n da/dt, not clamped at zero, so the contact is half a period of a
damped oscillator: it lasts pi/omega_d and the sphere leaves at e times its impact speed.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from x3dpd.deck import parse_deck, read_deck
from x3dpd.errors import DeckError
from x3dpd.model.build import build_model
from x3dpd.physics.hooke import damping_ratio, hooke_impact
from x3dpd.solver.simulation import Simulation

DECK = Path(__file__).resolve().parents[2] / "decks" / "hooke_wall.inp"


def _crossing(t, a, k):
    """Time where ``a`` crosses zero between samples k-1 and k (linear interpolation)."""
    return t[k - 1] + (t[k] - t[k - 1]) * a[k - 1] / (a[k - 1] - a[k])


def test_sphere_on_wall_matches_the_closed_form():
    deck = read_deck(DECK)
    model = build_model(deck)
    assert model.normal_law == "hooke"
    sim = Simulation(model, itrac=1)
    first = sim.snapshot()
    block = sim.advance(int(round((model.tmax - model.t0) / sim.dt)))
    t = np.r_[first.times, block.times]
    x = np.r_[first.data[:, -1, 0], block.data[:, -1, 0]]
    vx = np.r_[first.data[:, -1, 3], block.data[:, -1, 3]]
    r = model.radius[-1]
    a = r - x  # approach on the wall x = 0
    on = np.flatnonzero(a > 0.0)
    assert on.size and on[-1] < a.size - 1, "the sphere must touch and leave the wall"
    t_in = _crossing(t, a, on[0])
    t_out = _crossing(t, a, on[-1] + 1)
    rec = deck.hooke[0]
    m = model.mass[-1]
    v0 = abs(model.v0[-1, 0])
    tc_want, v_out_want = hooke_impact(m, rec.kn, rec.e, v0)
    # the closed form from the formulas themselves (zeta from e, omega_d from k/m)
    zeta = -math.log(rec.e) / math.sqrt(math.pi**2 + math.log(rec.e) ** 2)
    assert damping_ratio(rec.e) == pytest.approx(zeta, rel=1e-15)
    assert tc_want == pytest.approx(math.pi / (math.sqrt(rec.kn / m) * math.sqrt(1 - zeta**2)))
    # contact time: the zero crossings are interpolated between steps of dt = 1e-8 s (0.04 % of
    # t_c; the interpolation error is far smaller); the dashpot reads the half-step velocity, a
    # lag of dt/2 that shifts t_c by O(zeta omega dt) ~ 1e-4: 1e-3 covers both
    assert t_out - t_in == pytest.approx(tc_want, rel=1e-3)
    # rebound speed: the same O(zeta omega dt) lag of the damping; 1e-3 of e v
    assert vx[-1] == pytest.approx(v_out_want, rel=1e-3)
    # the force is not clamped: near the end the dashpot pulls (negative acceleration toward
    # the wall while the sphere leaves, i.e. dv/dt < 0 on the last contact steps)
    assert vx[on[-1]] < vx[on[-1] - 5]
    # energy: the ledger's viscous dissipation is the kinetic energy lost
    e_lost = 0.5 * m * (v0**2 - vx[-1] ** 2)
    d_visc = block.energy[-1, 6]
    assert d_visc == pytest.approx(e_lost, rel=1e-3)


def _deck_text(hooke_lines: str) -> str:
    text = DECK.read_text()
    start = text.index("\nHOOKE\n") + 1
    end = text.index("END", start) + 3
    return text[:start] + hooke_lines + text[end:]


@pytest.mark.parametrize(
    "card, message",
    [
        ("HOOKE\n 7 1e4 0.8\nEND", "NODLIM 7 names no PDMP group"),
        ("HOOKE\n 8 1e4 1.5\nEND", "E (coefficient of restitution) must be in (0, 1]"),
        ("HOOKE\n 8 -1 0.8\nEND", "KN (normal stiffness) must be > 0"),
        ("HOOKE\n 8 1e4\nEND", "HOOKE needs 3 values"),
    ],
)
def test_bad_hooke_cards_are_deck_errors(card, message):
    with pytest.raises(DeckError, match=message.replace("(", r"\(").replace(")", r"\)")) as err:
        build_model(parse_deck(_deck_text(card), "deck.inp"))
    assert err.value.card == "HOOKE"


def test_a_deck_without_hooke_runs_the_report_law():
    text = _deck_text("")
    model = build_model(parse_deck(text, "deck.inp"))
    assert model.normal_law == "lee_radok" and model.law_params is None
