"""A run's temperature through the API (issue 31 item 6): ``x3dpd.run_config(deck,
temperature=)`` builds the model at that operating temperature, and the run's key (what a
restart must match) says which; :meth:`RunConfig.replace` changes it and back again."""

from __future__ import annotations

from pathlib import Path

from x3dpd.api import build, run_config
from x3dpd.api.decks import read_deck, with_temperature

WC7 = Path(__file__).resolve().parents[2] / "decks" / "capsule_wc7.inp"


def test_run_config_builds_the_model_at_the_temperature_and_replace_undoes_it():
    cold = run_config(WC7)
    hot = run_config(WC7, temperature="850F")
    want = build(with_temperature(read_deck(WC7), "850F"))
    assert hot.model.radius.tobytes() == want.radius.tobytes()
    assert hot.model.x0.tobytes() == want.x0.tobytes()
    assert hot.model.radius[0] > cold.model.radius[0]
    assert hot.key != cold.key
    back = hot.replace(temperature=None)
    assert back.model.radius.tobytes() == cold.model.radius.tobytes()
    assert back.key == cold.key
    again = cold.replace(temperature="850F")
    assert again.key == hot.key and again.model.x0.tobytes() == want.x0.tobytes()
