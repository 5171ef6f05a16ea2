"""A material's properties against temperature: the ``[material.NAME.temperature]`` tables.

Each property is a table of values at temperatures, as its source gives them, or a constant:

    E, nu        a table, or a constant ``{ value, source }`` where the source gives no
                 temperature dependence (its source text says so)
    alpha_mean   the mean (secant) coefficient of linear thermal expansion from a reference
                 temperature T0 -- what handbooks tabulate -- or
    alpha        the instantaneous (tangent) coefficient, with the reference T0 at which the
                 strain is zero
    rho          a table, or ``{ from = "expansion", at = T_rho }``: the room-temperature density
                 carried to T by the expansion (below)

Interpolation is piecewise linear in temperature between a table's points: exact at the points,
no overshoot, monotone where the data are (ASME BPVC II-D states linear interpolation between its
tabulated temperatures). Outside a table nothing is extrapolated.

Expansion. With eps(T) = (L(T) - L(T0)) / L(T0) the linear thermal strain from T0:

    mean table:     eps(T) = alpha_mean(T) (T - T0)             alpha_mean interpolated linearly
    tangent table:  eps(T) = integral_T0^T alpha(T') dT'         alpha linear: exact trapezoids
    tangent:        alpha(T) = d eps / dT
                             = alpha_mean(T) + alpha_mean'(T) (T - T0)   (mean table; at a table
                               point the average of the two one-sided slopes)
    mean from T0:   alpha_mean(T) = eps(T) / (T - T0)            (tangent table; alpha(T0) at T0)
    between T1, T2: strain = (L(T2) - L(T1)) / L(T1) = (eps(T2) - eps(T1)) / (1 + eps(T1))
    density:        rho(T) = rho(T_rho) ((1 + eps(T_rho)) / (1 + eps(T)))^3

(the last two are exact for an isotropic solid; with T_rho = T0 the density is the familiar
rho0 / (1 + alpha_mean (T - T0))^3). Temperatures are kelvin and coefficients 1/K throughout.
"""

from __future__ import annotations

import math
from bisect import bisect_right
from dataclasses import dataclass, field

from x3dpd.materials.quantities import (
    DENSITY_UNITS,
    EXPANSION_UNITS,
    PRESSURE_UNITS,
    MaterialError,
    finite_number,
    source_of,
    unit_factor,
)
from x3dpd.materials.temperature_units import TEMPERATURE_UNITS, TemperatureError, to_kelvin

#: Slack [K] on a range's ends, for a temperature converted from another unit.
RANGE_SLACK = 1e-9
#: The keys of a temperature block, and of each kind of entry in it.
BLOCK_KEYS = ("E", "nu", "rho", "alpha_mean", "alpha")
_TABLE_KEYS = {"T_unit", "T", "values", "unit", "source"}
_CONSTANT_KEYS = {"value", "unit", "source"}
_DERIVED_KEYS = {"from", "T_unit", "at", "source"}


@dataclass(frozen=True)
class PropertyTable:
    """Values at temperatures, piecewise linear between them.

    kelvin : the table's temperatures [K], strictly increasing; values : SI values there.
    given_unit : the temperature unit the source gave them in (degF, degC, K).
    """

    kelvin: tuple[float, ...]
    values: tuple[float, ...]
    source: str
    given_unit: str = "K"

    @property
    def low(self) -> float:
        return self.kelvin[0]

    @property
    def high(self) -> float:
        return self.kelvin[-1]

    def segment(self, kelvin: float) -> int:
        """Index k of the segment [T_k, T_k+1] holding ``kelvin`` (the last one at the top)."""
        return min(max(bisect_right(self.kelvin, kelvin) - 1, 0), len(self.kelvin) - 2)

    def slope(self, k: int) -> float:
        """d value / dT on segment k [SI per K]."""
        t, v = self.kelvin, self.values
        return (v[k + 1] - v[k]) / (t[k + 1] - t[k])

    def at(self, kelvin: float) -> float:
        """The value at ``kelvin``: the table's own value at a point, linear between points."""
        kelvin = min(max(kelvin, self.low), self.high)
        k = self.segment(kelvin)
        if kelvin == self.kelvin[k + 1]:
            return self.values[k + 1]
        return self.values[k] + self.slope(k) * (kelvin - self.kelvin[k])


@dataclass(frozen=True)
class ConstantProperty:
    """A value its source gives at one temperature only, held over the material's range."""

    value: float
    source: str
    low: float = -math.inf
    high: float = math.inf

    def at(self, kelvin: float) -> float:
        return self.value


