"""``x3dpd design``: a linear design against its closed form, Dask against serial, resuming after
an interruption, and design files that are wrong at a line (nothing run)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests/: shared helpers
from factories import TABLE4_C, TABLE4_DRIVE, TABLE4_K, TABLE4_MASS, sdof_deck  # noqa: E402

from x3dpd.api import check
from x3dpd.deck.writer import write_deck
from x3dpd.design.explore import run_design
from x3dpd.design.sweep import read_csv
from x3dpd.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
BEAM_1 = ROOT / "decks" / "beam_1.inp"


def write(tmp_path: Path, text: str, name: str = "design.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_a_linear_design_reproduces_the_closed_form_frf_in_every_configuration(tmp_path):
    # the Table 4 structure without particles, at two time steps: both configurations are
    # the linear SDOF m x'' + c x' + k x = F sin(w t), X = F / |k - m w^2 + i c w|
    write_deck(sdof_deck(dt=1e-5, hz=37.0), tmp_path / "sdof.inp")
    spec = write(tmp_path, """
structure = "sdof.inp"
[fill]
count = 0
[vary]
dt = [1e-5, 2e-5]
[evaluate]
kind = "sweep"
node = 1
dof = 1
drives = [4.84040e-3]
frequencies = [36.0, 37.5, 39.0]
baselines = ["undamped"]
tol = 1e-3
""")
    rows = run_design(spec, tmp_path / "out", workers=1, echo=lambda s: None)
    assert sorted({r["config"] for r in rows}) == ["dt1e-05", "dt2e-05"]
    assert len(rows) == 6
    for r in rows:
        w = 2 * math.pi * r["frequency_hz"]
        exact = TABLE4_DRIVE / math.hypot(TABLE4_K - TABLE4_MASS * w * w, TABLE4_C * w)
        assert r["converged"] and r["count"] == 0 and r["added_mass"] == 0.0
        # tolerance: the criterion's 1e-3 plus the integrator's phase error (w dt)^2 / 24 =
        # 9e-7 at dt = 2e-5 s, amplified near resonance by 1 / (2 zeta) = 160: 2e-3 in all
        assert r["amplitude"] == pytest.approx(exact, rel=2e-3)
        assert r["baseline_undamped"] == pytest.approx(exact, rel=1e-12)   # closed form
        assert abs(r["attenuation_undamped_db"]) < 20 * math.log10(1 + 2e-3)
        # the ledger: all the drive's work goes to the dashpot, pi c w X^2 per cycle
        assert r["dissipated_dampers_per_cycle"] == pytest.approx(
            math.pi * TABLE4_C * w * exact ** 2, rel=5e-3)
        assert r["dissipated_friction_per_cycle"] == r["dissipated_viscoelastic_per_cycle"] == 0
    for name in ("dt1e-05", "dt2e-05"):   # each configuration's deck runs on its own
        deck = tmp_path / "out" / "configs" / name / f"{name}.inp"
        assert check(deck).exit_status == 0
        assert (tmp_path / "out" / "configs" / name / "sweep" / "sweep.csv").exists()
    assert len(read_csv(tmp_path / "out" / "design.csv")) == 6
    assert (tmp_path / "out" / "design_attenuation.png").exists()


TWO_BY_TWO = f"""
title = "2 x 2"
structure = "{BEAM_1}"
[fill]
count = 1
gap_fraction = 0.05
jitter = 0.5
[vary]
radius = [0.1, 0.125]
seed = [1, 2]
[evaluate]
kind = "sweep"
drives = [9.68080e-3]
frequencies = [37.0]
window = 2
max_cycles = 6
"""


def test_a_two_by_two_design_on_dask_equals_the_serial_run_bit_for_bit(tmp_path):
    spec = write(tmp_path, TWO_BY_TWO)
    serial = run_design(spec, tmp_path / "serial", workers=1, echo=lambda s: None)
    parallel = run_design(spec, tmp_path / "dask", workers=2, echo=lambda s: None)
    assert len(serial) == 4 and len({r["config"] for r in serial}) == 4
    assert ((tmp_path / "serial" / "design.csv").read_text()
            == (tmp_path / "dask" / "design.csv").read_text())
    assert {r["radius"] for r in serial} == {0.1, 0.125}


def test_an_interrupted_design_resumes_and_computes_only_what_is_missing(tmp_path):
    spec = write(tmp_path, TWO_BY_TWO)
    lines = []

    def stop_after_two(line):
        lines.append(line)
        if line.startswith("  [2/4 points"):
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_design(spec, tmp_path / "out", workers=1, echo=stop_after_two)
    assert not (tmp_path / "out" / "design.csv").exists()
    again = []
    rows = run_design(spec, tmp_path / "out", workers=1, echo=again.append)
    assert "(2 stored before)" in again[0]
    assert [x.split(", ETA")[0] for x in again if x.startswith("  [")] == [
        "  [3/4 points, 3/4 configurations", "  [4/4 points, 4/4 configurations"]
    straight = run_design(spec, tmp_path / "straight", workers=1, echo=lambda s: None)
    assert ((tmp_path / "out" / "design.csv").read_text()
            == (tmp_path / "straight" / "design.csv").read_text())
    assert len(rows) == 4


BAD = {
    "unknown key": ("[fill]\ncount = 1\nradious = 0.1\n", 6, "unknown key 'radious'"),
    "no values": ("[vary]\nradius = []\n", 5, "a design variable with no values"),
    "cannot fit": ("[[configuration]]\nname = \"big\"\ncount = 500\nradius = 0.05\n", 4,
                   "a fill that cannot fit"),
    "bad toml": ("[fill\ncount = 1\n", 4, "not a TOML file"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_malformed_design_file_is_refused_at_its_line_with_nothing_run(tmp_path, case):
    body, line, words = BAD[case]
    spec = write(tmp_path, f'title = "bad"\nstructure = "{BEAM_1}"\n\n' + body
                 + '\n[evaluate]\nkind = "sweep"\ndrives = [1e-3]\nfrequencies = [37.0]\n')
    with pytest.raises(InputError) as err:
        run_design(spec, tmp_path / "out", workers=1, echo=lambda s: None)
    assert str(err.value).startswith(f"{spec}:{line}")
    assert words in str(err.value)
    assert not (tmp_path / "out").exists()


def test_a_material_not_in_the_library_is_refused_at_its_line(tmp_path):
    pytest.importorskip("x3dpd.materials")
    spec = write(tmp_path, f'structure = "{BEAM_1}"\n[vary]\nmaterial = ["steel-beam",\n'
                 '  "unobtainium"]\n[evaluate]\nkind = "sweep"\ndrives = [1e-3]\n'
                 'frequencies = [37.0]\n')
    with pytest.raises(InputError) as err:
        run_design(spec, tmp_path / "out", workers=1, echo=lambda s: None)
    assert str(err.value).startswith(f"{spec}:3")
    assert "unobtainium" in str(err.value)
    assert not (tmp_path / "out").exists()


def test_a_deck_named_code_file_runs_only_when_the_design_says_so(tmp_path):
    deck = tmp_path / "coded.inp"
    deck.write_text(BEAM_1.read_text().replace(
        "USRFRC\n", "USRFRC\n   force.py\n", 1))
    (tmp_path / "force.py").write_text("def usrfrc(time, coords, vels, force):\n    pass\n")
    text = (f'structure = "coded.inp"\n[evaluate]\nkind = "sweep"\ndrives = [1e-3]\n'
            'frequencies = [37.0]\nwindow = 2\nmax_cycles = 6\n')
    with pytest.raises(InputError, match="usrfrc_code = true"):
        run_design(write(tmp_path, text), tmp_path / "out", workers=1, echo=lambda s: None)
    assert not (tmp_path / "out").exists()
