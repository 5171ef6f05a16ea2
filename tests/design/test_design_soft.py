"""Softer contacts in a design (``stiffness_scale``, issue 21 item 4; docs/design.md): every
modulus of the particles scaled by f, the step by f^(-2/5) (x3dpd.api.soft_step, the rule
``x3dpd study --stiffness-scale`` uses), and the contact then lasts f^(-2/5) longer, as Hertz's
closed form says."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import x3dpd
from x3dpd.design.configs import make_configurations
from x3dpd.design.design_file import read_design
from x3dpd.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
IMPACT = ROOT / "decks" / "impact_wall.inp"


def hertz_contact_time(e, v=62.832, r=0.0625, nu=0.33, rho=0.0007329707329707328):
    """Hertz (report 7.2.2): a sphere on a rigid wall, K = 4/3 E/(1 - nu^2) sqrt(R), a_max =
    (5 m v^2 / (4 K))^(2/5), t_c = 2.9432 a_max / v (Timoshenko & Goodier) [s]. Defaults:
    decks/impact_wall.inp's sphere (Figure 28)."""
    m = rho * 4 / 3 * math.pi * r**3
    k = 4 / 3 * e / (1 - nu**2) * math.sqrt(r)
    return 2.9432 * (5 * m * v * v / (4 * k)) ** 0.4 / v


def _design(tmp_path: Path, structure: Path, scales: str) -> Path:
    path = tmp_path / "soft.toml"
    path.write_text(
        f'structure = "{structure}"\n[fill]\ndt = 1e-9\n[vary]\n'
        f'stiffness_scale = {scales}\n[evaluate]\nkind = "ringdown"\n'
    )
    return path


def test_a_softer_configuration_lasts_f_to_the_minus_2_5_longer_as_hertz_says(tmp_path):
    full, soft = make_configurations(read_design(_design(tmp_path, IMPACT, "[1, 0.01]")))
    f = 0.01
    p0, p1 = full.deck.pdmp[0], soft.deck.pdmp[0]
    assert (p1.e0, p1.e1, p1.t1) == (p0.e0 * f, p0.e1 * f, p0.t1)
    assert full.values["dt"] == 1e-9
    assert soft.values["dt"] == pytest.approx(1e-9 * f**-0.4, rel=1e-12)
    assert (full.values["stiffness_scale"], soft.values["stiffness_scale"]) == (1.0, f)
    times = {}
    for m in (full, soft):
        scale = m.values["stiffness_scale"]
        path = tmp_path / f"{m.config.name}.inp"
        path.write_text(m.text)
        t_c = hertz_contact_time(3e7 * scale)
        res = x3dpd.run(path, tmax=1.2 * t_c, itrac=1)
        touching = np.asarray(res.energy["contact_energy"]) > 0.0
        times[scale] = touching.sum() * m.values["dt"]
        # ~7,550 steps per contact in both (the step scales with t_c): a step in 7,550 (1.3e-4)
        # plus the 2.9432 constant's 4 digits, inside 1e-3
        assert times[scale] == pytest.approx(t_c, rel=1e-3)
    assert times[f] / times[1.0] == pytest.approx(f**-0.4, rel=1e-3)


def test_a_bad_stiffness_scale_is_refused_at_its_line(tmp_path):
    with pytest.raises(
        InputError,
        match=r"soft.toml:5: vary.stiffness_scale: expected a scale "
        r"in \(0, 1\]",
    ):
        read_design(_design(tmp_path, IMPACT, "[1, 2]"))
    with pytest.raises(InputError, match=r"vary.stiffness_scale: expected a value > 0"):
        read_design(_design(tmp_path, IMPACT, "[0]"))
    # a HOOKE law's stiffness is its own card's, not the particles' moduli
    spec = _design(tmp_path, ROOT / "decks" / "hooke_wall.inp", "[0.1]")
    with pytest.raises(InputError, match=r"configuration Ex0.1: stiffness_scale .*HOOKE"):
        make_configurations(read_design(spec))