@dataclass(frozen=True)
class Expansion:
    """Linear thermal expansion from a table of mean (``kind="mean"``) or instantaneous
    (``kind="tangent"``) coefficients [1/K] and the reference temperature ``reference`` [K]
    where the strain is zero (module docstring for the equations)."""

    kind: str
    table: PropertyTable
    reference: float
    _integral: tuple[float, ...] = field(default=(), compare=False, repr=False)

    def __post_init__(self):
        if self.kind == "tangent":  # cumulative integral of alpha from the first point
            t, a = self.table.kelvin, self.table.values
            cumulative = [0.0]
            for k in range(len(t) - 1):
                cumulative.append(cumulative[-1] + 0.5 * (a[k] + a[k + 1]) * (t[k + 1] - t[k]))
            object.__setattr__(self, "_integral", tuple(cumulative))

    @property
    def source(self) -> str:
        return self.table.source

    def _from_first_point(self, kelvin: float) -> float:
        table = self.table
        k = table.segment(kelvin)
        t0, a0 = table.kelvin[k], table.values[k]
        return self._integral[k] + 0.5 * (a0 + table.at(kelvin)) * (kelvin - t0)

    def strain(self, kelvin: float) -> float:
        """eps(T) = (L(T) - L(T0)) / L(T0), T0 the reference."""
        if self.kind == "mean":
            return self.table.at(kelvin) * (kelvin - self.reference)
        return self._from_first_point(kelvin) - self._from_first_point(self.reference)

    def tangent(self, kelvin: float) -> float:
        """The instantaneous coefficient d eps / dT [1/K] (at a point of a mean table: the
        average of the two one-sided derivatives)."""
        table = self.table
        if self.kind == "tangent":
            return table.at(kelvin)
        slopes = [table.slope(table.segment(kelvin))]
        k = table.kelvin.index(kelvin) if kelvin in table.kelvin else -1
        if 0 < k < len(table.kelvin) - 1:
            slopes = [table.slope(k - 1), table.slope(k)]
        return table.at(kelvin) + sum(slopes) / len(slopes) * (kelvin - self.reference)

    def mean(self, kelvin: float) -> float:
        """The mean coefficient from the reference to ``kelvin`` [1/K] (the tangent at it)."""
        if self.kind == "mean":
            return self.table.at(kelvin)
        if kelvin == self.reference:
            return self.table.at(kelvin)
        return self.strain(kelvin) / (kelvin - self.reference)


@dataclass(frozen=True)
class DensityFromExpansion:
    """rho(T) = rho_at ((1 + eps(T_at)) / (1 + eps(T)))^3: a room-temperature density
    ``rho_at`` [kg/m^3] quoted at ``at`` [K], carried to T by the expansion."""

    rho_at: float
    at: float
    source: str
    expansion: Expansion

    low = -math.inf
    high = math.inf

    def at_kelvin(self, kelvin: float) -> float:
        ratio = (1.0 + self.expansion.strain(self.at)) / (1.0 + self.expansion.strain(kelvin))
        return self.rho_at * ratio**3


@dataclass(frozen=True)
class TemperatureTables:
    """A material's tables: E [Pa], nu, rho [kg/m^3] and its expansion, valid on
    [low, high] [K] -- where every tabulated property has data."""

    E: PropertyTable | ConstantProperty
    nu: PropertyTable | ConstantProperty
    rho: PropertyTable | DensityFromExpansion
    expansion: Expansion

    @property
    def low(self) -> float:
        return max(p.low for p in (self.E, self.nu, self.rho, self.expansion.table))

    @property
    def high(self) -> float:
        return min(p.high for p in (self.E, self.nu, self.rho, self.expansion.table))

    def covers(self, kelvin: float) -> bool:
        return self.low - RANGE_SLACK <= kelvin <= self.high + RANGE_SLACK

    def density(self, kelvin: float) -> float:
        if isinstance(self.rho, DensityFromExpansion):
            return self.rho.at_kelvin(kelvin)
        return self.rho.at(kelvin)

    def sources(self) -> dict[str, str]:
        return {
            "E": self.E.source,
            "nu": self.nu.source,
            "rho": self.rho.source,
            "alpha": self.expansion.source,
        }


def _kelvins(where: str, what: str, entry: dict, key: str) -> tuple[str, list[float]]:
    unit = entry.get("T_unit")
    if unit not in TEMPERATURE_UNITS:
        raise MaterialError(
            f"{where}: {what} T_unit {unit!r}: expected one of {', '.join(TEMPERATURE_UNITS)}"
        )
    raw = entry.get(key)
    raw = raw if isinstance(raw, list) else [raw]
    try:
        return unit, [to_kelvin(finite_number(where, f"{what} {key}", t), unit) for t in raw]
    except TemperatureError as exc:
        raise MaterialError(f"{where}: {what} {key}: {exc}") from None


