"""``x3dpd materials [NAME...] [--units LENGTH FORCE TIME] [--temperature T]``: the material
library (x3dpd.materials) as a table, one material's values with their sources, or a material at
a temperature from its tables."""

from __future__ import annotations

import click

from x3dpd.materials import (
    TEMPERATURE_SYMBOL,
    format_temperature,
    in_units,
    material,
    material_at,
    materials,
    parse_temperature,
    properties_at,
    temperature_range,
    temperature_unit_for,
    thermal_strain,
)
from x3dpd.materials.tables import RANGE_SLACK
from x3dpd.units import labels_for

#: The assembly temperature the strain is printed from (the TEMPERATURE card's default).
ASSEMBLY = "70F"


def _range(m, unit: str) -> str:
    low, high = temperature_range(m)
    span = f"{format_temperature(low, unit)} to {format_temperature(high, unit)}"
    return span if m.temperature is not None else f"room temperature only ({span})"


def _short_range(m, unit: str) -> str:
    if m.temperature is None:
        return "room"
    low, high = temperature_range(m)
    return "..".join(format_temperature(k, unit).split()[0] for k in (low, high))


def _si_rows(mats) -> tuple[list[str], list[list[str]]]:
    head = ["name", "E [GPa]", "Maxwell E_k [GPa] / tau_k [s]", "nu", "rho [kg/m^3]", "mu"]
    rows = [
        [
            m.name,
            f"{m.E / 1e9:.4g}",
            ", ".join(f"{e / 1e9:.4g} / {t:.3g}" for e, t in m.maxwell) or "-",
            f"{m.nu:.3g}",
            f"{m.rho:.5g}",
            f"{m.mu:.2f}",
        ]
        for m in mats
    ]
    return head, rows


def _deck_rows(mats, units) -> tuple[list[str], list[list[str]]]:
    lab = labels_for(in_units(mats[0], units).units)
    arms = f"Maxwell E_k [{lab['pressure']}] / tau_k [{lab['time']}]"
    head = ["name", f"E0 [{lab['pressure']}]", arms, "nu", f"rho [{lab['density']}]", "mu"]
    rows = []
    for m in mats:
        d = in_units(m, units)
        rows.append(
            [
                m.name,
                f"{d.E:.6g}",
                ", ".join(f"{e:.6g} / {t:.3g}" for e, t in d.maxwell) or "-",
                f"{d.nu:.3g}",
                f"{d.rho:.6g}",
                f"{d.mu:.2f}",
            ]
        )
    return head, rows


def _table(head, rows) -> str:
    width = [max(len(r[k]) for r in [head] + rows) for k in range(len(head))]

    def line(row):
        return "  ".join(c.ljust(w) for c, w in zip(row, width)).rstrip()

    return "\n".join([line(head), line(["-" * w for w in width])] + [line(r) for r in rows])


def _labels(units) -> dict[str, str]:
    """Units of the printed values: SI (GPa, kg/m^3, 1e-6/K) or the deck's."""
    if units is None:
        return {"E": "GPa", "rho": "kg/m^3", "alpha": "1e-6/K"}
    lab = labels_for(in_units("steel-304", units).units)
    per = f"1e-6/{TEMPERATURE_SYMBOL[temperature_unit_for(units)]}"
    return {"E": lab["pressure"], "rho": lab["density"], "alpha": per}


def _at_temperature(name: str, text: str, units) -> list[str]:
    """The lines of ``name`` at temperature ``text`` (raises before anything prints)."""
    deck_unit = temperature_unit_for(units)
    kelvin, given = parse_temperature(text, deck_unit)
    si = properties_at(name, kelvin, unit=given)
    deck = material_at(name, text, units)
    lab = _labels(units)
    e, rho = (si.E * 1e-9, si.rho) if units is None else (deck.E, deck.rho)
    mean, tangent = (si.alpha_mean, si.alpha) if units is None else (deck.alpha_mean, deck.alpha)
    m = material(name)
    kelvins = "" if given == "K" else f" ({format_temperature(kelvin, 'K')})"
    out = [
        f"{si.name} at {format_temperature(kelvin, given)}{kelvins}: {si.description}",
        f"  temperature data: {_range(m, given)}",
        f"  E [{lab['E']}] = {e:.6g}",
        f"      source: {si.sources['E']}",
        f"  nu = {si.nu:.4g}",
        f"      source: {si.sources['nu']}",
        f"  rho [{lab['rho']}] = {rho:.6g}",
        f"      source: {si.sources['rho']}",
    ]
    if si.alpha is not None:
        reference = format_temperature(si.reference, given)
        out += [
            f"  alpha_mean [{lab['alpha']}] from {reference} = {mean * 1e6:.4g}",
            f"  alpha, instantaneous [{lab['alpha']}] = {tangent * 1e6:.4g}",
            f"  thermal strain from {reference} = {si.strain:.6g}",
            f"      source: {si.sources['alpha']}",
        ]
        assembly = parse_temperature(ASSEMBLY)[0]
        if m.temperature.covers(assembly):
            strain = thermal_strain(name, ASSEMBLY, text, units)
            out.append(
                f"  thermal strain from {format_temperature(assembly, given)} "
                f"(assembly) = {strain:.6g}"
            )
    else:
        out.append("  no expansion data (room-temperature values only)")
    out += [f"  mu = {si.mu:.2f}", f"      source: {si.sources['mu']}"]
    return out


