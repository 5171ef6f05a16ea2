"""``x3dpd check`` (placeholder; being written)."""

import click


@click.command("check")
def check() -> None:
    """Not implemented yet."""
    raise click.ClickException("x3dpd check is not implemented yet")
