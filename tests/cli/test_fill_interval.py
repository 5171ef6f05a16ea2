"""``x3dpd fill``'s time step keeps the template's trace interval exactly: a periodic random
drive's period, a whole number of the template's output intervals, stays a whole number of
samples of the filled deck's trace (``x3dpd frf``'s leakage-free lines)."""

from __future__ import annotations

import re

import pytest
from cli_helpers import DECKS, run_cli

import x3dpd
from x3dpd.api.deck_step import interval_step
from x3dpd.deck import read_deck
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model
from x3dpd.model.timestep import recommended_time_step


def test_the_filled_deck_traces_at_the_templates_interval(tmp_path, capsys):
    """beam_64 traced every 100 steps of 5e-7 s (5e-5 s, 160000 samples in an 8 s period)
    filled with 20 spheres of R = 0.02 in: the recommended step (about 6.1e-8 s) once became
    ITRAC round(5e-5 / step) and an interval off 5e-5 (213 x 2.35e-7 = 5.0055e-5 s for the
    issue's spheres); now the step divides 5e-5 s exactly."""
    text = (DECKS / "beam_64.inp").read_text()
    text = re.sub(r"(?m)^(   0\.0 \S+ \S+ 5e-07 5e-07 0 \S+ 0 5 0) 2000$", r"\1 100", text)
    template = tmp_path / "tpl.inp"
    template.write_text(text)
    assert read_deck(template).parameters.itrac == 100
    out = tmp_path / "out.inp"
    args = ("fill", template, "--n", 20, "--radius", 0.02, "--gap", 0.002, "-o", out)
    assert run_cli(*args) == 0
    printed = capsys.readouterr().out
    deck = read_deck(out)
    par = deck.parameters
    assert par.itrac * par.dtmax == pytest.approx(5e-5, rel=1e-14, abs=0)
    assert 8.0 / (par.itrac * par.dtmax) == pytest.approx(160000, rel=1e-12, abs=0)
    rec = recommended_time_step(build_model(deck)).dt_recommended
    assert 0.99 * rec <= par.dtmax <= rec
    assert f"ITRAC {par.itrac} keeps the trace every 5e-05 s" in printed
    assert not check_model(build_model(deck)).warnings


def test_the_step_is_floored_when_the_interval_holds_few_steps():
    """An interval of 2.5 recommended steps: dividing it exactly (3 steps) would cost 17 % of
    the step; the step is floored to 3 digits and the interval rounded instead."""
    assert interval_step(2.0e-7, 5e-5) == (5e-5 / 250, 250)
    assert interval_step(2.3456789e-7, 5.864e-7) == (2.34e-7, 3)


def test_a_given_step_is_kept_as_given():
    deck = read_deck(DECKS / "beam_64.inp")
    fitted = x3dpd.fit_time_step(deck, dt=3e-8)
    assert fitted.dt == 3e-8 and fitted.itrac == round(1e-3 / 3e-8)
