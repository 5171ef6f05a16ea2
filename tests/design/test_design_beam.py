"""The shipped design files: designs/beam_count.toml makes the shipped beam decks and gives
``x3dpd sweep``'s numbers (the report's Section 8.3 study, once tools/study/beam_study.py);
designs/beam_size_fill.toml is well formed and its configurations fit."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from x3dpd.api import check, load_deck
from x3dpd.design.steady_state import Criterion
from x3dpd.design.commands import sweep_command
from x3dpd.design.configs import make_configurations
from x3dpd.design.design_file import read_design
from x3dpd.design.explore import run_design
from x3dpd.design.sweep import COLUMNS, read_csv

ROOT = Path(__file__).resolve().parents[2]
BEAM_COUNT = ROOT / "designs" / "beam_count.toml"
SIZE_FILL = ROOT / "designs" / "beam_size_fill.toml"


def _particles(deck):
    nodlim = deck.pdmp[0].nodlim
    return [(n.x, n.y, n.z) for n in deck.nodes if n.nid > nodlim]


def test_the_beam_count_design_makes_the_shipped_beam_decks():
    made = {m.config.name: m for m in make_configurations(read_design(BEAM_COUNT))}
    assert sorted(made) == ["beam_1", "beam_512", "beam_64"]
    for name, m in made.items():
        shipped = load_deck(ROOT / "decks" / f"{name}.inp")
        assert _particles(m.deck) == _particles(shipped)  # bit for bit
        fields = ("nodlim", "rzero", "prho", "ppoi", "e0", "e1", "t1", "pcof", "extra_terms")
        assert [getattr(m.deck.pdmp[0], f) for f in fields] == [
            getattr(shipped.pdmp[0], f) for f in fields
        ]
        assert m.deck.parameters.dtmax == shipped.parameters.dtmax
        assert [(x.nid, x.mass) for x in m.deck.masses] == [(x.nid, x.mass) for x in shipped.masses]
    # equal total particle mass, as the report's tests
    masses = [m.values["added_mass"] for m in made.values()]
    assert max(masses) == pytest.approx(min(masses), rel=1e-12)


def _reduced(tmp_path: Path) -> Path:
    """designs/beam_count.toml with beam_1 only, the 400 mV drive, two frequencies and a short
    cap."""
    text = BEAM_COUNT.read_text()
    head = text[: text.index("[[configuration]]")]
    head = head.replace('"../decks/beam_64.inp"', f'"{ROOT / "decks" / "beam_64.inp"}"')
    beam_1 = re.search(r"\[\[configuration\]\]\nname = \"beam_1\"\n(?:[^\[\n].*\n)*", text)
    evaluate = (
        '[evaluate]\nkind = "sweep"\ndrives = [9.68080e-3]\n'
        'frequencies = [37.0, 38.0]\ndirection = "down"\n'
        'baselines = ["undamped", "added-mass"]\ntol = 0.02\nwindow = 2\n'
        "max_cycles = 6\n"
    )
    path = tmp_path / "beam_count_reduced.toml"
    path.write_text(head + beam_1.group(0) + "\n" + evaluate)
    return path


def test_the_beam_count_design_gives_the_numbers_of_x3dpd_sweep_on_the_shipped_deck(tmp_path):
    # beam_study.py ran `x3dpd sweep decks/beam_N.inp` (sweep_command) with these settings; the
    # design must give the same points and the same numbers, bit for bit
    rows = run_design(_reduced(tmp_path), tmp_path / "design", workers=1, echo=lambda s: None)
    said = []
    sweep_command(
        str(ROOT / "decks" / "beam_1.inp"),
        freq="37,38",
        amps=["9.68080e-3"],
        direction="down",
        baselines=("undamped", "added-mass"),
        out=str(tmp_path / "sweep"),
        workers=1,
        echo=said.append,
        criterion=Criterion(tol=0.02, window=2, max_cycles=6),
    )
    by_design = read_csv(tmp_path / "design" / "configs" / "beam_1" / "sweep" / "sweep.csv")
    by_sweep = read_csv(tmp_path / "sweep" / "sweep.csv")
    # (the deck and its two baselines) x 2 frequencies
    assert len(by_design) == len(by_sweep) == 6
    for a, b in zip(by_design, by_sweep):
        for col in COLUMNS:
            if col not in ("wall_s", "compile_s"):
                assert a[col] == b[col] or (a[col] != a[col] and b[col] != b[col]), col
    # the report's rules of thumb ride along (x3dpd check's notes, under the sweep's drive)
    assert all("turn-on level" in r["notes"] or "to slide them" in r["notes"] for r in rows)
    assert all("(report Section" in r["notes"] for r in rows)
    deck_rows = [r for r in by_sweep if r["config"] == "deck"]
    assert [(r["drive"], r["frequency_hz"], r["amplitude"]) for r in rows] == [
        (r["drive"], r["frequency_hz"], r["amplitude"]) for r in deck_rows
    ]
    # the peak attenuations x3dpd sweep prints (beam_study.py's table) are design.csv's
    for line in said:
        hit = re.match(r"peak attenuation at drive (\S+): (\S+) dB vs (\S+)", line)
        if hit:
            drive, db, baseline = float(hit.group(1)), float(hit.group(2)), hit.group(3)
            col = f"peak_attenuation_{baseline.replace('-', '_')}_db"
            assert {round(r[col], 2) for r in rows if abs(r["drive"] - drive) < 1e-9} == {db}


def test_the_size_fill_design_is_well_formed_and_every_configuration_checks_clean():
    design = read_design(SIZE_FILL)
    made = make_configurations(design)
    assert len(made) == len(design.configurations) >= 4
    for m in made:
        assert check(m.deck).exit_status == 0
        # the count is floor(ratio x V / v): within one sphere's share below the ratio asked
        asked, got, r = m.config.values["fill_ratio"], m.values["fill_ratio"], m.values["radius"]
        one = got / m.values["count"]
        assert asked - one < got <= asked + 1e-12
        assert one == pytest.approx(4 / 3 * math.pi * r**3 / (0.263 * 0.372 * 0.372), rel=1e-9)


@pytest.mark.validate
def test_a_reduced_size_fill_design_runs_and_the_particles_add_damping(tmp_path):
    # designs/beam_size_fill.toml with the 1/8 in spheres at 5 and 10 % only, one drive, 0.3 s
    # driven and 0.6 s of ring-down (the shipped file: 1 s and 2 s, nine configurations)
    text = SIZE_FILL.read_text()
    head = text[: text.index("[[configuration]]")]
    head = head.replace('"../decks/beam_64.inp"', f'"{ROOT / "decks" / "beam_64.inp"}"')
    head = head.replace("fill_ratio = [0.05, 0.1, 0.2]", "fill_ratio = [0.05, 0.1]")
    big = re.search(r"\[\[configuration\]\]\nname = \"d1-8in\"\n(?:[^\[\n].*\n)*", text)
    path = tmp_path / "size_fill_reduced.toml"
    path.write_text(
        head + big.group(0) + '\n[evaluate]\nkind = "ringdown"\n'
        "drives = [9.68080e-3]\ndrive_frequency = 37.2\ndrive_until = 0.3\n"
        "ring = 0.6\n"
    )
    rows = run_design(path, tmp_path / "out", workers=1, echo=lambda s: None)
    assert sorted({r["config"] for r in rows}) == ["d1-8in_fill0.05", "d1-8in_fill0.1"]
    for r in rows:
        # the particles only dissipate: the damped structure's zeta is not below its own
        # c / (2 sqrt(k m)) = 0.318 % (10 % allowed for the ring-down estimate's scatter)
        assert r["zeta_percent"] > 0.9 * r["baseline_zeta_percent"] > 0
    best = {r["config"] for r in rows if r["best"]}
    assert len(best) == 1 and all(r["within_budget"] for r in rows if r["best"])
    assert (tmp_path / "out" / "design_damping.png").exists()
