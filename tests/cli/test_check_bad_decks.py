"""``x3dpd check`` on decks a user can get wrong in ways the parser once let through to a
traceback or named badly: a mode at 1e300 Hz, FRICTION fields swapped (a word where NODLIM's
integer goes), a mode file's error. Each is one ``FILE:LINE:COL: CARD: message`` line, exit 2,
nothing written."""

from __future__ import annotations

import re

from cli_helpers import DECKS, refused

MODAL = (DECKS / "beam_64_modal.inp").read_text()


def _line_of(text: str, needle: str) -> int:
    return text[: text.index(needle)].count("\n") + 1


def test_a_mode_frequency_out_of_range_is_named_at_its_record(tmp_path, capsys):
    """MODE 2 at 1e300 Hz once reached scipy's eigensolver (couple_added_mass: "array must not
    contain infs or NaNs"); a frequency above the range is refused at its MODE record."""
    text = MODAL.replace("MODE 2 239.872021", "MODE 2 1e300")
    deck = tmp_path / "modal.inp"
    deck.write_text(text)
    line = refused(
        capsys,
        "check",
        deck,
        message="MODAL: mode 2 has frequency 1e+300 (cycles per time unit): out of range",
        folder=tmp_path,
    )
    assert line.startswith(f"x3dpd: error: {deck}:{_line_of(text, 'MODE 2 1e300')}:4: MODAL:")
    assert "expected 0 <= FREQ <= 1e+12" in line


def test_a_mode_frequency_far_above_the_others_is_refused_when_the_housing_couples(
    tmp_path, capsys
):
    """1e15 Hz beside 38 Hz: the coupled eigenproblem's rounding (eps x 1e27 of the highest
    eigenvalue) swamps the lowest mode, which came out at 0 Hz; refused, naming the spread."""
    text = MODAL.replace("MODE 3 671.648606", "MODE 3 1e11")
    deck = tmp_path / "modal.inp"
    deck.write_text(text)
    line = refused(capsys, "check", deck, message="mode 3 has frequency 1e+11", folder=tmp_path)
    assert f":{_line_of(text, 'MODE 3 1e11')}:4: MODAL:" in line
    assert "above mode 1's 38.2761" in line and "HOUSING added" in line


def test_a_mode_file_frequency_out_of_range_is_named_at_its_file_record(tmp_path, capsys):
    text = re.sub(r"(?s)MODAL\n.*?END\n", "MODAL\n   FILE modes.csv zeta=0.003\nEND\n", MODAL)
    (tmp_path / "modes.csv").write_text(
        "units,in,lbf,s\nfreq_hz,,38.0,1e300\nnode,dof,1,2\n9,x,70.0,30.0\n"
    )
    deck = tmp_path / "modal.inp"
    deck.write_text(text)
    line = refused(capsys, "check", deck, message="mode 2 has frequency 1e+300", folder=tmp_path)
    assert f"{deck}:{_line_of(text, 'FILE modes.csv')}:4: MODAL: mode file modes.csv: " in line


def test_a_word_where_an_integer_goes_is_named_not_rewritten(tmp_path, capsys):
    """FRICTION ``mindlin 9 0.35 0.3`` (LAW and NODLIM swapped): the Fortran D-exponent rewrite
    turned the word into 'minelin' and float() raised; the field is named with the word as
    written."""
    text = (DECKS / "impact_wall.inp").read_text()
    text = text.replace("TRACE\n", "FRICTION\n   mindlin 8 0.35 0.3\nEND\nTRACE\n", 1)
    deck = tmp_path / "friction.inp"
    deck.write_text(text)
    line = refused(
        capsys,
        "check",
        deck,
        message="FRICTION: NODLIM (field 1) must be an integer; got 'mindlin'",
        folder=tmp_path,
    )
    assert line.startswith(f"x3dpd: error: {deck}:{_line_of(text, 'mindlin')}:4: ")
    assert "minelin" not in line
    # a word where a number goes: named too (MUS here), and 1.0D0 still reads as 1.0
    deck.write_text(text.replace("mindlin 8 0.35 0.3", "8 mindlin high 0.3"))
    refused(capsys, "check", deck, message="MUS (field 3) must be a number; got 'high'")
    deck.write_text(text.replace("mindlin 8 0.35 0.3", "8 mindlin 3.5D-1 0.3D0"))
    from cli_helpers import run_cli

    assert run_cli("check", deck) in (0, 1)


def test_a_mode_file_error_names_the_file_once(tmp_path, capsys):
    """A bad line of a MODAL FILE's CSV: the deck's place, then the file as the record gives
    it with its line -- not the file again as an absolute path."""
    text = re.sub(r"(?s)MODAL\n.*?END\n", "MODAL\n   FILE modes.csv zeta=0.003\nEND\n", MODAL)
    (tmp_path / "modes.csv").write_text("units,in,lbf,s\nfreq_hz,,38.0\nnode,dof,1\n9,x,seventy\n")
    deck = tmp_path / "modal.inp"
    deck.write_text(text)
    line = refused(capsys, "check", deck, message="MODAL: mode file modes.csv:4: ", folder=tmp_path)
    assert line.count("modes.csv") == 1, line
    assert str(tmp_path) not in line.split(": MODAL: ", 1)[1]
