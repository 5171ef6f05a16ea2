"""Temperatures: the units a material table or a user may give one in, and their conversions.

Three units, named as the library file names them: ``degF`` (Fahrenheit), ``degC`` (Celsius)
and ``K`` (kelvin). Every temperature is held in kelvin inside x3dpd::

    T [K] = T [degC] + 273.15 = (T [degF] - 32) * 5/9 + 273.15      (exact by definition)

A temperature difference of 1 degF is 5/9 K, so a coefficient per degF is 5/9 of the same
coefficient per K (1e-6/degF = 1.8e-6/K).

A temperature typed by a user (``x3dpd materials NAME --temperature T``) is a number with a unit
suffix -- ``850F``, ``850 degF``, ``455C``, ``728K`` -- or a bare number, read in the convention of
the deck's unit system (:func:`temperature_unit_for`): degF for inch and foot decks (the report's
convention), degC for metric ones.
"""

from __future__ import annotations

import math
import re

from x3dpd.materials.quantities import MaterialError
from x3dpd.units import DEFAULT

#: Units of temperature, by the name a library file uses.
TEMPERATURE_UNITS = ("degF", "degC", "K")
#: How each unit is printed.
SYMBOL = {"degF": "°F", "degC": "°C", "K": "K"}
#: Kelvin per degree of each unit (for coefficients and differences).
KELVIN_PER_DEGREE = {"degF": 5.0 / 9.0, "degC": 1.0, "K": 1.0}
#: Absolute zero [K] less a hair, the lowest temperature anything may be given at.
_ABSOLUTE_ZERO = -1e-9

_SUFFIX = {
    "f": "degF",
    "°f": "degF",
    "degf": "degF",
    "c": "degC",
    "°c": "degC",
    "degc": "degC",
    "k": "K",
}
_TYPED = re.compile(
    r"^\s*(?P<number>[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(?P<unit>[°a-zA-Z]*)\s*$"
)


class TemperatureError(MaterialError):
    """A temperature that cannot be read or is below absolute zero (exit status 2)."""


def _unit(unit: str) -> str:
    if unit not in TEMPERATURE_UNITS:
        raise TemperatureError(
            f"temperature unit {unit!r}: expected one of {', '.join(TEMPERATURE_UNITS)}"
        )
    return unit


def to_kelvin(value: float, unit: str) -> float:
    """``value`` in ``unit`` (degF, degC, K) as kelvin. Raises :class:`TemperatureError`
    below absolute zero."""
    unit = _unit(unit)
    if unit == "degF":
        kelvin = (value - 32.0) * 5.0 / 9.0 + 273.15
    elif unit == "degC":
        kelvin = value + 273.15
    else:
        kelvin = float(value)
    if not math.isfinite(kelvin) or kelvin < _ABSOLUTE_ZERO:
        raise TemperatureError(
            f"temperature {value:g} {SYMBOL[unit]} is below absolute zero (0 K = -459.67 °F)"
        )
    return kelvin


def from_kelvin(kelvin: float, unit: str) -> float:
    """``kelvin`` in ``unit`` (degF, degC, K): the inverse of :func:`to_kelvin`."""
    unit = _unit(unit)
    if unit == "degF":
        return (kelvin - 273.15) * 9.0 / 5.0 + 32.0
    if unit == "degC":
        return kelvin - 273.15
    return float(kelvin)


def temperature_unit_for(units=None) -> str:
    """The unit a bare temperature is read in for a deck in ``units`` = (length, force, time) or
    None (inch-lbf-s): ``degF`` for inch and foot systems (the report's convention), ``degC``
    for metric ones (m, cm, mm)."""
    length = (tuple(units) if units else DEFAULT)[0]
    return "degF" if length in ("in", "ft") else "degC"


def parse_temperature(text, default_unit: str = "degF") -> tuple[float, str]:
    """``(kelvin, unit)`` of a typed temperature: a number with a suffix F, degF, °F, C, degC, °C
    or K (any case), or a bare number taken in ``default_unit``. ``unit`` is the one the value
    was given in (for printing it back). Numbers are taken as they are. Raises
    :class:`TemperatureError` with a one-line message."""
    if isinstance(text, bool):
        raise TemperatureError(f"temperature {text!r}: expected a number with a unit")
    if isinstance(text, (int, float)):
        return to_kelvin(float(text), default_unit), _unit(default_unit)
    match = _TYPED.match(str(text))
    unit = _SUFFIX.get(match.group("unit").lower()) if match else None
    if match is None or (match.group("unit") and unit is None):
        raise TemperatureError(
            f"temperature {str(text)!r}: expected a number with a unit F, C or K "
            "(e.g. 850F, 455C, 728K) or a bare number"
        )
    unit = unit or _unit(default_unit)
    return to_kelvin(float(match.group("number")), unit), unit


def format_temperature(kelvin: float, unit: str) -> str:
    """``kelvin`` in ``unit``, to 0.01 degree, with its symbol: ``"850 °F"``, ``"-99.67 °F"``."""
    text = f"{from_kelvin(kelvin, unit):.2f}".rstrip("0").rstrip(".")
    return f"{'0' if text == '-0' else text} {SYMBOL[unit]}"
