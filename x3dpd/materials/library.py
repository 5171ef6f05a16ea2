"""The material library: :class:`Material` and the reader of its TOML file.

``library.toml`` beside this module holds the report's particle materials and common damper ones
(E, nu, rho, mu and Maxwell arms), each value with its source; its header says what each field
means. A user's own file in the same format is read by :func:`read_library`.

Every value is stored in SI (E [Pa], rho [kg/m^3], tau [s]); :func:`x3dpd.materials.in_units`
turns a material into a deck's unit system.
"""

from __future__ import annotations

import difflib
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from x3dpd.materials.quantities import (
    DENSITY_UNITS,
    PRESSURE_UNITS,
    MaterialError,
    finite_number,
    source_of,
    unit_factor,
)
from x3dpd.materials.tables import TemperatureTables, read_temperature_block

#: The library shipped with x3dpd.
LIBRARY = Path(__file__).with_name("library.toml")

#: Fields every material must give, and the optional ones.
REQUIRED = ("E", "nu", "rho", "mu")
OPTIONAL = ("maxwell", "restitution", "description", "aliases", "temperature")


@dataclass(frozen=True)
class Material:
    """One particle material, in SI.

    name : the library key (``tungsten-carbide``); aliases : other names it answers to.
    E : Young's modulus [Pa]; for a viscoelastic material the long-time modulus E0 of the
        report's Maxwell model (Section 7.2.3, Eq. 8): E(t) = E + sum_k E_k exp(-t / tau_k).
    nu : Poisson's ratio. rho : mass density [kg/m^3].
    mu : Coulomb friction coefficient, dry sliding, against steel (the usual cavity wall;
        x3dpd uses one PCOF for particle-particle and particle-wall contact, Section 7.2.4).
    maxwell : Maxwell arms ((E_k [Pa], tau_k [s]), ...); empty for an elastic material.
    restitution : normal coefficient of restitution where a source gives one, else None.
    sources : field name ("E", "nu", "rho", "mu", "maxwell", ...) -> where its value comes from.
    description : what the material is (alloy, grade, temper).
    temperature : its tables against temperature (E, nu, rho, expansion; x3dpd.materials.
        tables), or None for a material known at room temperature only.
    """

    name: str
    E: float
    nu: float
    rho: float
    mu: float
    maxwell: tuple[tuple[float, float], ...] = ()
    restitution: float | None = None
    sources: Mapping[str, str] = field(default_factory=dict, compare=False)
    aliases: tuple[str, ...] = ()
    description: str = ""
    temperature: TemperatureTables | None = field(default=None, compare=False, repr=False)

    @property
    def instantaneous_E(self) -> float:
        """E(0) = E + sum_k E_k [Pa]: the modulus a short impact sees."""
        return self.E + sum(e for e, _ in self.maxwell)

    @property
    def viscoelastic(self) -> bool:
        return bool(self.maxwell)


def _key(name: str) -> str:
    """A name as looked up: lower case, without spaces, hyphens, underscores, dots."""
    return re.sub(r"[\s_\-.]+", "", str(name).lower())


def _si(where: str, name: str, entry, units: dict | None) -> tuple[float, str]:
    """(value in SI, source) of one ``{ value, unit, source }`` table."""
    if not isinstance(entry, dict):
        raise MaterialError(f"{where}: {name} must be a table {{ value = ..., source = ... }}")
    unknown = set(entry) - {"value", "unit", "source"}
    if unknown:
        raise MaterialError(
            f"{where}: {name}: unknown key(s) {', '.join(sorted(unknown))}; "
            "expected value, unit, source"
        )
    source = source_of(where, name, entry)
    value = finite_number(where, f"{name} value", entry.get("value"))
    return value * unit_factor(where, name, entry, units), source


def _maxwell(where: str, raw) -> tuple[tuple[tuple[float, float], ...], str]:
    if not isinstance(raw, list):
        raise MaterialError(f"{where}: maxwell must be a list of {{ E, unit, tau, source }}")
    arms, sources = [], []
    for k, arm in enumerate(raw, 1):
        if not isinstance(arm, dict) or set(arm) != {"E", "unit", "tau", "source"}:
            raise MaterialError(
                f"{where}: maxwell arm {k} must give exactly E, unit, tau [s], source"
            )
        e, src = _si(
            where,
            f"maxwell arm {k} E",
            {"value": arm["E"], "unit": arm["unit"], "source": arm["source"]},
            PRESSURE_UNITS,
        )
        tau = finite_number(where, f"maxwell arm {k} tau", arm["tau"])
        if not (e > 0 and tau > 0):
            raise MaterialError(f"{where}: maxwell arm {k}: E and tau must be positive")
        arms.append((e, tau))
        sources.append(src)
    return tuple(arms), "; ".join(sources)


