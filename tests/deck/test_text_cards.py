"""Our text cards (x3dpd.deck.text_cards): a card whose records are words is read and written
from its registration alone.

The seam is shown on a card written here (HUMIDITY: one record ``RELATIVE PERCENT``) and
registered in a child process, so the package's registry stays the shipped one: the grammar,
the field table, the reader's gate, the transformer and the writer take it from its
``TextCard``; the test adds the field to ``Deck`` as a new card's third file does. The shipped
text cards (TEMPERATURE, MODAL, PLATES) are registered in the writer's order.
"""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
import types
from pathlib import Path

import pytest

from x3dpd.deck import text_cards
from x3dpd.deck.fields import BY_NAME, SINGLE_CARDS, TEXT_KEYS
from x3dpd.deck.text_card import TextCard

ROOT = Path(__file__).resolve().parents[2]
BEAM_1 = ROOT / "decks" / "beam_1.inp"

HUMIDITY = """
from dataclasses import dataclass
from x3dpd.deck.text_card import TextCard
from x3dpd.errors import DeckError, Pos

@dataclass(frozen=True)
class Humidity:
    percent: float
    pos: Pos

def _parse(pos, lines):
    if len(lines) != 1:
        raise DeckError("one record: RELATIVE PERCENT", "<deck>", pos.line, pos.column, "HUMIDITY")
    text, line, col = lines[0]
    col += len(text) - len(text.lstrip())  # the record's first word
    words = text.split()
    if len(words) != 2 or words[0].upper() != "RELATIVE":
        raise DeckError(f"expected RELATIVE PERCENT; got {text.strip()!r}", "<deck>", line, col,
                        "HUMIDITY")
    return Humidity(float(words[1]), pos)

TEXT_CARD = TextCard("HUMIDITY", "humidity", parse=_parse,
                     lines=lambda h: [f"RELATIVE {h.percent!r}"], header="RELATIVE PERCENT")
"""

CHILD = """
import dataclasses, json, sys, types
from pathlib import Path
import x3dpd
# the registry is loaded before the deck package, with the new card in it
package = types.ModuleType("x3dpd.deck")
package.__path__ = [str(Path(x3dpd.__file__).parent / "deck")]
sys.modules["x3dpd.deck"] = package
import x3dpd.deck.text_cards as tc
import humidity_card
tc.TEXT_CARDS = tc.TEXT_CARDS + tc._register(humidity_card)
tc.BY_TEXT_TERMINAL = {c.terminal: c for c in tc.TEXT_CARDS}
import x3dpd.deck.cards as cards

@dataclasses.dataclass(frozen=True)
class Deck(cards.Deck):   # the card's Deck field
    humidity: object = None

cards.Deck = Deck
del sys.modules["x3dpd.deck"]
from x3dpd.deck import format_deck, parse_deck, read_deck
from x3dpd.errors import DeckError

out = {}
for path in sys.argv[1:]:
    try:
        deck = read_deck(path)
        written = format_deck(deck)
        again = parse_deck(written)
        out[path] = {"percent": None if deck.humidity is None else deck.humidity.percent,
                     "again": None if again.humidity is None else again.humidity.percent,
                     "written": [l for l in written.splitlines() if "RELATIVE" in l],
                     "nodes": len(deck.nodes)}
    except DeckError as e:
        out[path] = {"error": str(e)}
print(json.dumps(out))
"""


def test_a_text_card_needs_no_code_of_the_deck_reader_or_writer(tmp_path):
    (tmp_path / "humidity_card.py").write_text(HUMIDITY)
    (tmp_path / "child.py").write_text(CHILD)
    base = BEAM_1.read_text()
    cases = {
        "good": "HUMIDITY\n  RELATIVE 45.5\nEND\n",
        "bad": "HUMIDITY\n  ABSOLUTE 12\nEND\n",
        "none": "",
        # its lines are text to its END: a word that would start a card is a record
        "keyword": "HUMIDITY\n  NODE 3\nEND\n",
    }
    paths = []
    for name, card in cases.items():
        p = tmp_path / f"{name}.inp"
        p.write_text(base + "\n" + card)
        paths.append(p)
    run = subprocess.run(
        [sys.executable, str(tmp_path / "child.py"), *map(str, paths)],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": f"{tmp_path}:{ROOT}"},
        timeout=300,
    )
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    good, bad, none, keyword = (got[str(p)] for p in paths)
    assert good["percent"] == good["again"] == 45.5  # the writer writes what the reader reads
    assert good["written"] == ["$ RELATIVE PERCENT", "   RELATIVE 45.5"]
    assert good["nodes"] == none["nodes"] > 0
    assert none["percent"] is None and none["written"] == []
    line = len(base.splitlines()) + 3  # a blank line, HUMIDITY, the record
    assert bad["error"] == (
        f"{paths[1]}:{line}:3: HUMIDITY: expected RELATIVE PERCENT; got 'ABSOLUTE 12'"
    )
    assert keyword["error"].startswith(f"{paths[3]}:{line}:3: HUMIDITY: expected RELATIVE")


def test_the_shipped_text_cards_are_registered_in_the_writers_order():
    names = [c.name for c in text_cards.TEXT_CARDS]
    assert names == ["TEMPERATURE", "MODAL", "PLATES"]
    for card in text_cards.TEXT_CARDS:
        assert card.name in SINGLE_CARDS and card.key in TEXT_KEYS
        assert BY_NAME[card.name].key == card.key
        assert text_cards.BY_TEXT_TERMINAL[card.terminal] is card


def test_the_registry_refuses_two_cards_on_the_same_four_letters_or_field():
    shipped = [importlib.import_module(c.module) for c in text_cards.TEXT_CARDS]
    for card, clash in (
        (TextCard("TEMPEST", "tempest", parse=print, lines=list), "key"),
        (TextCard("HUMIDITY", "modal", parse=print, lines=list), "field"),
    ):
        module = types.SimpleNamespace(__name__="tests.fake_card", TEXT_CARD=card)
        with pytest.raises(ValueError, match=f"share a {clash}"):
            text_cards._register(*shipped, module)
