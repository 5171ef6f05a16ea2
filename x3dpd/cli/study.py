"""``x3dpd study DECK``: what accuracy costs in time on this deck (docs/study.md).

Runs the deck at a ladder of time steps and fidelity choices through the Python API, prints a
table and a one-line verdict, and writes ``DIR/study.csv`` and ``DIR/study.png``.
"""

from __future__ import annotations

import os
from pathlib import Path

import click

from x3dpd.cli.temperature_option import temperature_option
from x3dpd.errors import InputError


def _tolerance(text: str) -> float:
    t = text.strip()
    try:
        value = float(t[:-1]) / 100.0 if t.endswith("%") else float(t)
    except ValueError:
        raise InputError(
            f"--tol: expected a fraction or a percentage like 1%, got {text!r}"
        ) from None
    if not 0.0 < value < 1.0:
        raise InputError(f"--tol: expected a tolerance between 0 and 100 %, got {text!r}")
    return value


def _steps(text: str | None):
    if not text:
        return None
    words = [v.strip() for v in text.split(",") if v.strip()]
    try:
        dts = [float(v) for v in words if v != "auto"]
    except ValueError:
        raise InputError(
            f"--dt: expected comma-separated steps in s (or auto), got {text!r}"
        ) from None
    if not all(0.0 < d < float("inf") for d in dts) or not words:
        raise InputError(f"--dt: expected positive steps in s, got {text!r}")
    return dts + (["auto"] if "auto" in words else [])


def _scales(text: str | None) -> tuple:
    if not text:
        return ()
    try:
        scales = tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise InputError(
            f"--stiffness-scale: expected comma-separated scales like 0.1,0.01, got {text!r}"
        ) from None
    if not scales or not all(0.0 < f <= 1.0 for f in scales):
        raise InputError(f"--stiffness-scale: expected scales in (0, 1], got {text!r}")
    return scales


@click.command("study")
@click.argument("deck", type=click.Path(dir_okay=False))
@click.option("--tmax", type=float, default=None, help="End time of every run [s].")
@click.option(
    "--out",
    "out",
    default=None,
    metavar="DIR",
    help="Directory for study.csv and study.png (default <deck stem>.study).",
)
@click.option(
    "--tol",
    default="1%",
    show_default=True,
    help="Accepted error of the main quantity (1% or 0.01).",
)
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    default=None,
    help="Local worker processes (default: one per core).",
)
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="Run on the Dask cluster at ADDRESS instead of local workers.",
)
@click.option(
    "--dt",
    "dts",
    default=None,
    metavar="LIST",
    help="Steps to run, comma-separated [s], and/or auto (the step chosen by "
    "accuracy, within the deck's DTMIN ... DTMAX when DTMIN < DTMAX, else up to "
    "the coarsest step); default DTMAX x 1/4 ... 8.",
)
@click.option(
    "--usrfrc",
    multiple=True,
    metavar="SPEC",
    help="Force spec replacing the deck's USRFRC card (repeatable).",
)
@click.option(
    "--motion",
    multiple=True,
    metavar="SPEC",
    help="Prescribed motion, as x3dpd run --motion (node=4,dof=2,amp=0.02,hz=36.75: "
    "a base-driven deck's shaker; repeatable).",
)
@click.option(
    "--no-fidelity",
    "no_fidelity",
    is_flag=True,
    help="Run the step ladder only (no elastic / bare-Coulomb variants).",
)
@click.option(
    "--stiffness-scale",
    "stiffness",
    default=None,
    metavar="LIST",
    help="Also run softer contacts: the particles' moduli scaled by each of these "
    "(e.g. 0.1,0.01), at the deck's step x scale^(-2/5).",
)
@click.option(
    "--walls",
    "walls",
    default=None,
    metavar="LIST",
    help="Also run these walls on every cavity, comma-separated: rigid, or a "
    "material of `x3dpd materials` (e.g. rigid,acrylic,aluminium).",
)
@temperature_option
@click.option("--overwrite", is_flag=True, help="Replace an existing study in DIR.")
@click.option("-q", "--quiet", is_flag=True, help="Print the verdict only.")
def study(
    deck,
    tmax,
    out,
    tol,
    workers,
    scheduler,
    dts,
    usrfrc,
    motion,
    no_fidelity,
    stiffness,
    walls,
    temperature,
    overwrite,
    quiet,
):
    """Measure what accuracy costs in time on DECK."""
    from x3dpd.study import run_study
    from x3dpd.study.report import table

    if not os.path.isfile(deck):
        raise InputError(f"deck {deck} does not exist")
    out = out or f"{Path(deck).stem}.study"
    n = workers or (1 if scheduler else max(1, os.cpu_count() or 1))

    def done(row):
        if not quiet:
            click.echo(f"  {row['setting'].label}: {row['status']}", err=True)

    result = run_study(
        deck,
        out,
        tmax=tmax,
        tol=_tolerance(tol),
        workers=n,
        scheduler=scheduler,
        dts=_steps(dts),
        usrfrc=usrfrc,
        motion=motion,
        overwrite=overwrite,
        progress=done,
        fidelity=not no_fidelity,
        stiffness=_scales(stiffness),
        temperature=temperature,
        walls=tuple((walls or "").split(",")),
    )
    if not quiet:
        click.echo(table(result))
        click.echo(f"wrote {', '.join(result.files)}")
    click.echo(f"verdict: {result.verdict}")
