"""``x3dpd design SPEC --plan``: every configuration made and checked, what each would run
printed, nothing written (x3dpd.design.plan).

The bound is computed here from the design file's own numbers: a sweep point runs at most
``max_cycles`` cycles of 1 / (f dt) steps, over every frequency, drive and chain."""

from __future__ import annotations

import shutil
import tomllib
from pathlib import Path

import pytest
from cli_helpers import folder_state, refused, run_cli

from x3dpd.design.plan import plan_design

ROOT = Path(__file__).resolve().parents[2]
BEAM_COUNT = ROOT / "designs" / "beam_count.toml"


def _copy(tmp_path: Path) -> Path:
    """beam_count.toml beside a copy of its structure (its path is relative)."""
    (tmp_path / "designs").mkdir()
    (tmp_path / "decks").mkdir()
    shutil.copy(ROOT / "decks" / "beam_64.inp", tmp_path / "decks")
    return Path(shutil.copy(BEAM_COUNT, tmp_path / "designs"))


def test_the_plan_of_the_beam_study_bounds_its_steps_from_the_design_file(tmp_path, capsys):
    spec = _copy(tmp_path)
    toml = tomllib.loads(spec.read_text())
    ev = toml["evaluate"]
    freqs, drives = ev["frequencies"], ev["drives"]
    cap = 400  # the default max_cycles (docs/design.md)
    before = folder_state(tmp_path)
    assert run_cli("design", spec, "--plan") == 0
    assert folder_state(tmp_path) == before  # nothing written, not even a configs folder
    said = capsys.readouterr().out
    _, planned = plan_design(spec)
    assert [p.name for p in planned] == [c["name"] for c in toml["configuration"]]
    for p, config in zip(planned, toml["configuration"]):
        expected = len(drives) * sum(cap / (f * config["dt"]) for f in freqs)
        assert p.points == len(freqs) * len(drives)
        assert p.max_steps == pytest.approx(expected, rel=1e-12)
        assert p.values["count"] == config["count"]
        row = next(line for line in said.splitlines() if line.strip().startswith(p.name))
        assert f"{p.max_steps:.3g}" in row and f"{config['count']}" in row
    # half the step, twice the steps: beam_512's bound is beam_64's twice
    assert planned[2].max_steps == pytest.approx(2.0 * planned[1].max_steps)
    assert f"{sum(p.max_steps for p in planned):.3g}" in said.splitlines()[-2]


def test_a_ringdown_plan_and_a_chain_both_ways(tmp_path):
    spec = tmp_path / "ring.toml"
    spec.write_text(
        f'structure = "{ROOT / "decks" / "beam_1.inp"}"\n'
        '[evaluate]\nkind = "ringdown"\ndrives = [1e-3, 2e-3, 4e-3]\ndrive_until = 0.5\n'
        "ring = 1.5\n"
    )
    _, (p,) = plan_design(spec)
    dt = p.values["dt"]  # the configuration's step (the one its particles need)
    assert p.points == 3 and p.max_steps == pytest.approx(3 * 2.0 / dt)
    spec.write_text(
        f'structure = "{ROOT / "decks" / "beam_1.inp"}"\n'
        '[evaluate]\nkind = "sweep"\ndrives = [1e-3]\nfrequencies = [36.0, 38.0]\n'
        'direction = "both"\nmax_cycles = 100\n'
    )
    _, (p,) = plan_design(spec)
    assert p.points == 4
    assert p.max_steps == pytest.approx(2 * (100 / (36.0 * dt) + 100 / (38.0 * dt)))


def test_a_design_without_out_or_plan_is_refused_and_a_bad_file_is_refused_by_the_plan(
    tmp_path, capsys
):
    spec = _copy(tmp_path)
    refused(capsys, "design", spec, message="--out DIR: give the output folder", folder=tmp_path)
    bad = tmp_path / "designs" / "bad.toml"
    bad.write_text(spec.read_text().replace("count = 512", "count = 5120000"))
    refused(capsys, "design", bad, "--plan", message="bad.toml", folder=tmp_path)


def test_a_ring_down_design_with_too_short_a_ring_is_refused_before_anything_runs(tmp_path, capsys):
    """beam_1's structure is one rigid body on one spring: f = sqrt(k / m) / (2 pi) = 37.74 Hz
    before any step, so a 0.1 s ring holds at most 3.8 cycles, against the analysis's 14. The
    plan and the run both refuse it at evaluate.ring's line, naming the configuration, and
    write nothing (a run used to compute every configuration's drive, ring and baseline
    first)."""
    spec = tmp_path / "ring.toml"
    spec.write_text(
        f'structure = "{ROOT / "decks" / "beam_1.inp"}"\n'
        '[evaluate]\nkind = "ringdown"\ndrives = [1e-3]\nring = 0.1\n'
    )
    for args in (("--plan",), ("--out", tmp_path / "out")):
        line = refused(
            capsys,
            "design",
            spec,
            *args,
            message="configuration config_1: at most 3.8 cycles",
            folder=tmp_path,
        )
        assert line.startswith(f"x3dpd: error: {spec}:5: evaluate.ring = 0.1 s, ")
        assert "needs at least 14" in line
