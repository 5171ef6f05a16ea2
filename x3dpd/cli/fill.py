"""``x3dpd fill TEMPLATE.inp --n N --radius R --packing cubic|hcp|random [--material NAME]
[--dt DT | --keep-dt] -o OUT.inp``, or ``x3dpd fill TEMPLATE.inp --plates SPEC [--plates
SPEC ...] [--radius R] [--material NAME] -o OUT.inp``: a multiple individual particle damper's
drilled plates, one sphere per hole (the PLATES card, x3dpd.deck.plates).

The deck written gets the time step its particles need (x3dpd.api.fit_time_step: the step
``x3dpd check`` recommends) unless ``--dt`` gives one or ``--keep-dt`` keeps the template's.
"""

from __future__ import annotations

import math

import click

from x3dpd.api.decks import PACKINGS, fill_positions, filled_deck
from x3dpd.cli.outputs import refuse_existing
from x3dpd.errors import InputError


class _SettleTime(click.ParamType):
    """``--settle``: a time > 0 [s] or ``auto``."""

    name = "T|auto"

    def convert(self, value, param, ctx):
        if isinstance(value, float) or value == "auto":
            return value
        try:
            t = float(value)
        except ValueError:
            t = math.nan
        if not t > 0.0 or math.isinf(t):
            self.fail(f"{value!r}: expected a time > 0 [s] or auto", param, ctx)
        return t


# Over 80 lines: a click command: its options' checks and the one call to the fill API.
@click.command("fill")
@click.argument("template", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--n",
    "n",
    type=click.IntRange(min=1),
    default=None,
    help="Number of particles (default: as many as fit).",
)
@click.option(
    "--radius",
    type=click.FloatRange(min=0.0, min_open=True),
    default=None,
    help="Particle radius [length] (default: the template's PDMP RZERO).",
)
@click.option("--packing", type=click.Choice(PACKINGS), default="cubic", show_default=True)
@click.option(
    "--gap",
    type=click.FloatRange(min=0.0),
    default=0.0,
    show_default=True,
    help="Clearance to the walls and between lattice neighbours [length].",
)
@click.option("--seed", type=int, default=None, help="Seed of the random packing / jitter.")
@click.option(
    "--jitter",
    type=click.FloatRange(0.0, 1.0),
    default=0.0,
    show_default=True,
    help="Box + cubic: move coordinates by up to JITTER x gap / 2.",
)
@click.option(
    "--material",
    default=None,
    metavar="NAME",
    help="Particle material from the library (`x3dpd materials`): sets the PDMP "
    "card's density, Poisson's ratio, E0, E1, T1 and friction (default: the "
    "template's).",
)
@click.option(
    "--dt",
    type=click.FloatRange(min=0.0, min_open=True),
    default=None,
    metavar="DT",
    help="Time step DTMAX [s] (default: the step `x3dpd check` recommends for the new particles).",
)
@click.option("--keep-dt", is_flag=True, help="Keep the template's DTMAX and ITRAC.")
@click.option(
    "--set", "set_id", type=int, default=None, help="CONTACT set to fill (default: the first)."
)
@click.option(
    "--settle",
    type=_SettleTime(),
    default=None,
    metavar="T|auto",
    help="Let the particles fall for T seconds under the deck's BODY "
    "gravity (a run of the filled deck without its USRFRC drive) and write where "
    "they come to rest; auto: until they rest (at most 20 free falls across the cavity). "
    "Says whether they rest, and warns when they still move.",
)
@click.option(
    "--cards",
    is_flag=True,
    help="Write only the PDMP, TRACE, NODE COORDINATES (the particles) and CONTACT "
    "cards, to paste into a deck, instead of the whole deck.",
)
@click.option(
    "--plates",
    "plates",
    multiple=True,
    metavar="SPEC",
    help="A drilled plate of a multiple individual particle damper, one sphere per hole "
    "(repeatable): a PLATES record, 'set=1 master=1 holes=221 pitch=0.6 hole=0.504 "
    "thickness=0.501 shim=0.009 size=10' (docs/deck-reference.md). Replaces the template's "
    "particles with the plates' spheres (--radius, --material: the spheres').",
)
@click.option("-o", "--output", required=True, metavar="OUT.inp", help="The deck to write.")
@click.option("--overwrite", is_flag=True, help="Replace an existing OUT.inp.")
def fill(
    template,
    n,
    radius,
    packing,
    gap,
    seed,
    jitter,
    material,
    dt,
    keep_dt,
    set_id,
    settle,
    cards,
    plates,
    output,
    overwrite,
) -> None:
    """Fill TEMPLATE's cavity with particles and write the deck OUT.inp."""
    from x3dpd.api import fit_time_step
    from x3dpd.api.decks import format_deck, read_deck, write_deck
    from x3dpd.materials import material as library_material

    if dt is not None and keep_dt:
        raise InputError("--dt and --keep-dt exclude each other: give one")
    refuse_existing([output], overwrite)
    if material is not None:
        material = library_material(material)
    deck = read_deck(template)
    if plates:
        given = [
            f"--{name}"
            for name, v in (("n", n), ("seed", seed), ("set", set_id), ("settle", settle))
            if v is not None
        ] + [f"--{name}" for name, v in (("gap", gap), ("jitter", jitter)) if v]
        if given or packing != "cubic":
            raise InputError(
                f"--plates puts one sphere in each hole: {', '.join(given) or '--packing'} "
                "does not apply (a plate's own keys place its spheres: docs/deck-reference.md)"
            )
        _fill_plates(deck, plates, radius, material, dt, keep_dt, cards, output)
        return
    result = fill_positions(
        deck, n=n, radius=radius, packing=packing, gap=gap, seed=seed, jitter=jitter, set_id=set_id
    )
    m = result.positions.shape[0]
    if m == 0:
        raise InputError(
            f"{template}: no particle of radius {result.radius:g} fits in the "
            f"cavity with gap {gap:g}"
        )
    out = filled_deck(deck, result, set_id, material=material)
    step = None if keep_dt else fit_time_step(out, dt=dt)
    if step is not None:
        out = step.deck
    settled = None
    if settle is not None:
        from x3dpd.api.settle import settle as settle_bed

        settled = settle_bed(out, None if settle == "auto" else settle)
        out = settled.deck
    if cards:
        from x3dpd.api.decks import Deck

        nodlim = out.pdmp[0].nodlim
        out = Deck(
            path=out.path,
            pdmp=out.pdmp,
            trace=out.trace,
            contacts=out.contacts,
            nodes=tuple(nd for nd in out.nodes if nd.nid > nodlim),
        )
    format_deck(out)  # raises before anything is written if the deck cannot be written
    write_deck(out, output)
    short = f" (asked for {n}: only {m} fit)" if n is not None and m < n else ""
    click.echo(
        f"x3dpd: {template} -> {output}: {m} particles of radius {result.radius:g}, "
        f"{packing} packing{short}; fill ratio {result.fill_ratio:.3f} of the cavity "
        f"volume {result.volume:.6g}"
        + (f"; material {material.name}" if material is not None else "")
    )
    if step is not None:
        click.echo(
            f"x3dpd: {output}: "
            + ("time step for the cards' particles: " if cards else "")
            + step.describe()
        )
    if settled is not None:
        if settled.at_rest:
            click.echo(f"x3dpd: {output}: {settled.describe()}")
        else:
            click.echo(f"x3dpd: warning: {output}: {settled.describe()}", err=True)


