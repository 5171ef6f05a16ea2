"""``x3dpd materials [NAME...] [--units LENGTH FORCE TIME]``: the material library
(x3dpd.materials) as a table, or one material's values with their sources."""

from __future__ import annotations

import click

from x3dpd.materials import in_units, material, materials
from x3dpd.units import labels_for


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
def materials_command(names: tuple[str, ...], units) -> None:
    """The particle materials x3dpd knows by name (for `x3dpd fill --material NAME`).

    Without NAME: one line per material. With NAMEs: each one's values, aliases and the source
    of every value. mu is the dry sliding friction coefficient against steel (docs/materials.md).
    """
    mats = [material(n) for n in names] if names else materials()
    if units is not None:
        in_units(mats[0], units)  # an unknown unit: a clear error before anything prints
    head, rows = _deck_rows(mats, units) if units else _si_rows(mats)
    if not names:
        click.echo(_table(head, rows))
        return
    for k, (m, row) in enumerate(zip(mats, rows)):
        if k:
            click.echo("")
        click.echo(f"{m.name}: {m.description}")
        if m.aliases:
            click.echo(f"  aliases: {', '.join(m.aliases)}")
        for label, value, field in zip(head[1:], row[1:], ("E", "maxwell", "nu", "rho", "mu")):
            if value == "-":
                continue
            click.echo(f"  {label} = {value}")
            click.echo(f"      source: {m.sources[field]}")