def _table(where: str, what: str, entry: dict, units: dict | None, extra=()) -> PropertyTable:
    unknown = set(entry) - _TABLE_KEYS - set(extra)
    if unknown:
        raise MaterialError(
            f"{where}: {what}: unknown key(s) {', '.join(sorted(unknown))}; expected "
            f"{', '.join(sorted(_TABLE_KEYS | set(extra)))}"
        )
    source = source_of(where, what, entry)
    given, kelvin = _kelvins(where, what, entry, "T")
    raw = entry.get("values")
    if not isinstance(raw, list) or len(raw) != len(kelvin) or len(kelvin) < 2:
        raise MaterialError(
            f"{where}: {what}: T and values must be lists of the same length, at least 2"
        )
    if any(b <= a for a, b in zip(kelvin, kelvin[1:])):
        raise MaterialError(f"{where}: {what}: the temperatures T must increase")
    factor = unit_factor(where, what, entry, units)
    values = [finite_number(where, f"{what} values", v) * factor for v in raw]
    return PropertyTable(tuple(kelvin), tuple(values), source, given)


def _property(where: str, what: str, entry, units: dict | None):
    if not isinstance(entry, dict):
        raise MaterialError(f"{where}: {what} must be a table {{ T_unit, T, values, source }}")
    if "value" in entry:
        unknown = set(entry) - _CONSTANT_KEYS
        if unknown:
            raise MaterialError(
                f"{where}: {what}: a constant takes value, unit, source; "
                f"not {', '.join(sorted(unknown))}"
            )
        factor = unit_factor(where, what, entry, units)
        value = finite_number(where, f"{what} value", entry["value"]) * factor
        return ConstantProperty(value, source_of(where, what, entry))
    return _table(where, what, entry, units)


def _expansion(where: str, block: dict) -> Expansion:
    kinds = [k for k in ("alpha_mean", "alpha") if k in block]
    if len(kinds) != 1:
        raise MaterialError(
            f"{where}: give exactly one of alpha_mean (mean coefficient from a reference "
            "temperature, as handbooks tabulate it) or alpha (instantaneous coefficient)"
        )
    what = kinds[0]
    entry = block[what]
    if not isinstance(entry, dict) or "reference" not in entry:
        raise MaterialError(f"{where}: {what} needs its reference temperature (reference = T0)")
    table = _table(where, what, entry, EXPANSION_UNITS, extra=("reference",))
    reference = _kelvins(where, what, entry, "reference")[1][0]
    kind = "mean" if what == "alpha_mean" else "tangent"
    if kind == "tangent" and not table.low <= reference <= table.high:
        raise MaterialError(f"{where}: alpha: the reference must lie within the table's T")
    return Expansion(kind, table, reference)


def _density(where: str, entry, rho_room: float, expansion: Expansion):
    if isinstance(entry, dict) and entry.get("from") == "expansion":
        unknown = set(entry) - _DERIVED_KEYS
        if unknown:
            raise MaterialError(
                f"{where}: rho from expansion takes from, T_unit, at, source; "
                f"not {', '.join(sorted(unknown))}"
            )
        at = _kelvins(where, "rho", entry, "at")[1][0]
        return DensityFromExpansion(rho_room, at, source_of(where, "rho", entry), expansion)
    if isinstance(entry, dict) and "value" in entry:
        raise MaterialError(
            f"{where}: rho cannot be a constant: give a table or "
            '{ from = "expansion", T_unit = ..., at = T, source = ... }'
        )
    return _property(where, "rho", entry, DENSITY_UNITS)


def _values(prop) -> tuple[float, ...]:
    if isinstance(prop, PropertyTable):
        return prop.values
    if isinstance(prop, ConstantProperty):
        return (prop.value,)
    return ()  # a density derived from the expansion


def read_temperature_block(where: str, block, rho_room: float) -> TemperatureTables:
    """The tables of one ``[material.NAME.temperature]`` block; ``rho_room`` [kg/m^3] is the
    material's room-temperature density (for ``rho = { from = "expansion", ... }``). Raises
    :class:`MaterialError` naming ``where`` and the property for anything malformed."""
    where = f"{where}: temperature"
    if not isinstance(block, dict):
        raise MaterialError(f"{where} must be a table of E, nu, rho and alpha_mean or alpha")
    unknown = set(block) - set(BLOCK_KEYS)
    if unknown:
        raise MaterialError(
            f"{where}: unknown key(s) {', '.join(sorted(unknown))}; expected "
            f"{', '.join(BLOCK_KEYS)}"
        )
    missing = [k for k in ("E", "nu", "rho") if k not in block]
    if missing:
        raise MaterialError(f"{where}: missing {', '.join(missing)}")
    expansion = _expansion(where, block)
    tables = TemperatureTables(
        E=_property(where, "E", block["E"], PRESSURE_UNITS),
        nu=_property(where, "nu", block["nu"], None),
        rho=_density(where, block["rho"], rho_room, expansion),
        expansion=expansion,
    )
    if not tables.low < tables.high:
        raise MaterialError(f"{where}: the property tables do not overlap in temperature")
    for name, prop, ok in (
        ("E", tables.E, lambda v: v > 0),
        ("nu", tables.nu, lambda v: 0 < v < 0.5),
        ("rho", tables.rho, lambda v: v > 0),
    ):
        if not all(ok(v) for v in _values(prop)):
            raise MaterialError(f"{where}: {name} has a value no solid has")
    return tables
