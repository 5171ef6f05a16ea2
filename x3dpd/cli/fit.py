"""``x3dpd fit MEASURED --out DIR``: a single-mode SDOF fitted to a measured FRF, written as deck
records. A thin layer over :mod:`x3dpd.design.fit`."""

from __future__ import annotations

import click


@click.command("fit", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("measured", type=click.Path(dir_okay=False))
@click.option("--out", required=True, metavar="DIR", help="Output folder (fit.txt, fit.png).")
@click.option("--band", metavar="LO:HI", help="Fit over this band [Hz] (default: the whole file).")
@click.option(
    "--quantity",
    type=click.Choice(["displacement", "velocity", "acceleration"]),
    help="What the response is (default: what the file says).",
)
@click.option(
    "--dataset",
    type=int,
    default=1,
    show_default=True,
    help="Which FRF of a UFF file (1 = the first).",
)
@click.option(
    "--node",
    type=int,
    default=9,
    show_default=True,
    help="Node id of the deck records (the beam decks' master node is 9).",
)
@click.option("--dof", type=int, default=1, show_default=True, help="Spring direction, 1-3.")
@click.option(
    "--mass", type=float, help="The effective mass, if known (then the force scale is fitted)."
)
@click.option(
    "--force-scale",
    type=float,
    help="Force per unit of the FRF's excitation (default 1: an FRF per unit force).",
)
@click.option(
    "--records",
    type=click.Choice(["sdof", "modal"]),
    default="sdof",
    show_default=True,
    help="The deck records written: sdof (MASS, MATID spring/damper, ELEMENTS) or "
    "modal (a MODAL card: one mode, its shape value 1/sqrt(m) at the node).",
)
@click.option("--overwrite", is_flag=True, help="Replace DIR/fit.txt and .png.")
@click.option("--quiet", "-q", is_flag=True, help="Print errors only.")
def fit(
    measured, out, band, quantity, dataset, node, dof, mass, force_scale, records, overwrite, quiet
):
    """Fit a single-mode SDOF to a measured FRF; deck records to DIR/fit.txt, DIR/fit.png."""
    from x3dpd.design.fit import fit_command

    fit_command(
        measured,
        out=out,
        band=band,
        quantity=quantity,
        dataset=dataset,
        node=node,
        dof=dof,
        mass=mass,
        force_scale=force_scale,
        records=records,
        overwrite=overwrite,
        echo=(lambda s: None) if quiet else click.echo,
    )
