"""The shipped modal decks against the closed forms they were built from.

* decks/beam_64_modal.inp: its three modes are a uniform Euler-Bernoulli cantilever's
  (frequency ratios (beta_n L)^2, tip values 2/sqrt(mu L), tip slopes) and its coupled first
  mode is Table 4's SDOF (frequency sqrt(k/m), tip mass m).
* decks/chassis_128.inp: its modes are a simply supported plate's (1,1), (2,1), (3,1) and its
  coupled first mode is Table 5's SDOF.
* A restart of the modal beam continues bit for bit.

Every expected number is computed here from the formulas (the beam's roots from
cos x cosh x = -1; the report's Table 4 and 5 values typed in).
"""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest
from scipy.optimize import brentq

import x3dpd
from x3dpd.model.build import build_model

DECKS = pathlib.Path(__file__).resolve().parents[2] / "decks"
#: Report Sec. 8.1: aluminium beam 12 x 1.5 x 0.175 in; density 0.0975 lbf/in^3 / 386.1.
L, B, H, RHO = 12.0, 1.5, 0.175, 0.0975 / 386.1
#: Table 4 (as the beam decks use it: the equivalent mass with the cavity, decks/README.md).
T4_M, T4_K, T4_C = 2.04213e-4, 1.14823e1, 3.08293e-4
#: Table 5.
T5_M, T5_K, T5_C = 3.54282e-4, 1.95442e2, 3.55e-3


def _modal(name):
    deck = x3dpd.load_deck(str(DECKS / name))
    return deck, build_model(deck)


def test_beam_modes_are_euler_bernoulli_cantilever_modes():
    deck, model = _modal("beam_64_modal.inp")
    card = deck.modal
    roots = [
        brentq(
            lambda x: math.cos(x) * math.cosh(x) + 1.0,
            (k - 0.5) * math.pi - 1,
            (k - 0.5) * math.pi + 1,
        )
        for k in (1, 2, 3)
    ]
    freq = np.array([m.freq for m in card.modes])
    assert freq[1:] / freq[0] == pytest.approx([(r / roots[0]) ** 2 for r in roots[1:]], rel=1e-8)
    tip = {s.dof: np.array(s.values) for s in card.shapes if s.node == 9}
    mu = RHO * B * H
    assert tip[1] == pytest.approx([2 / math.sqrt(mu * L)] * 3, rel=1e-8)
    for k, x in enumerate(roots):
        sigma = (math.cosh(x) + math.cos(x)) / (math.sinh(x) + math.sin(x))
        value = math.cosh(x) - math.cos(x) - sigma * (math.sinh(x) - math.sin(x))
        slope = x / L * (math.sinh(x) + math.sin(x) - sigma * (math.cosh(x) - math.cos(x)))
        # the beam runs along y and bends in x: rz = -dphi/dy
        assert tip[6][k] == pytest.approx(-tip[1][k] * slope / value, rel=1e-8)
    # the modulus the frequencies imply: f1 = roots[0]^2 / (2 pi L^2) sqrt(E I / mu)
    e_eff = (2 * math.pi * freq[0] * L**2 / roots[0] ** 2) ** 2 * mu / (B * H**3 / 12)
    assert 0.9 < e_eff / 10.0e6 < 1.0  # aluminium, tuned down a few per cent


def test_beam_first_coupled_mode_is_table_4s_sdof():
    _, model = _modal("beam_64_modal.inp")
    ms = model.modal
    assert ms.omega[0] == pytest.approx(math.sqrt(T4_K / T4_M), rel=1e-7)
    j = int(np.flatnonzero(ms.nodes == model.index_of(9))[0])
    assert 1.0 / ms.shape[j, 0, 0] ** 2 == pytest.approx(T4_M, rel=1e-7)
    assert ms.zeta[0] == pytest.approx(T4_C / (2 * math.sqrt(T4_K * T4_M)), rel=1e-3)


def test_chassis_modes_are_plate_modes_and_the_first_is_table_5s_sdof():
    deck, model = _modal("chassis_128.inp")
    a, b = 17.0, 8.0
    freq = np.array([m.freq for m in deck.modal.modes])
    ratio = [
        ((m / a) ** 2 + (n / b) ** 2) / ((1 / a) ** 2 + (1 / b) ** 2)
        for m, n in ((1, 1), (2, 1), (3, 1))
    ]
    assert freq / freq[0] == pytest.approx(ratio, rel=1e-8)
    shapes = {(s.node, s.dof): np.array(s.values) for s in deck.modal.shapes}
    amp = shapes[(9, 1)][0]
    # panel centre (y' = a/2, z' = b/2) and the stinger 3.425 in above the bottom, centred
    for k, m in enumerate((1, 2, 3)):
        assert shapes[(9, 1)][k] == pytest.approx(amp * math.sin(m * math.pi / 2), abs=1e-9)
        assert shapes[(10, 1)][k] == pytest.approx(
            amp * math.sin(m * math.pi * 3.425 / a), rel=1e-8
        )
    ms = model.modal
    assert ms.omega[0] == pytest.approx(math.sqrt(T5_K / T5_M), rel=1e-7)
    j = int(np.flatnonzero(ms.nodes == model.index_of(9))[0])
    assert 1.0 / ms.shape[j, 0, 0] ** 2 == pytest.approx(T5_M, rel=1e-7)


def test_restart_of_the_modal_beam_is_bit_identical(tmp_path):
    """10 ms straight, and 5 ms then a restart to 10 ms: the same trace bytes (the modal
    coordinates, rates and forces are part of the dump)."""
    deck = str(DECKS / "beam_64_modal.inp")
    whole = x3dpd.run(deck, tmax=0.01, trace=tmp_path / "whole.trace.txt")
    x3dpd.run(deck, tmax=0.005, trace=tmp_path / "part.trace.txt")
    x3dpd.run(deck, tmax=0.01, trace=tmp_path / "part.trace.txt", restart=True)
    assert whole.summary["steps"] == 20000
    assert (tmp_path / "whole.trace.txt").read_bytes() == (tmp_path / "part.trace.txt").read_bytes()


def test_the_ledger_closes_on_the_modal_beam_with_its_particles():
    """0.3 s of decks/beam_64_modal.inp at the report's step (the spheres fall, settle and are
    shaken; the cavity turns with the tip's slope): the residual stays below 1e-3 of the energy
    scale (the SDOF beam_64 gets 5.0e-4 over the same time)."""
    res = x3dpd.run(str(DECKS / "beam_64_modal.inp"), tmax=0.3)
    scale = res.summary["energy_scale"]
    assert np.abs(res.energy["residual"]).max() < 1e-3 * scale
    assert res.energy["dissipated_friction"][-1] > 0.0  # the particles did work
