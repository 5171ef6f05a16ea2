"""``x3dpd sweep DECK --freq ... --amp ... --out DIR``: steady-state frequency sweeps.

A thin layer over :mod:`x3dpd.design.sweep` (the criterion, chains, baselines, Dask and resuming
live there; docs/design-guide.md explains them).
"""

from __future__ import annotations

import click

from x3dpd.cli.temperature_option import temperature_option
from x3dpd.errors import InputError


@click.command("sweep", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("deck", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--freq",
    required=True,
    metavar="SPEC",
    help="Frequencies [Hz]: START:STOP:STEP (STOP included), a comma list, or "
    "auto:LO:HI[:RES[:POINTS]] to find the peak and its half-power band in [LO, HI] with "
    "as few points as it can (a coarse pass of 4, then one at a time at a fitted "
    "resonance curve's peak, until it settles within RES Hz [default (HI-LO)/100]; at "
    "most POINTS [7] per drive and chain; DIR/peaks.csv).",
)
@click.option(
    "--drive",
    type=click.Choice(["force", "base"]),
    default="force",
    show_default=True,
    help="force: a sine force on --node (the deck's USRFRC replaced); base: --node "
    "moved on a sine (a shaker table; the deck's USRFRC dropped).",
)
@click.option(
    "--amp",
    required=True,
    multiple=True,
    metavar="A",
    help="Drive amplitude(s); repeat or give a comma list. Force drive: a force. "
    "Base drive: a displacement [length], or with a suffix 0.1vel [length/s], "
    "200acc [length/s^2], 2g (standard gravity: 386.1 in/s^2, 9.80665 m/s^2).",
)
@click.option(
    "--node",
    type=int,
    help="Driven and measured node [default: the deck's USRFRC "
    "drive node, else the first cavity's master; a base "
    "drive must name its base].",
)
@click.option("--dof", type=int, help="DOF 1-3 [default: the USRFRC drive's, else 1].")
@click.option(
    "--response",
    multiple=True,
    metavar="NODE:DOF",
    help="Also measure this node and DOF (repeatable): a row each in sweep.csv "
    "(accelerance = its acceleration / the drive force; for a base drive "
    "transmissibility = its acceleration / the base's), DIR/sweep_responses.png "
    "(base drive: DIR/sweep.png) [base drive default: the first cavity's "
    "master along --dof].",
)
@click.option(
    "--direction",
    type=click.Choice(["up", "down", "both"]),
    help="Chain the points, each continuing from the previous one's state "
    "[default: every point from the deck's initial state, in parallel].",
)
@click.option(
    "--baseline", default="", metavar="LIST", help="Comma list of baselines: undamped, added-mass."
)
@click.option("--out", "out", required=True, metavar="DIR", help="Output folder.")
@click.option(
    "--workers",
    type=int,
    metavar="K",
    help="Local worker processes [default: all cores]; 1 = serial in this process.",
)
@click.option("--scheduler", metavar="ADDRESS", help="Run on an existing Dask cluster.")
@click.option("--dt", type=float, metavar="DT", help="Time step [s] [default: the deck's DTMAX].")
@click.option(
    "--tol", type=float, default=0.01, show_default=True, help="Steady-state relative tolerance."
)
@click.option("--window", type=int, default=5, show_default=True, help="Cycles per window.")
@click.option(
    "--max-cycles",
    type=int,
    default=400,
    show_default=True,
    help="Cap on drive cycles per point (a capped point is flagged).",
)
@click.option(
    "--samples-per-cycle",
    type=int,
    default=200,
    show_default=True,
    help="Recorded samples per drive cycle (amplitude measurement).",
)
@click.option(
    "--replicas",
    type=int,
    default=1,
    show_default=True,
    help="Run each point R times, the particles started a hair apart, each to --tol x "
    "sqrt(R), on as many workers, and pool them into one answer with one interval.",
)
@click.option(
    "--no-extrapolate",
    is_flag=True,
    help="Never extrapolate a linear transient; wait for it to die.",
)
@click.option(
    "--no-predict",
    is_flag=True,
    help="Start each point from the deck's or the previous point's state as it is, "
    "not with the structure put on its predicted steady-state motion.",
)
@click.option(
    "--measured",
    multiple=True,
    metavar="FILE[@NODE:DOF]",
    help="A measured FRF (CSV or UFF dataset 58; repeatable) drawn on the plot of "
    "NODE:DOF [default: the first --response, else the driven point], converted "
    "to the plot's quantity (docs/design-guide.md).",
)
@click.option(
    "--measured-scale",
    type=float,
    default=1.0,
    show_default=True,
    help="Multiplies the measured FRFs (a unit conversion, e.g. 386.1 for g to in/s^2).",
)
@temperature_option
@click.option("--overwrite", is_flag=True, help="Discard a different sweep stored in DIR.")
@click.option("--quiet", "-q", is_flag=True, help="Print errors only.")
def sweep(
    deck,
    freq,
    drive,
    amp,
    node,
    dof,
    response,
    direction,
    baseline,
    out,
    workers,
    scheduler,
    dt,
    tol,
    window,
    max_cycles,
    samples_per_cycle,
    replicas,
    no_extrapolate,
    no_predict,
    measured,
    measured_scale,
    temperature,
    overwrite,
    quiet,
):
    """Steady-state response of a node across frequencies (DIR/sweep.csv, DIR/sweep.png)."""
    from x3dpd.design.commands import sweep_command

    if workers is not None and workers < 1:
        raise InputError(f"--workers {workers}: expected 1 or more")
    from x3dpd.design.steady_state import Criterion

    criterion = Criterion(
        tol=tol,
        window=window,
        max_cycles=max_cycles,
        samples_per_cycle=samples_per_cycle,
        extrapolate=not no_extrapolate,
        predict=not no_predict,
        replicas=replicas,
    )
    if problems := criterion.problems():
        raise InputError(
            "; ".join(
                f"--{name.replace('_', '-')} {getattr(criterion, name):g}: expected {must}"
                for name, must in problems
            )
        )

    sweep_command(
        deck,
        freq=freq,
        amps=amp,
        node=node,
        dof=dof,
        direction=direction,
        baselines=tuple(b for b in baseline.split(",") if b.strip()),
        out=out,
        workers=workers,
        scheduler=scheduler,
        dt=dt,
        criterion=criterion,
        overwrite=overwrite,
        responses=response,
        drive=drive,
        measured_files=measured,
        measured_scale=measured_scale,
        temperature=temperature,
        echo=(lambda s: None) if quiet else click.echo,
    )
