"""Particle materials by name: the report's and common damper ones, every value with its source.

>>> from x3dpd.materials import material, in_units
>>> wc = material("tungsten carbide")          # Material, SI: E [Pa], rho [kg/m^3]
>>> in_units(wc, "in lbf s").E                 # psi, for a deck in the report's units

The library is ``library.toml`` beside this module (docs/materials.md). This package is at the
bottom of x3dpd's layers: it imports nothing of x3dpd but ``errors`` and ``units``.
"""

from x3dpd.materials.library import (
    LIBRARY,
    Material,
    MaterialError,
    material,
    materials,
    read_library,
)
from x3dpd.materials.units import DeckMaterial, in_units

__all__ = [
    "LIBRARY",
    "DeckMaterial",
    "Material",
    "MaterialError",
    "in_units",
    "material",
    "materials",
    "read_library",
]
