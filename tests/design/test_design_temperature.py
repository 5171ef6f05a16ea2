"""``temperature`` as a design variable (issue 31 item 6; docs/design.md): each configuration is
the structure deck at one operating temperature (its TEMPERATURE card's OPERATING replaced),
design.csv carries it, and a temperature the deck cannot take is refused at its line before
anything is written."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import refused

from x3dpd.api import build
from x3dpd.api.decks import read_deck, with_temperature
from x3dpd.design.configs import make_configurations
from x3dpd.design.design_file import read_design
from x3dpd.design.explore import run_design

ROOT = Path(__file__).resolve().parents[2]
WC7 = ROOT / "decks" / "capsule_wc7.inp"
RINGDOWN = (
    '[evaluate]\nkind = "ringdown"\ndrives = [0.04]\ndrive_frequency = 37.0\n'
    "drive_until = 0.05\nring = 0.5\n"
)


def _spec(tmp_path: Path, body: str, structure: Path = WC7) -> Path:
    spec = tmp_path / "design.toml"
    spec.write_text(f'structure = "{structure}"\n[fill]\ndt = 5e-7\n' + body + RINGDOWN)
    return spec


def test_each_configuration_is_the_deck_at_its_temperature(tmp_path):
    spec = _spec(tmp_path, '[vary]\ntemperature = [-94, "455C"]\n')
    made = make_configurations(read_design(spec))
    assert [m.config.name for m in made] == ["T-94", "T455C"]
    assert [m.deck.temperature.operating.text for m in made] == ["-94F", "455C"]
    for m, t in zip(made, (-94, "455C")):
        want = build(with_temperature(read_deck(WC7), t))
        got = build(m.deck)
        assert got.radius.tobytes() == want.radius.tobytes()
        assert got.x0.tobytes() == want.x0.tobytes()
    assert made[1].values["temperature"] == pytest.approx(455 * 9 / 5 + 32)  # degF: an inch deck


def test_design_csv_carries_the_temperature(tmp_path):
    """Two short ring-downs (0.05 s driven, 0.5 s free): the rows say at which temperature."""
    spec = _spec(tmp_path, "[vary]\ntemperature = [70, 850]\n")
    rows = run_design(spec, tmp_path / "out", workers=1, echo=lambda s: None)
    assert {(r["config"], r["temperature"]) for r in rows} == {("T70", 70.0), ("T850", 850.0)}
    text = (tmp_path / "out" / "configs" / "T850" / "T850.inp").read_text()
    assert "\n   OPERATING 850F\n" in text


@pytest.mark.parametrize(
    ("body", "structure", "message"),
    [
        (
            "[vary]\ntemperature = [70, 1200]\n",
            WC7,
            "configuration T1200: temperature: OPERATING 1200F (the design's temperature): "
            "material 'titanium': 1200 °F is outside its temperature table",
        ),
        ("[vary]\ntemperature = [70, true]\n", WC7, "vary.temperature: expected a temperature"),
        (
            "[vary]\ntemperature = [70, 850]\n",
            ROOT / "decks" / "beam_1.inp",
            "has no TEMPERATURE card",
        ),
    ],
)
def test_a_temperature_the_deck_cannot_take_is_refused_at_its_line(
    tmp_path, capsys, body, structure, message
):
    spec = _spec(tmp_path, body, structure)
    line = refused(
        capsys, "design", spec, "--out", tmp_path / "out", message=message, folder=tmp_path
    )
    number = next(
        k for k, t in enumerate(spec.read_text().splitlines(), 1) if t.startswith("temperature")
    )
    assert line.startswith(f"x3dpd: error: {spec}:{number}: ")
