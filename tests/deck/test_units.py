"""The UNITS card (our extension): parsed, checked, written back, and followed by the labels."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from x3dpd.deck import format_deck, parse_deck
from x3dpd.errors import DeckError
from x3dpd.model.build import build_model
from x3dpd.units import labels_for, parse_units, trace_units

ROOT = Path(__file__).resolve().parents[2]
BASE = "PARAMETERS\n 0 1 0 1e-3 1e-3 0 1e9 0 5 0 10\nEND\nNODE\n 1 0 0 0\nEND\n"


def test_default_is_the_reports_inch_lbf_second():
    model = build_model(parse_deck(BASE))
    assert model.units == ("in", "lbf", "s")
    lab = labels_for(model.units)
    assert (lab["length"], lab["mass"], lab["energy"], lab["velocity"]) == (
        "in",
        "lbf s^2/in",
        "lbf in",
        "in/s",
    )
    from x3dpd.io.trace import DEFAULT_UNITS

    assert trace_units(None) == {
        **DEFAULT_UNITS,
        "force": "lbf",
        "mass": "lbf s^2/in",
        "energy": "lbf in",
    }


@pytest.mark.parametrize(
    "text, system, mass, energy",
    [
        ("m N s", ("m", "N", "s"), "kg", "J"),
        ("MM, n, S", ("mm", "N", "s"), "t", "mJ"),
        ("cm dyn s", ("cm", "dyn", "s"), "g", "erg"),
        ("ft lbf s", ("ft", "lbf", "s"), "slug", "lbf ft"),
    ],
)
def test_declared_system_reaches_the_model_and_round_trips(text, system, mass, energy):
    deck = parse_deck(f"UNITS\n  {text}\nEND\n" + BASE)
    assert deck.units.system == system
    assert build_model(deck).units == system
    lab = labels_for(system)
    assert (lab["mass"], lab["energy"]) == (mass, energy)
    again = parse_deck(format_deck(deck))
    assert again.units.system == system


@pytest.mark.parametrize(
    "text, words",
    [
        ("m furlong s", ["UNITS", "FORCE unit 'furlong'", "lbf, N"]),
        ("m N", ["expected 3 unit names"]),
        ("", ["expected 3 unit names"]),
    ],
)
def test_bad_units_card_is_a_deck_error_at_the_card(text, words):
    with pytest.raises(DeckError) as err:
        parse_deck(BASE + f"UNITS\n  {text}\nEND\n")
    msg = str(err.value)
    assert ":7:" in msg or ":8:" in msg  # the card's lines
    for w in words:
        assert w in msg


def test_units_card_may_appear_once():
    with pytest.raises(DeckError, match="only once"):
        parse_deck("UNITS\n m N s\nEND\nUNITS\n m N s\nEND\n" + BASE)


def test_parse_units_rejects_unknown_names():
    with pytest.raises(ValueError, match="TIME unit 'h'"):
        parse_units(["m", "N", "h"])


def test_check_reports_the_declared_units(tmp_path, capsys):
    from x3dpd.cli import main

    deck = tmp_path / "si.inp"
    text = (ROOT / "decks" / "beam_1.inp").read_text()
    deck.write_text("UNITS\n  m N s\nEND\n" + text)
    with pytest.raises(SystemExit):
        main(["check", str(deck)])
    out = capsys.readouterr().out
    assert "units            m N s" in out and "mass kg" in out
    assert "m/s lasts" in out and "length/s" not in out and " in/s" not in out
    shutil.rmtree(tmp_path)


def test_a_runs_sidecar_and_plot_follow_the_declared_units(tmp_path, monkeypatch):
    import json

    from x3dpd.cli import main

    monkeypatch.chdir(tmp_path)
    text = (ROOT / "decks" / "beam_1.inp").read_text()
    Path("si.inp").write_text("UNITS\n  m N s\nEND\n" + text)
    Path("in.inp").write_text(text)
    for name in ("si", "in"):
        with pytest.raises(SystemExit) as ex:
            main([f"{name}.inp", "--tmax", "0.002", "--quiet", "--plot", f"{name}.png"])
        assert ex.value.code == 0
    si = json.loads(Path("si.trace.txt.json").read_text())["units"]
    inch = json.loads(Path("in.trace.txt.json").read_text())["units"]
    assert si == {
        "time": "s",
        "length": "m",
        "velocity": "m/s",
        "angular_velocity": "rad/s",
        "force": "N",
        "mass": "kg",
        "energy": "J",
    }
    assert inch["length"] == "in" and inch["energy"] == "lbf in" and inch["mass"] == "lbf s^2/in"
    assert Path("si.png").stat().st_size > 10_000
