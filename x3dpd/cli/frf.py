"""``x3dpd frf TRACE... --drive NODE:DOF --response NODE:DOF --out DIR``: H1, H2 and coherence of
runs, measured FRFs overlaid. A thin layer over :mod:`x3dpd.testlab.frf`
(docs/testing-like-a-test-engineer.md)."""

from __future__ import annotations

import click

from x3dpd.cli.progress import ReadProgress
from x3dpd.cli.spectral_options import spectral_options


@click.command("frf", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("traces", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option(
    "--drive",
    required=True,
    metavar="NODE:DOF",
    help="The driven DOF: a USRFRC law's force or a --motion's acceleration, "
    "recomputed from the trace's sidecar.",
)
@click.option(
    "--response",
    "responses",
    multiple=True,
    required=True,
    metavar="NODE:DOF",
    help="A traced node's DOF (repeatable).",
)
@click.option("--out", required=True, metavar="DIR", help="Output folder (frf.csv, frf.png).")
@spectral_options
@click.option(
    "--measured",
    multiple=True,
    metavar="FILE",
    help="A measured FRF to overlay: CSV or UFF dataset 58 (repeatable).",
)
@click.option(
    "--measured-scale",
    type=float,
    default=1.0,
    show_default=True,
    help="Multiplies the measured FRFs (a unit conversion, e.g. 386.1 for g to in/s^2).",
)
@click.option(
    "--baseline",
    default="",
    metavar="LIST",
    help="Comma list of baselines (undamped, added-mass) whose closed-form FRFs to "
    "overlay: the first TRACE's deck without its particles, and with their mass "
    "added rigidly.",
)
@click.option(
    "--deck",
    type=click.Path(exists=True, dir_okay=False),
    help="The deck of the baselines [default: the one the first TRACE's run read, "
    "from its sidecar].",
)
@click.option("--overwrite", is_flag=True, help="Replace DIR/frf.csv and .png.")
@click.option("--quiet", "-q", is_flag=True, help="Print errors only.")
def frf(
    traces,
    drive,
    responses,
    out,
    quantity,
    window,
    segment,
    nperseg,
    overlap,
    band,
    t_from,
    measured,
    measured_scale,
    baseline,
    deck,
    overwrite,
    quiet,
):
    """Frequency response functions H1, H2 and coherence of runs (DIR/frf.csv, frf.png)."""
    from x3dpd.testlab.frf import frf_command

    frf_command(
        traces,
        drive=drive,
        responses=responses,
        out=out,
        quantity=quantity,
        window=window,
        segment=segment,
        nperseg=nperseg,
        overlap=overlap,
        band=band,
        t_from=t_from,
        measured=measured,
        measured_scale=measured_scale,
        baselines=tuple(b.strip() for b in baseline.split(",") if b.strip()),
        deck=deck,
        overwrite=overwrite,
        echo=(lambda s: None) if quiet else click.echo,
        progress=None if quiet else ReadProgress(),
    )
