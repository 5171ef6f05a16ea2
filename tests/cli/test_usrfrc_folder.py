"""A deck's USRFRC card names its user force file relative to the deck, whatever the working
directory: a file without ``.py`` (``drive``) was code when ``x3dpd`` ran from the deck's
folder (``os.path.exists`` relative to the shell) and an unknown force kind from anywhere else."""

from __future__ import annotations

from cli_helpers import DECKS, run_cli

CODE = "def usrfrc(time, coords, vels, force):\n    pass\n"


def _deck(folder):
    folder.mkdir()
    deck = folder / "deck.inp"
    deck.write_text((DECKS / "beam_1.inp").read_text().replace("USRFRC\n", "USRFRC\n   drive\n", 1))
    return deck


def test_a_code_file_without_py_is_found_beside_the_deck_from_anywhere(
    tmp_path, capsys, monkeypatch
):
    deck = _deck(tmp_path / "a")
    (tmp_path / "a" / "drive").write_text(CODE)
    elsewhere = tmp_path / "b"
    elsewhere.mkdir()
    for cwd, name in ((deck.parent, "deck.inp"), (elsewhere, "../a/deck.inp")):
        monkeypatch.chdir(cwd)
        assert run_cli("check", name) == 0
        out, err = capsys.readouterr()
        assert "code run" in out and "drive: a USRFRC Python file" in out, out + err


def test_a_file_in_the_working_directory_is_not_the_decks(tmp_path, capsys, monkeypatch):
    """``drive`` in the shell's folder but not beside the deck: not the deck's code file (the
    spec is then read as a built-in law, and refused as one)."""
    deck = _deck(tmp_path / "a")
    (tmp_path / "drive").write_text(CODE)
    monkeypatch.chdir(tmp_path)
    assert run_cli("check", deck) == 2
    err = capsys.readouterr().err
    assert "USRFRC: usrfrc spec 'drive': unknown force kind 'drive'" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
