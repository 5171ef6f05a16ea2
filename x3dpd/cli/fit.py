"""``x3dpd fit MEASURED --out DIR``: a single-mode SDOF fitted to a measured FRF, written as deck
records; ``x3dpd fit MEASURED... --modes N --out DIR``: N modes fitted to a set of FRFs, written
as a mode file and a MODAL card. A thin layer over :mod:`x3dpd.testlab.fit` and
:mod:`x3dpd.testlab.modal_fit`."""

from __future__ import annotations

import click

from x3dpd.errors import InputError

#: Options of the single-mode fit only, with their defaults there.
_SDOF_ONLY = {"dataset": 1, "node": 9, "dof": 1, "mass": None, "records": "sdof"}


@click.command("fit", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("measured", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option(
    "--out",
    required=True,
    metavar="DIR",
    help="Output folder (fit.txt, fit.png; with --modes: modes.csv, modal_card.inp, "
    "modal_fit.txt, modal_fit.png).",
)
@click.option(
    "--modes",
    type=click.IntRange(min=1),
    metavar="N",
    help="Fit N modes to the set of FRFs in MEASURED... (UFF 58 records or x3dpd frf CSVs, one "
    "per response point, one reference; or one response and a roving hammer) by LSCF and "
    "LSFD; the driving-point FRF is required. Without it: one FRF, one mode.",
)
@click.option(
    "--band",
    metavar="LO:HI",
    help="Fit over this band [Hz] (default: the whole file). It must hold 5 lines at least "
    "(with --modes N: 5 per mode and 10); with --modes, one band holds all N modes.",
)
@click.option(
    "--quantity",
    type=click.Choice(["displacement", "velocity", "acceleration"]),
    help="What the response is (default: what the file says).",
)
@click.option("--dataset", type=int, help="Which FRF of a UFF file (1 = the first) [1].")
@click.option(
    "--node",
    type=int,
    help="Node id of the deck records (the beam decks' master node is 9) [9].",
)
@click.option("--dof", type=int, help="Spring direction, 1-3 [1].")
@click.option(
    "--mass", type=float, help="The effective mass, if known (then the force scale is fitted)."
)
@click.option(
    "--force-scale",
    type=float,
    help="Force per unit of the FRF's excitation (default 1: an FRF per unit force); "
    "negative for an FRF of reversed sign (drive and response in opposite directions).",
)
@click.option(
    "--records",
    type=click.Choice(["sdof", "modal"]),
    help="The deck records written: sdof (MASS, MATID spring/damper, ELEMENTS) or "
    "modal (a MODAL card: one mode, its shape value 1/sqrt(m) at the node) [sdof].",
)
@click.option(
    "--units",
    metavar="L,F,T",
    help="With --modes: the FRFs' unit system (e.g. m,N,s), declared in modes.csv so that a "
    "deck in other units converts it.",
)
@click.option("--overwrite", is_flag=True, help="Replace the files in DIR.")
@click.option("--quiet", "-q", is_flag=True, help="Print errors only.")
def fit(measured, out, modes, band, quantity, force_scale, units, overwrite, quiet, **sdof):
    """Fit a single-mode SDOF to a measured FRF (deck records to DIR/fit.txt, DIR/fit.png), or
    with --modes N, N modes to a set of FRFs (a mode file and a MODAL card)."""
    echo = (lambda s: None) if quiet else click.echo
    if modes is not None:
        given = [k for k, v in sdof.items() if v is not None]
        if given:
            raise InputError(
                f"--{given[0]} is an option of the single-mode fit; with --modes the nodes "
                "and directions are the measured points"
            )
        from x3dpd.testlab.modal_fit import modal_fit_command

        modal_fit_command(
            measured,
            out=out,
            modes=modes,
            band=band,
            quantity=quantity,
            force_scale=force_scale,
            units=units,
            overwrite=overwrite,
            echo=echo,
        )
        return
    if len(measured) > 1:
        raise InputError(
            f"{len(measured)} files given: the single-mode fit reads one FRF (several are a "
            "set: add --modes N)"
        )
    if units is not None:
        raise InputError("--units is an option of the multi-mode fit (--modes N)")
    from x3dpd.testlab.fit import fit_command

    options = {k: _SDOF_ONLY[k] if v is None else v for k, v in sdof.items()}
    fit_command(
        measured[0],
        out=out,
        band=band,
        quantity=quantity,
        force_scale=force_scale,
        overwrite=overwrite,
        echo=echo,
        **options,
    )
