"""Which configuration a design calls best (x3dpd.design.design_table.mark_best): only one
whose every point converged, within the mass budget, and whose score's 95 % interval clears
the runner-up's; otherwise "no significant difference" (issue 30 item 2, issue 33 item 15)."""

from __future__ import annotations

import math

import pytest

from x3dpd.design.design_table import mark_best, noise_db


def _rows(config, peak, ci, *, converged=True, added_mass=1e-6, drives=(1.0,)):
    """A configuration's sweep rows: at each drive a peak point of amplitude ``peak`` (its
    half-width ``ci``) and a lower point, the undamped baseline's peak at 1, so the peak
    attenuation is -20 log10(peak) dB."""
    out = []
    for drive in drives:
        for amp, hw in ((peak, ci), (0.5 * peak, ci)):
            out.append(
                {
                    "config": config,
                    "drive": drive,
                    "amplitude": amp,
                    "amplitude_ci": hw,
                    "peak_amplitude": peak,
                    "peak_attenuation_undamped_db": -20.0 * math.log10(peak),
                    "peak_attenuation_added_mass_db": math.nan,
                    "converged": converged,
                    "added_mass": added_mass,
                }
            )
    return out


def _best(rows, tol=0.01, budget=None):
    mark_best(rows, budget, "sweep", tol)
    return {r["config"] for r in rows if r["best"]}, {r["config"]: r["verdict"] for r in rows}


def test_a_clear_winner_is_best():
    rows = _rows("a", 0.5, 0.005) + _rows("b", 0.7, 0.005)
    best, verdict = _best(rows)
    assert best == {"a"} and verdict["a"] == "best" and verdict["b"] == ""
    a = next(r for r in rows if r["config"] == "a")
    # the score's half-width from the peak point: 20/ln 10 x 0.005/0.5 dB
    assert a["score_ci"] == pytest.approx(20 / math.log(10) * 0.01)


def test_overlapping_intervals_are_no_significant_difference():
    """6.02 dB against 5.85 dB, each +/- 0.17 dB: the intervals overlap."""
    rows = _rows("a", 0.50, 0.01) + _rows("b", 0.51, 0.01)
    best, verdict = _best(rows)
    assert best == set()
    assert verdict["a"] == "no significant difference from b"
    assert verdict["b"] == "no significant difference from a"


def test_numerical_noise_between_exact_answers_is_no_difference():
    """A bare structure and a sphere that never touches a wall: both deterministic (zero
    half-width), 0.01 dB apart -- below what points computed to 1 % resolve (0.086 dB)."""
    assert noise_db(0.01) == pytest.approx(0.0864, abs=1e-4)
    rows = _rows("bare", 1.0, 0.0) + _rows("sphere", 10 ** (-0.01 / 20), 0.0)
    best, verdict = _best(rows)
    assert best == set() and verdict["sphere"].startswith("no significant difference")


def test_a_configuration_with_an_unconverged_point_is_never_best():
    rows = _rows("a", 0.2, 0.001, converged=False) + _rows("b", 0.7, 0.001)
    best, _ = _best(rows)
    assert best == {"b"}


def test_nothing_is_best_when_every_point_ended_at_the_cap():
    rows = _rows("a", 0.2, math.inf, converged=False) + _rows("b", 0.7, math.inf, converged=False)
    best, verdict = _best(rows)
    assert best == set() and set(verdict.values()) == {""}


def test_the_mass_budget_still_rules():
    rows = _rows("heavy", 0.2, 0.001, added_mass=2e-6) + _rows("light", 0.7, 0.001)
    best, _ = _best(rows, budget=1e-6)
    assert best == {"light"}
