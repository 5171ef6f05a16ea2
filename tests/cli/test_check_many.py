"""``x3dpd check a.inp b.inp ...``: every deck is checked; the exit status is the worst."""

from __future__ import annotations

from cli_helpers import DECKS, run_cli


def test_several_decks_are_all_reported(capsys):
    rc = run_cli("check", DECKS / "beam_64.inp", DECKS / "impact_wall.inp")
    out = capsys.readouterr().out
    assert out.count("summary") == 2
    assert "beam_64.inp:" in out and "impact_wall.inp:" in out
    assert rc == max(
        run_cli("check", DECKS / "beam_64.inp"), run_cli("check", DECKS / "impact_wall.inp")
    )


def test_a_bad_deck_does_not_stop_the_others(tmp_path, capsys):
    bad = tmp_path / "bad.inp"
    bad.write_text("PARAMETERS\n 0 1 x\nEND\n")
    rc = run_cli("check", bad, tmp_path / "missing.inp", DECKS / "beam_1.inp")
    captured = capsys.readouterr()
    assert rc == 2
    assert "bad.inp:2:" in captured.err and "missing.inp: no such deck file" in captured.err
    assert "beam_1.inp:" in captured.out and "summary" in captured.out
    assert "Traceback" not in captured.err


def test_the_printed_appendix_a_deck_is_flagged_among_clean_ones(capsys):
    rc = run_cli("check", DECKS / "appendix_a_cube.inp", DECKS / "appendix_a.inp")
    out = capsys.readouterr().out
    assert rc == run_cli("check", DECKS / "appendix_a.inp") >= 1
    assert out.count("summary") == 2 and "appendix_a_cube.inp: clean" in out