def _fill_plates(deck, specs, radius, material, dt, keep_dt, cards, output) -> None:
    """``--plates``: the template's structure with a PLATES card (written as it is; the reader
    builds the holes and spheres) and the step the spheres need."""
    from dataclasses import replace

    from x3dpd.api import fit_time_step
    from x3dpd.api.decks import (
        Deck,
        expand_plates,
        format_deck,
        plated_deck,
        plates_from_specs,
        write_deck,
    )

    from x3dpd.errors import DeckError

    out = plated_deck(deck, plates_from_specs(specs), radius=radius, material=material)
    try:
        built = expand_plates(out)  # a bad plate is an error here, before anything is written
    except DeckError as exc:
        spec = specs[exc.line - 1] if 0 < exc.line <= len(specs) else specs[0]
        raise InputError(f"--plates {spec!r}: {exc.message}") from None
    step = None if keep_dt else fit_time_step(built, dt=dt)
    if step is not None:
        out = replace(out, parameters=step.deck.parameters)
    if cards:
        out = Deck(path=out.path, pdmp=out.pdmp, trace=out.trace, plates=out.plates)
    format_deck(out)
    write_deck(out, output)
    count = built.nodes[-1].nid - built.pdmp[0].nodlim
    click.echo(
        f"x3dpd: {deck.path} -> {output}: {len(out.plates)} drilled plates, {count} spheres "
        f"of radius {out.pdmp[0].rzero:g} (PLATES card: the reader builds its holes)"
        + (f"; material {material.name}" if material is not None else "")
    )
    if step is not None:
        click.echo(f"x3dpd: {output}: " + step.describe())