@click.command("materials")
@click.argument("names", nargs=-1, metavar="[NAME]...")
@click.option(
    "--units",
    nargs=3,
    default=None,
    metavar="LENGTH FORCE TIME",
    help="Show the values in a deck's unit system, e.g. `--units in lbf s` (the "
    "report's decks: psi, lbf s^2/in^4) or `--units mm N s` (default: GPa, kg/m^3).",
)
@click.option(
    "--temperature",
    "temperature",
    default=None,
    metavar="T",
    help="Show the values at T from the material's tables: 850F, 455C, 728K, or a bare "
    "number in the deck's convention (degF for inch and foot units, the default; degC for "
    "metric --units). A T outside a material's tables is an error naming its range.",
)
def materials_command(names: tuple[str, ...], units, temperature) -> None:
    """The particle materials x3dpd knows by name (for `x3dpd fill --material NAME`).

    Without NAME: one line per material, with the temperatures it has data at. With NAMEs:
    each one's values, aliases and the source of every value, and its temperature range. With
    --temperature T: the values at T (E, nu, rho, the mean and instantaneous coefficients of
    thermal expansion, the strain from 70 F) with their sources. mu is the dry sliding friction
    coefficient against steel (docs/materials.md).
    """
    mats = [material(n) for n in names] if names else materials()
    if units is not None:
        in_units(mats[0], units)  # an unknown unit: a clear error before anything prints
    unit = temperature_unit_for(units)
    if temperature is not None:
        _print_at_temperature(names, mats, temperature, units)
        return
    head, rows = _deck_rows(mats, units) if units else _si_rows(mats)
    if not names:
        head.append(f"T range [{TEMPERATURE_SYMBOL[unit]}]")
        for row, m in zip(rows, mats):
            row.append(_short_range(m, unit))
        click.echo(_table(head, rows))
        return
    for k, (m, row) in enumerate(zip(mats, rows)):
        if k:
            click.echo("")
        click.echo(f"{m.name}: {m.description}")
        if m.aliases:
            click.echo(f"  aliases: {', '.join(m.aliases)}")
        click.echo(f"  temperature data: {_range(m, unit)}")
        for label, value, field in zip(head[1:], row[1:], ("E", "maxwell", "nu", "rho", "mu")):
            if value == "-":
                continue
            click.echo(f"  {label} = {value}")
            click.echo(f"      source: {m.sources[field]}")


def _print_at_temperature(names, mats, temperature: str, units) -> None:
    if names:
        blocks = [_at_temperature(m.name, temperature, units) for m in mats]
        click.echo("\n\n".join("\n".join(b) for b in blocks))
        return
    kelvin, given = parse_temperature(temperature, temperature_unit_for(units))
    lab = _labels(units)
    head = ["name", f"E [{lab['E']}]", "nu", f"rho [{lab['rho']}]", f"alpha_mean [{lab['alpha']}]"]
    head += ["reference", "strain from reference"]
    rows, without = [], []
    for m in mats:
        low, high = temperature_range(m)
        if not low - RANGE_SLACK <= kelvin <= high + RANGE_SLACK:
            without.append(m.name)
            continue
        si = properties_at(m, kelvin, unit=given)
        d = material_at(m, temperature, units)
        e, rho = (si.E * 1e-9, si.rho) if units is None else (d.E, d.rho)
        alpha = si.alpha_mean if units is None else d.alpha_mean
        expanding = si.alpha is not None
        rows.append(
            [
                m.name,
                f"{e:.6g}",
                f"{si.nu:.4g}",
                f"{rho:.6g}",
                f"{alpha * 1e6:.4g}" if expanding else "-",
                format_temperature(si.reference, given).replace(" ", "") if expanding else "-",
                f"{si.strain:.5g}" if expanding else "-",
            ]
        )
    click.echo(f"at {format_temperature(kelvin, given)}:")
    click.echo(_table(head, rows))
    if without:
        click.echo(f"no data at {format_temperature(kelvin, given)}: {', '.join(without)}")
