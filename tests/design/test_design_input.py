"""``x3dpd design`` on design files a user can get wrong, each refused at its line before
anything is written (a binary file, a master node that does not exist or is never used, a fill
that cannot fit from [vary], no drive point), the default drive point kept for a configuration
without particles, and a deck's code file named before it runs."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from cli_helpers import refused

from x3dpd.design.explore import run_design

ROOT = Path(__file__).resolve().parents[2]
BEAM_1 = ROOT / "decks" / "beam_1.inp"
SWEEP = '[evaluate]\nkind = "sweep"\ndrives = [1e-3]\nfrequencies = [37.0]\n'


def _spec(tmp_path: Path, body: str, structure: Path = BEAM_1) -> Path:
    spec = tmp_path / "design.toml"
    spec.write_text(f'structure = "{structure}"\n' + body)
    return spec


def _refused(capsys, spec: Path, message: str) -> str:
    """``x3dpd design SPEC --out DIR`` refused (exit 2, one line holding ``message``, nothing
    written beside SPEC)."""
    folder = spec.parent
    return refused(capsys, "design", spec, "--out", folder / "out", message=message, folder=folder)


def _line(spec: Path, text: str) -> int:
    lines = spec.read_text().splitlines()
    return next(k for k, line in enumerate(lines, 1) if line.startswith(text))


def test_a_binary_design_file_is_refused(tmp_path, capsys):
    spec = tmp_path / "design.toml"
    spec.write_bytes(b'title = "x"\n\x89PNG\r\n\x1a\n\x00\xff\xfe')
    _refused(capsys, spec, f"{spec}:2: not a TOML file: byte 0x89 is not UTF-8 text")


@pytest.mark.parametrize(
    "cavity, fill, message",
    [
        ("masters = [9, 999]", "cavities = 2", "cavity.masters: node 999 is not a node of"),
        ("masters = [999]", "count = 1", "cavity.masters: the first is the deck's own cavity's"),
        ("masters = [9]", "count = 1", "no configuration has more than one"),
    ],
)
def test_master_nodes_are_checked_and_must_be_used(tmp_path, capsys, cavity, fill, message):
    """[cavity] masters = [999] (no such node) was ignored when no configuration had several
    cavities, and every point ran."""
    spec = _spec(tmp_path, f"[cavity]\n{cavity}\n[fill]\n{fill}\n" + SWEEP)
    line = _refused(capsys, spec, message)
    assert line.startswith(f"x3dpd: error: {spec}:{_line(spec, 'masters')}: ")


def test_a_fill_from_vary_that_cannot_fit_names_its_line(tmp_path, capsys):
    """count = [1, 500]: the 500-sphere configuration comes from [vary] alone; its error once
    named no line (0)."""
    spec = _spec(tmp_path, "[fill]\nradius = 0.05\n[vary]\ncount = [1, 500]\n" + SWEEP)
    line = _refused(capsys, spec, "configuration n500: ")
    assert line.startswith(f"x3dpd: error: {spec}:{_line(spec, 'count = [1, 500]')}: ")
    assert "a fill that cannot fit" in line


def _undriven(tmp_path: Path) -> Path:
    """beam_1 without its USRFRC card: the drive point is the cavity's master, node 9 x."""
    deck = tmp_path / "undriven.inp"
    deck.write_text(re.sub(r"(?ms)^USRFRC\n.*?^END\n", "", BEAM_1.read_text()))
    return deck


def test_a_configuration_without_particles_is_driven_at_the_structures_master(tmp_path):
    """[fill] count = 0 drops the cavity with the particles: the drive point (the structure
    deck's cavity master) was lost and the design refused, naming --node and --dof, which it
    does not have. A short dwell of the bare SDOF at node 9 x."""
    spec = _spec(
        tmp_path,
        '[fill]\ncount = 0\ndt = 4e-5\n[evaluate]\nkind = "dwell"\ndrives = [1e-3]\n'
        "frequency = 37.0\nwindow = 2\nmax_cycles = 6\n",
        _undriven(tmp_path),
    )
    rows = run_design(spec, tmp_path / "out", workers=1, echo=lambda s: None)
    assert len(rows) == 1 and rows[0]["count"] == 0 and rows[0]["amplitude"] > 0
    stored = (tmp_path / "out" / "configs" / "config_1" / "sweep" / "sweep.json").read_text()
    assert '"node": 9' in stored and '"dof": 1' in stored


@pytest.mark.parametrize("kind", ["sweep", "ringdown"])
def test_no_drive_point_is_refused_before_anything_is_written(tmp_path, capsys, kind):
    """decks/impact_wall.inp: no USRFRC drive, no cavity on a master node; the ring-down's
    error once came after configs/*/ was written."""
    deck = ROOT / "decks" / "impact_wall.inp"
    evaluate = SWEEP if kind == "sweep" else '[evaluate]\nkind = "ringdown"\n'
    spec = _spec(tmp_path, "[fill]\ncount = 0\ndt = 1e-9\n" + evaluate, deck)
    message = (
        "evaluate: impact_wall.inp has no USRFRC drive and no cavity master node to drive; "
        "give node and dof in [evaluate]"
    )
    line = _refused(capsys, spec, message)
    assert line.startswith(f"x3dpd: error: {spec}:{_line(spec, '[evaluate]')}: ")
    assert "--node" not in line


class _Stop(Exception):
    pass


def test_a_deck_code_file_is_named_before_the_design_runs_it(tmp_path):
    """usrfrc_code = true: the design copies the structure's code file beside every
    configuration's deck and runs it (a sweep point's predicted start loads the deck's
    forces); the first line after the checks names it, before anything is written."""
    deck = tmp_path / "coded.inp"
    deck.write_text(BEAM_1.read_text().replace("USRFRC\n", "USRFRC\n   force.py\n", 1))
    (tmp_path / "force.py").write_text("def usrfrc(time, coords, vels, force):\n    pass\n")
    spec = _spec(tmp_path, "usrfrc_code = true\n[fill]\ncount = 0\n" + SWEEP, deck)
    lines = []

    def echo(line: str) -> None:
        lines.append(line)
        raise _Stop

    with pytest.raises(_Stop):
        run_design(spec, tmp_path / "out", workers=1, echo=echo)
    assert lines[0].startswith("code run: force.py (the structure's USRFRC Python file")
    assert "executes it with your permissions" in lines[0]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "options, message",
    [
        (("--replicas", 0), "--replicas 0: expected 1 or more"),
        (("--max-cycles", 10), "--max-cycles 10: expected 3 x window (15) or more cycles"),
        (("--tol", 2), "--tol 2: expected a fraction 0 < tol < 1"),
        (("--window", 1), "--window 1: expected 2 or more cycles"),
    ],
)
def test_a_steady_state_setting_that_cannot_work_is_named(tmp_path, capsys, options, message):
    """The refusal names the one setting at fault and what it must be (it listed every rule);
    a tolerance of 2 (200 %) measured nothing and was taken."""
    out = tmp_path / "out"
    args = ("sweep", BEAM_1, "--freq", 37, "--amp", 1e-3, "--out", out, *options)
    refused(capsys, *args, message=message, folder=tmp_path)


def test_a_design_file_s_steady_state_setting_is_refused_at_its_line(tmp_path, capsys):
    spec = _spec(tmp_path, SWEEP + "window = 10\nmax_cycles = 20\n")
    line = _refused(capsys, spec, "max_cycles = 20: expected 3 x window (30) or more cycles")
    assert line.startswith(f"x3dpd: error: {spec}:{_line(spec, 'max_cycles')}: evaluate.max_cycles")
