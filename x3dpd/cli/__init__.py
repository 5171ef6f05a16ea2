"""The ``x3dpd`` command line.

``x3dpd DECK [options]`` runs a deck (the same as ``x3dpd run DECK``); subcommands sit beside it.
Each subcommand lives in its own module of this package; this module only assembles the group and
turns typed errors into one-line messages and exit statuses (2 bad input, 3 unstable run,
130 interrupted), never a traceback.
"""

from __future__ import annotations

import sys

import click

from x3dpd import __version__
from x3dpd.errors import X3dpdError


class _DeckOrCommand(click.Group):
    """A group whose first argument may be a deck path instead of a subcommand name."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        if args and args[0] not in self.commands and not args[0].startswith("-"):
            args = ["run", *args]
        return super().parse_args(ctx, args)


@click.group(cls=_DeckOrCommand, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="x3dpd")
def cli() -> None:
    """x3dpd: X3D-compatible particle impact damper solver.

    Run a deck with ``x3dpd DECK`` (or ``x3dpd run DECK`` when the deck's name is also a
    subcommand's name).
    """


def _register() -> None:
    from x3dpd.cli import (
        cache,
        check,
        design,
        export,
        fill,
        fit,
        frf,
        materials,
        movie,
        plot,
        ringdown,
        run,
        spectrum,
        study,
        sweep,
        tracediff,
    )

    cli.add_command(run.run)
    cli.add_command(check.check)
    cli.add_command(tracediff.tracediff)
    cli.add_command(sweep.sweep)
    cli.add_command(ringdown.ringdown)
    cli.add_command(study.study)
    cli.add_command(design.design)
    cli.add_command(movie.movie)
    cli.add_command(export.export)
    cli.add_command(plot.plot)
    cli.add_command(fill.fill)
    cli.add_command(frf.frf)
    cli.add_command(spectrum.spectrum)
    cli.add_command(fit.fit)
    cli.add_command(materials.materials_command)
    cli.add_command(cache.cache)


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``x3dpd`` console script."""
    _register()
    try:
        rc = cli.main(args=argv, prog_name="x3dpd", standalone_mode=False)
    except X3dpdError as exc:
        click.echo(f"x3dpd: error: {exc}", err=True)
        sys.exit(exc.exit_status)
    except click.exceptions.Abort:
        click.echo("x3dpd: interrupted", err=True)
        sys.exit(130)
    except KeyboardInterrupt:
        click.echo("x3dpd: interrupted", err=True)
        sys.exit(130)
    except click.ClickException as exc:
        exc.show()
        sys.exit(2 if exc.exit_code == 2 else exc.exit_code)
    except click.exceptions.Exit as exc:
        sys.exit(exc.exit_code)
    # with standalone_mode=False click *returns* the code given to ctx.exit(n)
    sys.exit(rc if isinstance(rc, int) else 0)