def _material(where: str, key: str, table) -> Material:
    if not isinstance(table, dict):
        raise MaterialError(f"{where}: must be a table of fields")
    unknown = set(table) - set(REQUIRED) - set(OPTIONAL)
    if unknown:
        raise MaterialError(
            f"{where}: unknown field(s) {', '.join(sorted(unknown))}; expected "
            f"{', '.join(REQUIRED + OPTIONAL)}"
        )
    missing = [f for f in REQUIRED if f not in table]
    if missing:
        raise MaterialError(f"{where}: missing {', '.join(missing)}")
    sources = {}
    e, sources["E"] = _si(where, "E", table["E"], PRESSURE_UNITS)
    rho, sources["rho"] = _si(where, "rho", table["rho"], DENSITY_UNITS)
    nu, sources["nu"] = _si(where, "nu", table["nu"], None)
    mu, sources["mu"] = _si(where, "mu", table["mu"], None)
    arms: tuple = ()
    if "maxwell" in table:
        arms, sources["maxwell"] = _maxwell(where, table["maxwell"])
    restitution = None
    if "restitution" in table:
        restitution, sources["restitution"] = _si(where, "restitution", table["restitution"], None)
    aliases = table.get("aliases", [])
    if not (isinstance(aliases, list) and all(isinstance(a, str) for a in aliases)):
        raise MaterialError(f"{where}: aliases must be a list of names")
    tables = None
    if "temperature" in table:
        if arms:
            raise MaterialError(
                f"{where}: a viscoelastic material cannot have a temperature table "
                "(its Maxwell arms have no data at temperature)"
            )
        tables = read_temperature_block(where, table["temperature"], rho)
    return Material(
        name=key,
        E=e,
        nu=nu,
        rho=rho,
        mu=mu,
        maxwell=arms,
        restitution=restitution,
        sources=sources,
        aliases=tuple(aliases),
        description=str(table.get("description", "")),
        temperature=tables,
    )


def read_library(path=LIBRARY) -> tuple[Material, ...]:
    """Every material of a library file, in file order. Raises :class:`MaterialError` naming
    the file and the material when the file is malformed or a value lacks its source."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except OSError as exc:
        raise MaterialError(f"{path}: cannot read the material library: {exc.strerror}") from None
    except tomllib.TOMLDecodeError as exc:
        raise MaterialError(f"{path}: not a TOML file: {exc}") from None
    table = data.get("material")
    if not isinstance(table, dict) or set(data) != {"material"}:
        raise MaterialError(f"{path}: expected only [material.NAME] tables")
    out = [_material(f"{path}: material {key!r}", key, t) for key, t in table.items()]
    seen: dict[str, str] = {}
    for m in out:
        for name in (m.name, *m.aliases):
            other = seen.setdefault(_key(name), m.name)
            if other != m.name:
                raise MaterialError(
                    f"{path}: the name {name!r} of material {m.name!r} is "
                    f"already material {other!r}'s"
                )
    return tuple(out)


@lru_cache(maxsize=8)
def _library(path: str) -> tuple[Material, ...]:
    return read_library(path)


def materials(library=None) -> list[Material]:
    """The materials of ``library`` (a file path; default: the shipped library.toml)."""
    return list(_library(str(library or LIBRARY)))


def material(name, library=None) -> Material:
    """The material called ``name`` (its key or an alias; case, spaces, hyphens and underscores
    do not matter). A :class:`Material` is returned as it is. An unknown name raises
    :class:`MaterialError` listing the closest names."""
    if isinstance(name, Material):
        return name
    every = materials(library)
    names = {}
    for m in every:
        for n in (m.name, *m.aliases):
            names[_key(n)] = m
    hit = names.get(_key(name))
    if hit is not None:
        return hit
    close = difflib.get_close_matches(_key(name), list(names), n=5, cutoff=0.5)
    suggest = sorted({names[c].name for c in close})
    hint = (
        f"did you mean {', '.join(suggest)}?"
        if suggest
        else f"known: {', '.join(m.name for m in every)}"
    )
    raise MaterialError(f"unknown material {name!r}: {hint} (`x3dpd materials` lists them)")
