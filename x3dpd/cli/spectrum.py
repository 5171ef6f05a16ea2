"""``x3dpd spectrum TRACE... --node N --dof D --out DIR``: the response spectrum of a node (the
report's Fig. 10). A thin layer over :mod:`x3dpd.testlab.frf`."""

from __future__ import annotations

import click

from x3dpd.cli.progress import ReadProgress
from x3dpd.cli.spectral_options import spectral_options


@click.command("spectrum", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("traces", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option("--node", type=int, required=True, help="A traced node.")
@click.option("--dof", type=int, default=1, show_default=True, help="Direction, 1-6.")
@click.option(
    "--out", required=True, metavar="DIR", help="Output folder (spectrum.csv, spectrum.png)."
)
@click.option(
    "--method",
    type=click.Choice(["fft", "welch"]),
    default="fft",
    show_default=True,
    help="fft: amplitude spectrum of the whole record; welch: averaged PSD.",
)
@spectral_options
@click.option("--overwrite", is_flag=True, help="Replace DIR/spectrum.csv and .png.")
@click.option("--quiet", "-q", is_flag=True, help="Print errors only.")
def spectrum(
    traces,
    node,
    dof,
    out,
    method,
    quantity,
    window,
    segment,
    nperseg,
    overlap,
    band,
    t_from,
    overwrite,
    quiet,
):
    """Amplitude spectrum or PSD of a node's response (DIR/spectrum.csv, spectrum.png)."""
    from x3dpd.testlab.frf import spectrum_command

    if not 1 <= dof <= 6:
        raise click.BadParameter(f"{dof}: expected 1..6", param_hint="--dof")
    spectrum_command(
        traces,
        node=node,
        dof=dof,
        out=out,
        quantity=quantity,
        method=method,
        window=window,
        segment=segment,
        nperseg=nperseg,
        overlap=overlap,
        band=band,
        t_from=t_from,
        overwrite=overwrite,
        echo=(lambda s: None) if quiet else click.echo,
        progress=None if quiet else ReadProgress(),
    )
