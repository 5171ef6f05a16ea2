"""``x3dpd design SPEC --out DIR``: a design study from one design file (docs/design.md).

A thin layer over :mod:`x3dpd.design.explore` (configurations, Dask, resuming live there).
"""

from __future__ import annotations

import click

from x3dpd.errors import InputError


@click.command("design", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("spec", type=click.Path(exists=True, dir_okay=False))
@click.option("--out", "out", metavar="DIR", help="Output folder (required unless --plan).")
@click.option(
    "--workers",
    type=int,
    metavar="K",
    help="Local worker processes [default: all cores]; 1 = serial in this process.",
)
@click.option("--scheduler", metavar="ADDRESS", help="Run on an existing Dask cluster.")
@click.option(
    "--overwrite",
    is_flag=True,
    help="Recompute configurations whose deck or settings changed since DIR was "
    "written (the others are kept).",
)
@click.option(
    "--plan",
    is_flag=True,
    help="Make and check every configuration, print what each would run (particles, step, "
    "points, the most steps) and write nothing.",
)
@click.option("--quiet", "-q", is_flag=True, help="Print errors only.")
def design(spec, out, workers, scheduler, overwrite, plan, quiet):
    """Evaluate every configuration of a design file (DIR/design.csv, DIR/design_*.png)."""
    from x3dpd.design.explore import run_design

    if plan:
        from x3dpd.design.plan import format_plan, plan_design

        click.echo("\n".join(format_plan(*plan_design(spec))))
        return
    if out is None:
        raise InputError("--out DIR: give the output folder (or --plan to see what would run)")
    if workers is not None and workers < 1:
        raise InputError(f"--workers {workers}: expected 1 or more")
    run_design(
        spec,
        out,
        workers=workers,
        scheduler=scheduler,
        overwrite=overwrite,
        echo=(lambda s: None) if quiet else click.echo,
    )
