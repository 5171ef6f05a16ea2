"""The options ``x3dpd frf`` and ``x3dpd spectrum`` share: response quantity, Welch segments,
window, band and start time."""

from __future__ import annotations

import click


def spectral_options(fn):
    """Add --quantity, --window, --segment, --nperseg, --overlap, --band and --from."""
    options = [
        click.option(
            "--quantity",
            type=click.Choice(["displacement", "velocity", "acceleration"]),
            default="acceleration",
            show_default=True,
            help="What the responses are read as (acceleration: the velocity's "
            "spectrum times i w).",
        ),
        click.option(
            "--window",
            default="hann",
            show_default=True,
            help="Window of each segment (any scipy.signal.get_window name).",
        ),
        click.option(
            "--segment",
            type=float,
            metavar="SECONDS",
            help="Welch segment length [s] (default: 8 averages over the record).",
        ),
        click.option("--nperseg", type=int, metavar="N", help="Welch segment length [samples]."),
        click.option(
            "--overlap",
            type=float,
            default=0.5,
            show_default=True,
            help="Overlap of the segments, a fraction 0 <= overlap < 1.",
        ),
        click.option("--band", metavar="LO:HI", help="Frequency band to keep [Hz]."),
        click.option(
            "--from",
            "t_from",
            type=float,
            metavar="T",
            help="Use the trace from time T on [s] (skip a start transient).",
        ),
    ]
    for option in reversed(options):
        fn = option(fn)
    return fn
