"""``x3dpd check DECK``: verdicts and exit statuses on the shipped decks and on broken ones."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from x3dpd.cli.check import check

DECKS = Path(__file__).resolve().parents[2] / "decks"


def run(*args):
    return CliRunner().invoke(check, [str(a) for a in args])


def test_printed_appendix_a_opens_with_the_cavity_headline():
    result = run(DECKS / "appendix_a.inp")
    assert result.exit_code == 1, result.output
    lines = result.output.splitlines()
    assert lines[0].endswith("appendix_a.inp: 3 warnings")
    assert lines[1].startswith(
        "warning: cavity set 1: the twelve contact triangles lie in the planes x = 0.0625, "
        "0.1875, y = 0.0625, 0.1875, z = ±0.09375, inside the particle cloud (particle centres "
        "span x, y from 0.03125 to 0.21875 and z from -0.09375 to 0.09375)"
    )
    assert "38 of the 50 particles start outside the cavity they bound" in lines[1]
    assert "decks/appendix_a_cube.inp" in lines[1]
    assert "open: the faces do not close" in result.output


def test_cube_deck_is_clean():
    result = run(DECKS / "appendix_a_cube.inp")
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert lines[0].endswith("appendix_a_cube.inp: clean, 1 note")
    assert "9.6 steps per contact, peak force within about 1.5 %" in result.output
    assert "closed, interior volume 0.015625; fill ratio 0.409" in result.output
    assert "structure: omega <= 61.86 rad/s (node 25 x)" in result.output


def test_a_hooke_deck_is_advised_by_its_own_contact():
    """decks/hooke_wall.inp: the HOOKE contact (half a damped period of k_n = 1e4 lbf/in on the
    sphere's 7.49575e-7 lbf s^2/in, e = 0.8: 2.727e-5 s, tests/model/test_model_timestep.py),
    not a Hertz impact of the deck's unused E0 (1.09e-5 s)."""
    result = run(DECKS / "hooke_wall.inp")
    assert result.exit_code == 0, result.output
    assert (
        "contact: HOOKE particle-wall impact at 10 in/s lasts 2.73e-05 s; / 50 = 5.45e-07 s"
        in result.output
    )
    assert "Hertz" not in result.output
    # the peak-force error check quotes was measured on Hertz impacts: not said of this one
    assert "2.73e+03 steps per contact)" in result.output and "peak force" not in result.output


def test_cube_deck_is_clean_at_the_decks_own_resolution():
    """At 9 steps per contact the deck's 5e-7 s step is within the recommendation: exit 0."""
    result = run("--steps-per-contact", 9, DECKS / "appendix_a_cube.inp")
    assert result.exit_code == 0, result.output
    assert result.output.splitlines()[0].endswith("appendix_a_cube.inp: clean")


def test_deck_error_is_one_line_and_exit_2(tmp_path):
    text = (DECKS / "appendix_a_cube.inp").read_text()
    bad = tmp_path / "bad.inp"
    bad.write_text(text.replace("   1 2 25\n", "   1 7 25\n"))  # material 7 does not exist
    runner = CliRunner(mix_stderr=False) if _has_mix_stderr() else CliRunner()
    result = runner.invoke(check, [str(bad)])
    assert result.exit_code == 2
    err = result.stderr
    (line,) = err.strip().splitlines()
    assert line.startswith(f"x3dpd: error: {bad}:")
    assert ": ELEMENTS: element 1 uses material 7, which no MATID record defines" in line
    assert "Traceback" not in err


def test_syntax_error_is_exit_2(tmp_path):
    bad = tmp_path / "bad.inp"
    bad.write_text("PARAMETERS\n 0. 1. 0. x\nEND\n")
    result = run(bad)
    assert result.exit_code == 2
    assert "Traceback" not in result.output


def test_missing_file_is_a_usage_error(tmp_path):
    assert run(tmp_path / "nope.inp").exit_code == 2


def test_console_entry_point_passes_the_exit_status_on():
    for name, status in (("appendix_a.inp", 1), ("appendix_a_cube.inp", 0)):
        proc = subprocess.run(
            [sys.executable, "-m", "x3dpd", "check", str(DECKS / name)],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert proc.returncode == status, proc.stdout + proc.stderr


def _has_mix_stderr() -> bool:
    import inspect

    return "mix_stderr" in inspect.signature(CliRunner.__init__).parameters


@pytest.mark.parametrize("spec", ["constant:node=25,dof=1,amp=1"])
def test_usrfrc_option_adds_the_external_force_effect(spec):
    result = run("--usrfrc", spec, DECKS / "appendix_a_cube.inp")
    assert "external_force" in result.output


def test_clean_deck_above_the_recommended_step_says_why():
    """beam_64's DTMAX is about 5x the recommended step: still clean (its contacts span enough
    steps), but the verdict carries a note that names both steps, so verdict and advice agree."""
    from pathlib import Path

    deck = Path(__file__).resolve().parents[2] / "decks" / "beam_64.inp"
    result = CliRunner().invoke(check, [str(deck)])
    assert result.exit_code == 0, result.output
    first, second = result.output.splitlines()[:2]
    assert first.endswith("beam_64.inp: clean, 1 note")
    assert second.startswith("note: DTMAX 5e-07 s is ") and "x the recommended" in second
    assert "x3dpd study" in second
