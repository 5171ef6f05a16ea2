"""``x3dpd ringdown TRACE|DECK --node N --dof D --out DIR``: damping ratio versus amplitude.

A thin layer over :mod:`x3dpd.testlab.ringdown` (docs/design-guide.md).
"""

from __future__ import annotations

import click

from x3dpd.cli.temperature_option import temperature_option


@click.command("ringdown", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("source", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--node",
    type=int,
    help="Node whose ring-down is analysed [deck input: default "
    "the USRFRC drive node, else the first cavity's master; "
    "required for a trace].",
)
@click.option("--dof", type=int, default=1, show_default=True, help="Direction, 1-3.")
@click.option("--out", "out", required=True, metavar="DIR", help="Output folder.")
@click.option(
    "--baseline",
    "baseline",
    metavar="TRACE",
    help="A trace of the baseline (no particles) to overlay (trace input).",
)
@click.option(
    "--from",
    "t_from",
    type=float,
    metavar="T",
    help="Analyse a trace from time T on (after the drive stopped) [s].",
)
@click.option(
    "--drive-until",
    type=click.FloatRange(min=0.0),
    default=1.0,
    show_default=True,
    metavar="T",
    help="Deck input: drive with the deck's USRFRC until T, then release [s].",
)
@click.option(
    "--ring",
    type=click.FloatRange(min=0.0, min_open=True),
    default=2.0,
    show_default=True,
    metavar="T",
    help="Deck input: free ring-down recorded for T seconds.",
)
@click.option("--no-baseline", is_flag=True, help="Deck input: skip the particle-free run.")
@click.option(
    "--g",
    "g",
    type=click.FloatRange(min=0.0, min_open=True),
    default=None,
    help="One standard gravity for dB re 1 g [length/s^2] (default: in the deck's units, its "
    "UNITS card's, or the trace's: 386.1 in/s^2, 9.80665 m/s^2).",
)
@click.option(
    "--measured",
    multiple=True,
    metavar="FILE",
    help="A measured ring-down to overlay: CSV (time, displacement|acceleration) or UFF "
    "dataset 58 (repeatable).",
)
@temperature_option
@click.option("--overwrite", is_flag=True, help="Replace DIR/ringdown.csv and .png.")
@click.option("--quiet", "-q", is_flag=True, help="Print errors only.")
def ringdown(
    source,
    node,
    dof,
    out,
    baseline,
    t_from,
    drive_until,
    ring,
    no_baseline,
    g,
    measured,
    temperature,
    overwrite,
    quiet,
):
    """Damping (% zeta) versus amplitude (dB re 1 g) of a ring-down (DIR/ringdown.csv, .png)."""
    from x3dpd.testlab.ringdown import ringdown_command

    ringdown_command(
        source,
        node=node,
        dof=dof,
        out=out,
        baseline=baseline,
        t_from=t_from,
        drive_until=drive_until,
        ring=ring,
        no_baseline=no_baseline,
        g=g,
        overwrite=overwrite,
        measured=measured,
        temperature=temperature,
        echo=(lambda s: None) if quiet else click.echo,
    )
