"""The Section 11 MIP decks (decks/mip_*.inp, tools/make_mip_decks.py) against the report's
numbers, computed here from the report's text: the apparatus's and the engine's modes, the
spheres' count and weight (Section 11.4: 16.5 lb of 0.5 in spheres, 9.2 lb of 0.25 in), the
measured plates' free lengths; and a short run of each whose energy ledger closes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import x3dpd
from x3dpd.api.structures import linear_sdof
from x3dpd.deck import read_deck
from x3dpd.model.build import build_model

DECKS = Path(__file__).resolve().parents[1] / "decks"
G = 386.1


@pytest.mark.parametrize(
    "name,diameter,spheres,pounds,thickness",
    [
        ("mip_apparatus_05.inp", 0.5, 884, 16.5, (0.501, 0.5015, 0.502, 0.503)),
        ("mip_apparatus_025.inp", 0.25, 3952, 9.2, (0.250, 0.251, 0.251, 0.252)),
    ],
)
def test_the_apparatus_is_section_11_3s(name, diameter, spheres, pounds, thickness):
    model = build_model(read_deck(DECKS / name))
    sdof = linear_sdof(model, 1, 2, ignore_particles=True)
    # 350 lb, 6.25e5 lbf/in: 132 Hz; zeta 0.047 at the low level (Sec. 11.3, Table 6)
    assert sdof.m * G == pytest.approx(350.0, rel=1e-12)
    assert sdof.k == 6.25e5
    assert math.sqrt(sdof.k / sdof.m) / (2 * math.pi) == pytest.approx(132.0, abs=0.5)
    assert sdof.c / (2 * math.sqrt(sdof.k * sdof.m)) == pytest.approx(0.047, rel=1e-12)
    # four plates of 221 (988) holes, one sphere each: the report's weight within 2 %
    assert model.n_particles == spheres
    assert np.all(model.radius == 0.5 * diameter)
    assert float(np.sum(model.mass[model.particle_start :])) * G == pytest.approx(pounds, rel=0.02)
    # free lengths: measured thickness + 0.009 in shim - diameter (Sec. 11.3-11.4)
    lengths = sorted(float(p[0]) for p in np.diff(model.x0[model.shape_nodes][:, :, 1], axis=1))
    assert lengths == pytest.approx(sorted(t + 0.009 for t in thickness), abs=1e-12)


def test_the_engine_is_section_11_2s():
    deck = read_deck(DECKS / "mip_engine.inp")
    model = build_model(deck)
    sdof = linear_sdof(model, 1, 2, ignore_particles=True)
    assert sdof.m * G == pytest.approx(600.0, rel=1e-12)
    assert math.sqrt(sdof.k / sdof.m) / (2 * math.pi) == pytest.approx(146.0, rel=1e-12)
    assert sdof.c / (2 * math.sqrt(sdof.k * sdof.m)) == pytest.approx(0.067, rel=1e-12)
    # the stall: forces that give the mode alone 0.4 and 3.0 ips rms at resonance, F = v c
    (spec,) = deck.usrfrc[0].specs
    fields = dict(kv.split("=") for kv in spec.split(":", 1)[1].split(","))
    for key, ips in (("amp", 0.4), ("amp1", 3.0)):
        assert float(fields[key]) == pytest.approx(ips * math.sqrt(2) * sdof.c, abs=0.05)
    assert float(fields["ramp"]) == 5.0 and float(fields["hz"]) == 146.0


@pytest.mark.parametrize("name", ["mip_apparatus_05.inp", "mip_engine.inp"])
def test_a_short_run_closes_its_ledger(name):
    res = x3dpd.run(DECKS / name, tmax=0.004, itrac=400)
    assert res.summary["status"] == "complete"
    assert abs(res.summary["relative_residual"]) < 1e-10
    assert res.energy["dissipated_viscoelastic"][-1] > 0.0  # the spheres' impacts
