"""`x3dpd study` on every shipped deck (decks/*.inp, so a new deck is included by itself): a
tiny window in the default suite, longer ones under ``-m validate``.

Each study writes study.csv with its contract columns -- ``dt`` (a number, or ``auto`` for the
step chosen by accuracy), ``wall_s_per_sim_s`` and ``error`` -- and study.png, and prints a
verdict. A deck that ``x3dpd run`` refuses (the printed Appendix A deck, whose walls cut through
its particles) is refused by the study too, with the same diagnosis and exit 2, writing nothing.
"""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

import x3dpd
from x3dpd.api.safety import initial_penetration_error
from x3dpd.cli import main

DECKS = sorted((Path(__file__).resolve().parents[2] / "decks").glob("*.inp"))
#: Drive for decks without a USRFRC card (Appendix C's, decks/README.md).
APPENDIX_C = "sine:node=25,dof=1,amp=4.84040e-3,hz=37.21"
#: The base-driven deck's shaker (as tests/api/test_api_run.py runs it: the same loop)
DRIVES = {"shaker_fig9.inp": ("--motion", "node=4,dof=2,amp=0.02,hz=36.75")}


def refused(deck: Path) -> bool:
    """Whether ``x3dpd run`` refuses the deck before its first step (the same rule)."""
    return (
        initial_penetration_error(x3dpd.build(x3dpd.load_deck(deck)), 0.25, str(deck)) is not None
    )


def study(deck: Path, out: Path, steps_of_dtmax: int, *extra: str):
    dt = x3dpd.load_deck(deck).parameters.dtmax
    argv = [
        "study",
        str(deck),
        "--tmax",
        repr(steps_of_dtmax * dt),
        "--dt",
        f"{dt!r},{2 * dt!r},auto",
        "--no-fidelity",
        "--workers",
        "1",
        "--out",
        str(out),
        "-q",
        *extra,
    ]
    with pytest.raises(SystemExit) as e:
        main(argv)
    return e.value.code


def check_outputs(out: Path) -> list[dict]:
    with open(out / "study.csv") as f:
        rows = list(csv.DictReader(f))
    assert rows and {"dt", "wall_s_per_sim_s", "error"} <= set(rows[0])
    for r in rows:
        assert r["dt"] == "auto" or float(r["dt"]) > 0
        if r["status"] == "complete":
            assert float(r["wall_s_per_sim_s"]) > 0
        assert r["error"] == "" or float(r["error"]) >= 0  # empty: nothing to compare
    assert sum(r["dt"] == "auto" for r in rows) == 1
    assert 0 < (out / "study.png").stat().st_size < 300_000
    return rows


@pytest.mark.parametrize("deck", DECKS, ids=lambda p: p.name)
def test_every_shipped_deck_can_be_studied_in_a_tiny_window(tmp_path, deck, capsys):
    code = study(deck, tmp_path / "s", 40, *DRIVES.get(deck.name, ()))
    text = capsys.readouterr()
    if refused(deck):
        assert code == 2 and "starts" in text.err and not (tmp_path / "s").exists()
        return
    assert code == 0, text.err
    assert "verdict: " in text.out
    rows = check_outputs(tmp_path / "s")
    assert rows[0]["error"] in ("", "0.0")  # the finest run is the reference


@pytest.mark.validate
@pytest.mark.parametrize("deck", DECKS, ids=lambda p: p.name)
def test_every_shipped_deck_can_be_studied_over_many_output_intervals(tmp_path, deck, capsys):
    d = x3dpd.load_deck(deck)
    par = d.parameters
    intervals = min(30, max(1, round((par.tmax - par.time) / (par.itrac * par.dtmax))))
    extra = ("--usrfrc", APPENDIX_C) if "appendix_a" in deck.name else DRIVES.get(deck.name, ())
    code = study(deck, tmp_path / "s", intervals * par.itrac, *extra)
    text = capsys.readouterr()
    if refused(deck):
        assert code == 2
        return
    assert code == 0, text.err
    rows = check_outputs(tmp_path / "s")
    auto = next(r for r in rows if r["dt"] == "auto")
    assert auto["status"] == "complete"
