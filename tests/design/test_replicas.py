"""Replicas of a sweep point pooled into one answer (x3dpd.design.replicas; issue 30 item 4):
the pooling's closed form, the replicas' starts, and a sweep whose replicas run on Dask
workers and pool into the same bytes as serially."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from x3dpd.deck.parser import read_deck
from x3dpd.design.replicas import JITTER, jittered, pool
from x3dpd.design.spec import SweepSpec
from x3dpd.design.steady_state import Criterion
from x3dpd.design.sweep import deck_hash, run_sweep

BEAM_1 = Path(__file__).resolve().parents[2] / "decks" / "beam_1.inp"


def test_pooling_weights_each_replica_by_its_interval():
    """Two estimates 1.00 +/- 0.02 and 1.03 +/- 0.04 (95 %): weights 1/sigma^2 in the ratio
    4:1, mean 1.006, half-width 1.96 (1/s1^2 + 1/s2^2)^(-1/2) = 0.0179 -- times sqrt(chi^2) =
    1.32, since they disagree by more than their intervals allow (chi^2 = 1.73 > R - 1 = 1)."""
    s1, s2 = 0.02 / 1.96, 0.04 / 1.96
    w1, w2 = 1 / s1**2, 1 / s2**2
    mean = (w1 * 1.00 + w2 * 1.03) / (w1 + w2)
    chi2 = w1 * (1.00 - mean) ** 2 + w2 * (1.03 - mean) ** 2
    hw = 1.96 * (w1 + w2) ** -0.5 * math.sqrt(max(chi2, 1.0))
    assert pool([1.00, 1.03], [0.02, 0.04]) == pytest.approx((mean, hw), rel=1e-12)


def test_replicas_that_agree_within_their_intervals_shrink_it_by_sqrt_r():
    m, h = pool([1.0, 1.001, 0.999, 1.0], [0.01] * 4)
    assert m == pytest.approx(1.0, abs=1e-12) and h == pytest.approx(0.005, rel=1e-12)


def test_replicas_without_their_own_interval_pool_by_their_spread():
    """Zero half-widths (periodic motions) or none (replicas stopped as long enough to pool):
    the plain mean, the half-width t_{0.975, R-1} s / sqrt(R) from the replicas' spread."""
    from scipy.stats import t

    assert pool([2.0, 2.0], [0.0, 0.0]) == (2.0, 0.0)
    m, h = pool([2.0, 2.2], [0.0, 0.0])
    assert m == pytest.approx(2.1) and h == pytest.approx(t.ppf(0.975, 1) * 0.1414213562 / 2**0.5)
    values = [1.0, 1.1, 0.95, 1.02]
    m, h = pool(values, [math.inf, 0.01, math.inf, 0.02])
    s = float(np.std(values, ddof=1))
    assert m == pytest.approx(np.mean(values)) and h == pytest.approx(t.ppf(0.975, 3) * s / 2)


def test_a_replica_starts_its_particles_a_hair_apart():
    deck = read_deck(BEAM_1)
    assert jittered(deck, 0) is deck
    other = jittered(deck, 3)
    nodlim = deck.pdmp[0].nodlim
    radius = deck.pdmp[0].rzero
    moved = 0
    for a, b in zip(deck.nodes, other.nodes):
        d = np.abs([a.x - b.x, a.y - b.y, a.z - b.z])
        if a.nid > nodlim:
            assert np.all(d <= JITTER * radius) and d.max() > 0
            moved += 1
        else:
            assert d.max() == 0.0
    assert moved == 1
    assert jittered(deck, 3) == other  # seeded


def _spec(replicas: int) -> SweepSpec:
    return SweepSpec(
        deck=read_deck(BEAM_1),
        deck_text_hash=deck_hash(BEAM_1),
        frequencies=(37.0,),
        drives=(9.68080e-3,),
        node=9,
        dof=1,
        criterion=Criterion(window=3, max_cycles=12, replicas=replicas),
    )


def test_a_points_replicas_pool_into_one_row_on_dask_as_serially(tmp_path):
    serial = run_sweep(_spec(3), tmp_path / "serial", workers=1)
    (row,) = [r for r in serial if r["config"] == "deck"]
    assert row["replicas"] == 3
    stored = [
        json.loads(p.read_text()) for p in sorted((tmp_path / "serial" / "points").glob("*.json"))
    ]
    assert sorted(r["replica"] for r in stored) == [0, 1, 2]
    assert row["cycles"] == sum(r["cycles"] for r in stored)
    expected = pool([r["amplitude"] for r in stored], [r["amplitude_ci"] for r in stored])
    assert (row["amplitude"], row["amplitude_ci"]) == expected
    done = all(r["converged"] for r in stored)
    assert row["converged"] == (done and expected[1] <= 0.01 * expected[0])
    parallel = run_sweep(_spec(3), tmp_path / "dask", workers=2)
    for a, b in zip(serial, parallel):
        for k in set(a) - {"wall_s", "compile_s"}:
            assert a[k] == b[k] or (a[k] != a[k] and b[k] != b[k]), k  # NaN equals NaN
