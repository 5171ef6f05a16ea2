"""A material at a temperature: its E, nu, rho and thermal expansion from its tables.

>>> from x3dpd.materials import material_at, thermal_strain
>>> ss = material_at("SS-302", "850F", "in lbf s")   # psi, lbf s^2/in^4, alpha per degF
>>> thermal_strain("SS-302", "70F", "850F")           # (L(850 F) - L(70 F)) / L(70 F)

A temperature is a string with its unit (``"850F"``, ``"455C"``, ``"728K"``) or a number in the
convention of the deck's units (degF for inch-lbf-s, degC for metric: temperature_units).

Every property comes from the material's ``temperature`` tables (x3dpd.materials.tables: linear
between table points, nothing extrapolated); a temperature outside them is refused with an error
naming the material and its range. Friction (mu) has no table: the room-temperature value is used
at every temperature, and its source says so. A material without tables (the report's own steels,
lead, brass, ...) is known at room temperature only -- 20 to 25 degC, where handbooks quote it --
and answers there with its nominal values and no expansion.

The tables are their own sources: at room temperature they may differ from the nominal entry
(:func:`x3dpd.materials.material`) by the spread between handbooks (steel-304: 195 GPa in the
ASME table at 70 degF against ASM's nominal 193 GPa); docs/materials.md lists them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from x3dpd.materials.library import Material, material, materials
from x3dpd.materials.quantities import MaterialError
from x3dpd.materials.tables import RANGE_SLACK
from x3dpd.materials.temperature_units import (
    KELVIN_PER_DEGREE,
    format_temperature,
    from_kelvin,
    parse_temperature,
    to_kelvin,
    temperature_unit_for,
)
from x3dpd.materials.units import DeckMaterial, round12, unit_system, in_units

#: Where handbooks quote room-temperature values [K]: 20 to 25 degC.
ROOM = (to_kelvin(20.0, "degC"), to_kelvin(25.0, "degC"))
#: Friction at temperature: what the sources of mu say.
_MU_NOTE = "room-temperature value, used at every temperature (no source tabulates it hot): "


@dataclass(frozen=True)
class MaterialAt:
    """A material at ``kelvin`` [K], in SI: E [Pa], nu, rho [kg/m^3], mu, maxwell (the room
    -temperature arms; only room-temperature materials have any), and its expansion: alpha_mean
    [1/K] the mean coefficient from ``reference`` [K], alpha [1/K] the instantaneous one, strain
    = (L(T) - L(T_ref)) / L(T_ref). The three are None for a room-temperature-only material.
    ``sources``: property name -> where its value comes from."""

    name: str
    kelvin: float
    E: float
    nu: float
    rho: float
    mu: float
    maxwell: tuple[tuple[float, float], ...] = ()
    alpha_mean: float | None = None
    alpha: float | None = None
    reference: float | None = None
    strain: float | None = None
    sources: dict = field(default_factory=dict, compare=False)
    description: str = ""


@dataclass(frozen=True)
class DeckMaterialAt(DeckMaterial):
    """:class:`MaterialAt` in a deck's units (x3dpd.materials.units.DeckMaterial: E, rho,
    maxwell in the deck's system; ``pdmp_fields()``), with the temperatures ``temperature``
    and ``reference`` in ``temperature_unit`` (degF or degC: temperature_unit_for) and the
    coefficients alpha_mean, alpha per degree of that unit."""

    temperature: float
    temperature_unit: str
    alpha_mean: float | None
    alpha: float | None
    reference: float | None
    strain: float | None
    sources: dict = field(compare=False)


def _material(name, library) -> Material:
    return name if isinstance(name, Material) else material(name, library)


def _with_tables(library=None) -> list[str]:
    return [m.name for m in materials(library) if m.temperature is not None]


def temperature_range(name, library=None) -> tuple[float, float]:
    """(low, high) [K] where ``name`` has data: its tables' common range, or 20 to 25 degC
    for a material known at room temperature only."""
    mat = _material(name, library)
    if mat.temperature is None:
        return ROOM
    return mat.temperature.low, mat.temperature.high


def check_temperature(name, kelvin: float, unit: str = "degF", library=None) -> Material:
    """``name``'s material when it has data at ``kelvin``; else :class:`MaterialError`, one
    line naming the material, the temperature and the range (both in ``unit``)."""
    mat = _material(name, library)
    low, high = temperature_range(mat, library)
    if low - RANGE_SLACK <= kelvin <= high + RANGE_SLACK:
        return mat
    span = f"{format_temperature(low, unit)} to {format_temperature(high, unit)}"
    asked = format_temperature(kelvin, unit)
    if mat.temperature is None:
        hot = ", ".join(_with_tables(library))
        raise MaterialError(
            f"material {mat.name!r} has room-temperature values only ({span}), not {asked}; "
            f"materials with temperature tables: {hot}"
        )
    raise MaterialError(f"material {mat.name!r}: {asked} is outside its temperature table, {span}")


def properties_at(name, kelvin: float, library=None, unit: str = "degF") -> MaterialAt:
    """``name`` (a library name or a Material) at ``kelvin`` [K], in SI. ``unit`` is only the
    unit an out-of-range error prints temperatures in."""
    mat = check_temperature(name, kelvin, unit, library)
    tables = mat.temperature
    mu_source = _MU_NOTE + mat.sources["mu"]
    if tables is None:
        sources = {k: f"room-temperature value: {v}" for k, v in mat.sources.items()}
        return MaterialAt(
            name=mat.name,
            kelvin=kelvin,
            E=mat.E,
            nu=mat.nu,
            rho=mat.rho,
            mu=mat.mu,
            maxwell=mat.maxwell,
            sources=sources,
            description=mat.description,
        )
    kelvin = min(max(kelvin, tables.low), tables.high)
    expansion = tables.expansion
    return MaterialAt(
        name=mat.name,
        kelvin=kelvin,
        E=tables.E.at(kelvin),
        nu=tables.nu.at(kelvin),
        rho=tables.density(kelvin),
        mu=mat.mu,
        alpha_mean=expansion.mean(kelvin),
        alpha=expansion.tangent(kelvin),
        reference=expansion.reference,
        strain=expansion.strain(kelvin),
        sources={**tables.sources(), "mu": mu_source},
        description=mat.description,
    )


def _kelvin(temperature, units) -> tuple[float, str]:
    return parse_temperature(temperature, temperature_unit_for(unit_system(units)))


def material_at(name, temperature, units=None, library=None) -> DeckMaterialAt:
    """``name`` at ``temperature`` in a deck's ``units`` (None: inch-lbf-s, as
    :func:`x3dpd.materials.in_units`): E, rho, maxwell in the deck's system, nu, mu, the
    temperatures in its convention (degF or degC) and alpha per degree of it. ``temperature``
    is ``"850F"``, ``"455C"``, ``"728K"`` or a number in that convention. Raises
    :class:`MaterialError` outside the material's tables."""
    system = unit_system(units)
    kelvin, given = _kelvin(temperature, system)
    at = properties_at(name, kelvin, library, unit=given)
    deck = in_units(
        Material(at.name, at.E, at.nu, at.rho, at.mu, at.maxwell, sources=at.sources), system
    )
    unit = temperature_unit_for(system)
    per_degree = KELVIN_PER_DEGREE[unit]  # 1/K -> 1/degree of unit

    def scaled(alpha):
        return None if alpha is None else round12(alpha * per_degree)

    return DeckMaterialAt(
        name=deck.name,
        E=deck.E,
        nu=deck.nu,
        rho=deck.rho,
        mu=deck.mu,
        maxwell=deck.maxwell,
        units=deck.units,
        temperature=round12(from_kelvin(at.kelvin, unit)),
        temperature_unit=unit,
        alpha_mean=scaled(at.alpha_mean),
        alpha=scaled(at.alpha),
        reference=None if at.reference is None else round12(from_kelvin(at.reference, unit)),
        strain=at.strain,
        sources=at.sources,
    )


