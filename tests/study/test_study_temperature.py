"""`x3dpd study --temperature T`: every setting of the study runs at T over the deck's
TEMPERATURE card's operating temperature, as `x3dpd run --temperature` does; a deck without
the card is refused before anything is written."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

import x3dpd
from x3dpd.cli import main
from x3dpd.study import run_study

DECK = Path(__file__).resolve().parents[2] / "decks" / "capsule_wc7.inp"


def _study(out: Path, temperature=None) -> list[dict]:
    """A one-setting study of a short window (4000 steps) at ``temperature``; its rows."""
    dt = x3dpd.load_deck(DECK).parameters.dtmax
    run_study(DECK, out, tmax=4000 * dt, dts=[dt], fidelity=False, temperature=temperature)
    with open(out / "study.csv") as f:
        return list(csv.DictReader(f))


def test_the_study_runs_at_the_temperature_asked_for(tmp_path):
    card = x3dpd.load_deck(DECK).temperature.operating.text
    own = _study(tmp_path / "own")
    same = _study(tmp_path / "same", card)
    cold = _study(tmp_path / "cold", "-94F")
    # the card's own temperature asked for: the same runs, bit for bit
    assert [r["amplitude"] for r in same] == [r["amplitude"] for r in own]
    # at -94 F the titanium capsule has shrunk more than the carbide spheres (its expansion
    # coefficient is the larger): their first impacts come sooner
    assert float(cold[0]["power_per_cycle"]) > 10 * float(own[0]["power_per_cycle"])


def test_a_deck_without_a_temperature_card_is_refused(tmp_path, capsys):
    deck = Path(__file__).resolve().parents[2] / "decks" / "beam_1.inp"
    with pytest.raises(SystemExit) as e:
        main(["study", str(deck), "--temperature", "850F", "--out", str(tmp_path / "s")])
    assert e.value.code == 2
    assert "no TEMPERATURE card" in capsys.readouterr().err
    assert not (tmp_path / "s").exists()
