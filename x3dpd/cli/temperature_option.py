"""``--temperature T``, the option ``x3dpd run``, ``check``, ``sweep``, ``ringdown`` and ``study``
share: the operating temperature over the deck's TEMPERATURE card's (docs/deck-reference.md)."""

from __future__ import annotations

import click

temperature_option = click.option(
    "--temperature",
    metavar="T",
    help="Operating temperature over the deck's TEMPERATURE card's: 850F, 455C, 728K, or "
    "a number on the scale of the deck's UNITS card (docs/deck-reference.md, TEMPERATURE).",
)
