"""`x3dpd check` on decks at the edge of double precision: a diagnosis, never a traceback or a
clean bill."""

from __future__ import annotations

from pathlib import Path

import pytest

from x3dpd.cli import main

DECKS = Path(__file__).resolve().parents[2] / "decks"


def mutated(tmp_path, deck, old, new):
    text = (DECKS / deck).read_text()
    assert old in text
    path = tmp_path / deck
    path.write_text(text.replace(old, new))
    return str(path)


def check(path, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["check", path])
    out = capsys.readouterr()
    return exit_.value.code, out.out + out.err


@pytest.mark.parametrize("density", ["1e-322", "1e-300", "1e308"])
def test_an_extreme_density_is_diagnosed(tmp_path, capsys, density):
    path = mutated(tmp_path, "impact_wall.inp", "0.0007329707329707328", density)
    code, text = check(path, capsys)
    assert "Traceback" not in text
    assert code in (1, 2) and "clean" not in text.splitlines()[0]


def test_an_initial_speed_of_1e300_is_an_error(tmp_path, capsys):
    path = mutated(tmp_path, "impact_wall.inp", "-62.832", "-1e300")
    code, text = check(path, capsys)
    assert code == 2 and "overflows" in text


def test_a_body_acceleration_of_1e300_is_an_error(tmp_path, capsys):
    path = mutated(tmp_path, "beam_64.inp", "0.0 -386.1 0.0", "0.0 -1e300 0.0")
    code, text = check(path, capsys)
    assert code == 2 and "BODY acceleration" in text and "time step" in text


@pytest.mark.parametrize(
    "old, new",
    [
        ("   9 0.0625 0.0 0.0", "   9999999999999999999 0.0625 0.0 0.0"),
        ("   1 9", "   1 9999999999999999999"),
    ],
)
def test_an_id_beyond_int64_is_a_deck_error(tmp_path, capsys, old, new):
    path = mutated(tmp_path, "impact_wall.inp", old, new)
    code, text = check(path, capsys)
    assert code == 2 and "below 2^53" in text and "Traceback" not in text