def thermal_strain(name, temperature_from, temperature_to, units=None, library=None) -> float:
    """The linear strain of ``name`` from ``temperature_from`` to ``temperature_to``:
    (L(T2) - L(T1)) / L(T1) = (eps(T2) - eps(T1)) / (1 + eps(T1)), eps the strain from the
    table's reference (tables module). A radius R at T1 is R (1 + strain) at T2. Temperatures as
    in :func:`material_at`. A room-temperature-only material has no expansion: 0.0 from a
    temperature to itself, else :class:`MaterialError`."""
    system = unit_system(units)
    (k1, u1), (k2, u2) = _kelvin(temperature_from, system), _kelvin(temperature_to, system)
    mat = check_temperature(name, k1, u1, library)
    check_temperature(mat, k2, u2, library)
    if mat.temperature is None:
        if abs(k2 - k1) <= RANGE_SLACK:
            return 0.0
        raise MaterialError(
            f"material {mat.name!r} has no expansion data (room-temperature values only): "
            f"no strain from {format_temperature(k1, u1)} to {format_temperature(k2, u2)}"
        )
    expansion = mat.temperature.expansion
    eps1, eps2 = expansion.strain(k1), expansion.strain(k2)
    return (eps2 - eps1) / (1.0 + eps1)


def mean_expansion(name, temperature_from, temperature_to, units=None, library=None) -> float:
    """The mean coefficient between two temperatures, per degree of the deck's convention
    (degF for inch-lbf-s): thermal_strain / (T2 - T1); at T1 = T2 the instantaneous one,
    referred to the length at T1."""
    system = unit_system(units)
    unit = temperature_unit_for(system)
    k1, k2 = _kelvin(temperature_from, system)[0], _kelvin(temperature_to, system)[0]
    if abs(k2 - k1) > RANGE_SLACK:
        strain = thermal_strain(name, temperature_from, temperature_to, system, library)
        return strain / ((k2 - k1) / KELVIN_PER_DEGREE[unit])
    at = properties_at(name, k1, library, unit=unit)
    if at.alpha is None:
        raise MaterialError(f"material {at.name!r} has no expansion data")
    return at.alpha / (1.0 + at.strain) * KELVIN_PER_DEGREE[unit]
