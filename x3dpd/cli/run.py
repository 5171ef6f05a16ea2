"""``x3dpd run`` (placeholder; being written)."""

import click


@click.command("run")
def run() -> None:
    """Not implemented yet."""
    raise click.ClickException("x3dpd run is not implemented yet")
