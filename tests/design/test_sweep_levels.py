"""A drive level no run can hold is refused before anything runs: ``x3dpd sweep --drive base
--amp 1e300g`` ran, blew up (exit 3, y = -2.3e298), left sweep.json, and its diagnosis blamed
the time step; a force of 1e300 likewise, and a design's drives."""

from __future__ import annotations

import pytest
from cli_helpers import DECKS, refused
from factories import base_sdof_deck

from x3dpd.deck.writer import write_deck


@pytest.fixture
def shaker(tmp_path):
    path = tmp_path / "shaker.inp"
    write_deck(base_sdof_deck(dt=1e-5, dof=2), path)
    return path


@pytest.mark.parametrize(
    "amp, message",
    [
        ("1e300g", "a drive whose acceleration amplitude is 3.861e+302 in/s^2 at 30 Hz"),
        ("1e200vel", "a drive whose velocity amplitude is 1e+200 in/s at 30 Hz"),
        ("1e130", "a drive whose displacement amplitude is 1e+130 in at 30 Hz"),
    ],
)
def test_a_base_level_beyond_double_precision_is_refused(shaker, tmp_path, capsys, amp, message):
    args = ("sweep", shaker, "--drive", "base", "--node", 2, "--dof", 2, "--response", "1:2")
    args += ("--freq", "30:40:10", "--workers", 1, "--max-cycles", 15)
    line = refused(
        capsys, *args, "--amp", amp, "--out", tmp_path / "out", message=message, folder=tmp_path
    )
    assert "beyond what a run can hold" in line


def test_a_force_beyond_double_precision_is_refused(tmp_path, capsys):
    refused(
        capsys,
        "sweep",
        DECKS / "beam_1.inp",
        "--freq",
        "37",
        "--amp",
        "1e300",
        "--out",
        tmp_path / "out",
        message="--amp: a drive whose force amplitude is 1e+300 lbf at 37 Hz",
        folder=tmp_path,
    )
    spec = tmp_path / "design.toml"
    spec.write_text(
        f'structure = "{DECKS / "beam_1.inp"}"\n[evaluate]\nkind = "sweep"\n'
        "drives = [1e-3, 1e300]\nfrequencies = [37.0]\n"
    )
    refused(
        capsys,
        "design",
        spec,
        "--out",
        tmp_path / "out",
        message=f"{spec}:4: evaluate.drives: a force amplitude of 1e+300 is beyond",
        folder=tmp_path,
    )
