"""``x3dpd tracediff A B``: do two trace files agree within tolerances?

Exit status 0 when they agree, 1 when they differ, 2 when a file cannot be read or the traces
follow different nodes (a one-line ``x3dpd: error: ...`` from the group, no traceback).
"""

from __future__ import annotations

import sys
import warnings

import click

from x3dpd.api.traces import TraceWarning, compare_traces, read_trace


@click.command("tracediff")
@click.argument("a", metavar="A", type=click.Path(dir_okay=False))
@click.argument("b", metavar="B", type=click.Path(dir_okay=False))
@click.option(
    "--rtol",
    type=click.FloatRange(min=0.0),
    default=1e-9,
    show_default=True,
    help="Relative tolerance: values differ when |a-b| > atol + rtol*|b|.",
)
@click.option(
    "--atol",
    type=click.FloatRange(min=0.0),
    default=0.0,
    show_default=True,
    help="Absolute tolerance [trace units].",
)
@click.option(
    "--until", type=float, default=None, metavar="T", help="Compare output times t <= T [s] only."
)
def tracediff(a: str, b: str, rtol: float, atol: float, until: float | None) -> None:
    """Compare trace A against reference trace B, value by value.

    Prints the largest absolute and relative error of each column and the first place
    (earliest time, then node, then column) where |a-b| > atol + rtol*|b|.
    Exit status: 0 agree, 1 differ, 2 unreadable file or different node lists.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", TraceWarning)
        ta = read_trace(a)
        tb = read_trace(b)
    for w in caught:
        if issubclass(w.category, TraceWarning):
            click.echo(f"x3dpd: warning: {w.message}", err=True)
    report = compare_traces(ta, tb, rtol=rtol, atol=atol, until=until)
    click.echo(f"A: {a} ({ta.node_ids.size} nodes, {ta.times.size} output times)")
    click.echo(f"B: {b} ({tb.node_ids.size} nodes, {tb.times.size} output times)")
    click.echo(report.format())
    if not report.agree:
        # sys.exit, not ctx.exit: with standalone_mode=False click *returns* ctx.exit's code
        # and x3dpd.cli.main() would exit 0.
        sys.exit(1)
