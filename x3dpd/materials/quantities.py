"""What the material library's readers share: its error and the units a file may give values in.

Every value is converted to SI on reading: moduli to Pa, densities to kg/m^3, coefficients of
thermal expansion to 1/K (x3dpd.materials.temperature_units has the temperature units).
"""

from __future__ import annotations

import math

from x3dpd.errors import InputError

#: Pounds-force in newtons and inches in metres (both exact by definition).
_LBF = 4.4482216152605
_INCH = 0.0254

#: Units a library file may give a modulus in [Pa per unit].
PRESSURE_UNITS = {
    "Pa": 1.0,
    "kPa": 1e3,
    "MPa": 1e6,
    "GPa": 1e9,
    "psi": _LBF / _INCH**2,
    "ksi": 1e3 * _LBF / _INCH**2,
    "Msi": 1e6 * _LBF / _INCH**2,
}
#: Units a library file may give a density in [kg/m^3 per unit]; ``lb/in^3`` is pound-mass
#: (0.45359237 kg) per cubic inch, ``lbf s^2/in^4`` the mass density of an inch-lbf-s deck.
DENSITY_UNITS = {
    "kg/m^3": 1.0,
    "g/cm^3": 1e3,
    "lb/in^3": 0.45359237 / _INCH**3,
    "lbf s^2/in^4": _LBF / _INCH**4,
}
#: Units a library file may give a coefficient of thermal expansion in [1/K per unit]: a
#: coefficient per degF is 9/5 of the same per K (a degF is 5/9 K).
EXPANSION_UNITS = {
    "1/K": 1.0,
    "1/degC": 1.0,
    "1/degF": 1.8,
    "1e-6/K": 1e-6,
    "1e-6/degC": 1e-6,
    "1e-6/degF": 1.8e-6,
}


class MaterialError(InputError):
    """An unknown material name, a malformed library file, or a temperature a material has no
    data at (exit status 2)."""


def finite_number(where: str, what: str, raw) -> float:
    """``raw`` as a float; :class:`MaterialError` naming ``where`` and ``what`` when it is not a
    finite number."""
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or not math.isfinite(raw):
        raise MaterialError(f"{where}: {what} must be a finite number; got {raw!r}")
    return float(raw)


def unit_factor(where: str, what: str, entry: dict, units: dict | None) -> float:
    """The SI factor of ``entry['unit']`` among ``units`` (1.0 for a dimensionless value, which
    must give no unit)."""
    if units is None:
        if "unit" in entry:
            raise MaterialError(f"{where}: {what} is dimensionless: it takes no unit")
        return 1.0
    unit = entry.get("unit")
    if unit not in units:
        raise MaterialError(f"{where}: {what} unit {unit!r}: expected one of {', '.join(units)}")
    return units[unit]


def source_of(where: str, what: str, entry: dict) -> str:
    """``entry['source']``; :class:`MaterialError` when it is missing or blank."""
    source = entry.get("source")
    if not isinstance(source, str) or not source.strip():
        raise MaterialError(f"{where}: {what} has no source")
    return source
