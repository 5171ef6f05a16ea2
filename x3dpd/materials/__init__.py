"""Particle materials by name: the report's and common damper ones, every value with its source.

>>> from x3dpd.materials import material, in_units
>>> wc = material("tungsten carbide")          # Material, SI: E [Pa], rho [kg/m^3]
>>> in_units(wc, "in lbf s").E                 # psi, for a deck in the report's units
>>> material_at("SS-302", "850F", "in lbf s")   # at temperature: E, nu, rho, alpha (tables)
>>> thermal_strain("SS-302", "70F", "850F")     # (L(850 F) - L(70 F)) / L(70 F)

The library is ``library.toml`` beside this module (docs/materials.md). This package is at the
bottom of x3dpd's layers: it imports nothing of x3dpd but ``errors`` and ``units``. Materials at
temperature: ``tables`` (the tables and their equations), ``at_temperature`` (the functions),
``temperature_units`` (degF, degC, K).
"""

from x3dpd.materials.at_temperature import (
    ROOM,
    DeckMaterialAt,
    MaterialAt,
    check_temperature,
    material_at,
    mean_expansion,
    properties_at,
    temperature_range,
    thermal_strain,
)
from x3dpd.materials.library import (
    LIBRARY,
    Material,
    MaterialError,
    material,
    materials,
    read_library,
)
from x3dpd.materials.temperature_units import (
    SYMBOL as TEMPERATURE_SYMBOL,
)
from x3dpd.materials.temperature_units import (
    TEMPERATURE_UNITS,
    TemperatureError,
    format_temperature,
    from_kelvin,
    parse_temperature,
    temperature_unit_for,
    to_kelvin,
)
from x3dpd.materials.units import DeckMaterial, in_units

__all__ = [
    "LIBRARY",
    "ROOM",
    "TEMPERATURE_SYMBOL",
    "TEMPERATURE_UNITS",
    "DeckMaterial",
    "DeckMaterialAt",
    "Material",
    "MaterialAt",
    "MaterialError",
    "TemperatureError",
    "check_temperature",
    "format_temperature",
    "from_kelvin",
    "in_units",
    "material",
    "material_at",
    "materials",
    "mean_expansion",
    "parse_temperature",
    "properties_at",
    "read_library",
    "temperature_range",
    "temperature_unit_for",
    "thermal_strain",
    "to_kelvin",
]
