"""Temperature units (x3dpd.materials.temperature_units): degF, degC and K against the fixed
points of the scales, round trips, the typed forms a user may give and the refusals."""

from __future__ import annotations

import pytest

from x3dpd.materials import (
    TemperatureError,
    format_temperature,
    from_kelvin,
    parse_temperature,
    temperature_unit_for,
    to_kelvin,
)


@pytest.mark.parametrize(
    ("value", "unit", "kelvin"),
    [
        (32.0, "degF", 273.15),  # water freezes
        (212.0, "degF", 373.15),  # water boils
        (-40.0, "degF", 233.15),  # -40 F = -40 C
        (-459.67, "degF", 0.0),  # absolute zero
        (0.0, "degC", 273.15),
        (-40.0, "degC", 233.15),
        (100.0, "degC", 373.15),
        (728.0, "K", 728.0),
    ],
)
def test_fixed_points(value, unit, kelvin):
    assert to_kelvin(value, unit) == pytest.approx(kelvin, abs=1e-12)
    assert from_kelvin(kelvin, unit) == pytest.approx(value, abs=1e-12)


@pytest.mark.parametrize("value", [-94.0, 70.0, 365.0, 850.0, 1200.0])
def test_round_trips_f_c_k(value):
    """F -> K -> C -> K -> F returns the value; 1 degF is 5/9 K."""
    kelvin = to_kelvin(value, "degF")
    celsius = from_kelvin(kelvin, "degC")
    assert celsius == pytest.approx((value - 32.0) * 5.0 / 9.0, abs=1e-12)
    assert from_kelvin(to_kelvin(celsius, "degC"), "degF") == pytest.approx(value, abs=1e-12)
    assert to_kelvin(value + 9.0, "degF") - kelvin == pytest.approx(5.0, abs=1e-12)


def test_typed_temperatures():
    f850 = (850.0 - 32.0) * 5.0 / 9.0 + 273.15
    for text in ("850F", "850 F", "850f", "850degF", "850 °F", "+850F", "8.5e2F"):
        assert parse_temperature(text) == (pytest.approx(f850, abs=1e-12), "degF"), text
    assert parse_temperature("455C") == (pytest.approx(728.15, abs=1e-12), "degC")
    assert parse_temperature("-94 degC") == (pytest.approx(179.15, abs=1e-12), "degC")
    assert parse_temperature("728K") == (728.0, "K")
    assert parse_temperature("728k") == (728.0, "K")
    # a bare number: the default unit (the deck's convention), numbers as numbers
    assert parse_temperature("850") == (pytest.approx(f850, abs=1e-12), "degF")
    assert parse_temperature("455", "degC") == (pytest.approx(728.15, abs=1e-12), "degC")
    assert parse_temperature(455, "degC") == (pytest.approx(728.15, abs=1e-12), "degC")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("85OF", "expected a number with a unit F, C or K"),
        ("850X", "expected a number with a unit F, C or K"),
        ("hot", "expected a number with a unit F, C or K"),
        ("", "expected a number with a unit F, C or K"),
        ("850 F C", "expected a number with a unit F, C or K"),
        ("-500F", "-500 °F is below absolute zero"),
        ("-1K", "below absolute zero"),
    ],
)
def test_bad_temperatures_are_one_line_errors(text, message):
    with pytest.raises(TemperatureError, match=message) as info:
        parse_temperature(text)
    assert "\n" not in str(info.value)


def test_the_decks_convention():
    """Bare numbers: degF for inch and foot decks (the report's), degC for metric ones."""
    assert temperature_unit_for(None) == "degF"
    assert temperature_unit_for(("in", "lbf", "s")) == "degF"
    assert temperature_unit_for(("ft", "lbf", "s")) == "degF"
    for length in ("m", "cm", "mm"):
        assert temperature_unit_for((length, "N", "s")) == "degC"


def test_printing():
    assert format_temperature(to_kelvin(850, "degF"), "degF") == "850 °F"
    assert format_temperature(200.0, "degF") == "-99.67 °F"
    assert format_temperature(273.15, "degC") == "0 °C"
    assert format_temperature(273.1499999, "degC") == "0 °C"
    assert format_temperature(293.15, "K") == "293.15 K"
