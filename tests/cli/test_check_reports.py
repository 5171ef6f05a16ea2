"""What ``x3dpd check`` says must be true of the deck: a repeated mode pair (a rod's y and z
bending) is one mode, not two 0 bandwidths apart; a step without limit does not deny a USRFRC
drive; a bed that fills its cavity wall to wall is a warning; the units line knows a UNITS
card."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from cli_helpers import DECKS, run_cli

from x3dpd.deck.parser import parse_deck
from x3dpd.deck.writer import write_deck
from x3dpd.design.baselines import without_particles
from x3dpd.model.build import build_model
from x3dpd.model.rules_of_thumb import rules_of_thumb

MODAL = (DECKS / "beam_64_modal.inp").read_text()


def _modal(card: str) -> str:
    return re.sub(r"MODAL\n.*?END\n", card, MODAL, flags=re.DOTALL)


def _check(capsys, *args) -> tuple[int, str]:
    capsys.readouterr()
    status = run_cli("check", *args)
    return status, capsys.readouterr().out


def test_a_repeated_pair_is_one_mode_in_the_rules(tmp_path, capsys):
    """A rod's bending pair at 40 Hz (the solver's shapes turned: 60 and 40 along the drive at
    node 9 x) and a third mode at 120 Hz. Once: "nearest neighbour, mode 2, at 40 Hz: 0
    half-power bandwidths away", and mode 1's effective mass 1/60^2 where the pair's is
    1/(60^2 + 40^2)."""
    text = _modal(
        "MODAL\n   MODE 1 40.0 0.01\n   MODE 2 40.0 0.01\n   MODE 3 120.0 0.01\n"
        "   SHAPE 9 1 60.0 40.0 20.0\n   HOUSING included\nEND\n"
    )
    model = build_model(parse_deck(text, "rod.inp"))
    got = {r.code: r for r in rules_of_thumb(model)}
    mp = float(np.sum(model.mass[model.particle_start :]))
    assert got["mass-ratio"].value == pytest.approx(mp * (60.0**2 + 40.0**2), rel=1e-12)
    assert "modes 1 and 2 (one repeated mode at 40 Hz)'s effective mass at node 9 x" in (
        got["mass-ratio"].text
    )
    assert got["mode-separation"].value == pytest.approx(3.0, rel=1e-12)
    assert "nearest neighbour, mode 3, at 120 Hz" in got["mode-separation"].text
    assert "100 half-power bandwidths" in got["mode-separation"].text
    deck = tmp_path / "rod.inp"
    deck.write_text(text)
    status, out = _check(capsys, deck)
    assert status in (0, 1) and ", 0 half-power" not in out and "mode 2, at 40 Hz" not in out


def test_a_step_without_limit_does_not_deny_the_drive(tmp_path, capsys):
    """beam_64_modal without its particles: no contact, and the modes are integrated exactly,
    so nothing limits the step -- but USRFRC drives node 9, which check once denied ("no
    loaded structural DOFs")."""
    deck = tmp_path / "bare.inp"
    write_deck(without_particles(parse_deck(MODAL, str(deck))), deck)
    assert "sine:node=9,dof=1" in deck.read_text()
    status, out = _check(capsys, deck)
    assert status == 0, out
    assert "no loaded structural DOFs" not in out
    assert (
        "no limit (no contacts and no spring or damper on a free structural DOF; the modes "
        "are integrated exactly at any step)" in out
    )


def test_a_bed_wall_to_wall_along_the_drive_is_a_warning(tmp_path, capsys):
    """beam_64's cavity is 0.263 in along x, the drive's axis: cubic spheres of R = 0.263 / 8
    with the default gap 0 fill it wall to wall (four across), and check said clean."""
    out_deck = tmp_path / "jam.inp"
    r = 0.263 / 8
    assert run_cli("fill", DECKS / "beam_64.inp", "--radius", r, "-o", out_deck) == 0
    status, out = _check(capsys, out_deck)
    assert status == 1, out
    assert "warning: cavity set 1: the particles fill it wall to wall along x (the drive's" in out
    assert "no room to move relative to the cavity" in out
    # with a gap the bed has room: clean again
    spaced = tmp_path / "spaced.inp"
    assert (
        run_cli("fill", DECKS / "beam_64.inp", "--radius", r, "--gap", 0.01 * r, "-o", spaced) == 0
    )
    assert _check(capsys, spaced)[0] == 0


def test_a_bed_jammed_along_every_axis_without_a_drive(tmp_path, capsys):
    """appendix_a_cube (no USRFRC): 64 cubic spheres fill the 0.25 in cube in every axis."""
    jam = tmp_path / "cube.inp"
    assert run_cli("fill", DECKS / "appendix_a_cube.inp", "-o", jam) == 0
    status, out = _check(capsys, jam)
    assert status == 1
    assert "wall to wall along x, y, z (every axis; free length" in out


@pytest.mark.parametrize("declared", [True, False])
def test_the_units_line_knows_a_units_card(tmp_path, capsys, declared):
    text = (DECKS / "impact_wall.inp").read_text()
    deck = tmp_path / "u.inp"
    deck.write_text(
        text.replace("TITLE\n", "UNITS\n   in lbf s\nEND\nTITLE\n", 1) if declared else text
    )
    status, out = _check(capsys, deck)
    line = next(x for x in out.splitlines() if x.strip().startswith("units"))
    if declared:
        assert "in lbf s (from the UNITS card;" in line and "declare" not in line
    else:
        assert "in lbf s (the default: declare others with a UNITS card;" in line
    assert math.isfinite(status)
