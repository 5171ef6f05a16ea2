"""``x3dpd movie TRACE -o FILE.mp4|FILE.gif|FILE.png``: the particles in their moving cavity."""

from __future__ import annotations

import click

from x3dpd.api.figures import VIEWS, write_movie
from x3dpd.api.traces import iter_blocks
from x3dpd.errors import InputError
from x3dpd.cli._trace_scene import DECK_HELP, load_scene
from x3dpd.cli.outputs import refuse_existing


@click.command("movie")
@click.argument("trace", type=click.Path(dir_okay=False))
@click.option(
    "-o",
    "--output",
    required=True,
    metavar="FILE",
    help="FILE.mp4 (H.264), FILE.gif, or FILE.png (one still, see --at).",
)
@click.option(
    "--every",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Draw every N-th output time.",
)
@click.option(
    "--fps",
    type=click.FloatRange(min=0.1),
    default=25.0,
    show_default=True,
    help="Frames per second of the movie.",
)
@click.option(
    "--view",
    type=click.Choice(sorted(VIEWS)),
    default="xy",
    show_default=True,
    help="Projection plane (xy: looking along -z).",
)
@click.option("--from", "t_from", type=float, default=None, metavar="T", help="Start time [s].")
@click.option("--to", "t_to", type=float, default=None, metavar="T", help="End time [s].")
@click.option(
    "--at",
    "t_at",
    type=float,
    default=None,
    metavar="T",
    help="For a .png still: the first output time >= T [s] (default: the first).",
)
@click.option("--deck", default=None, metavar="DECK", help=DECK_HELP)
@click.option("--overwrite", is_flag=True, help="Replace an existing output file.")
def movie(trace, output, every, fps, view, t_from, t_to, t_at, deck, overwrite) -> None:
    """Write a movie (or a still) of the particles in the cavity from TRACE."""
    refuse_existing([output], overwrite)
    info, _, scene = load_scene(trace, deck)
    lo = t_at if t_at is not None else (t_from if t_from is not None else float("-inf"))
    hi = t_to if t_to is not None else float("inf")
    first, last = info.meta.get("t0"), info.meta.get("last_time")
    if first is not None and last is not None and not (lo <= last and hi >= first and lo <= hi):
        none = (
            f"none at or after --at {t_at:g} s"
            if t_at is not None
            else f"none from {_g(lo)} to {_g(hi)}"
        )
        raise InputError(f"{trace}: its output times run from {first:g} to {last:g} s: {none}")
    blocks = iter_blocks(trace, info.node_ids.shape[0], every=every, t_from=lo, t_to=hi)
    n = write_movie(output, scene, blocks, view=view, fps=fps)
    click.echo(f"x3dpd: {trace} -> {output} ({n} frame{'s' if n != 1 else ''}, view {view})")


def _g(t: float) -> str:
    return "the start" if t == float("-inf") else "the end" if t == float("inf") else f"{t:g} s"
