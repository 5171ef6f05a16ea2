"""``x3dpd tracediff`` (placeholder; being written)."""

import click


@click.command("tracediff")
def tracediff() -> None:
    """Not implemented yet."""
    raise click.ClickException("x3dpd tracediff is not implemented yet")
