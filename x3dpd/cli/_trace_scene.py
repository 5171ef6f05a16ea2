"""The deck behind a trace, for the commands that draw or export it (movie, export, plot).

The trace's sidecar records ``deck_path`` (as given to the run, so relative to where it ran) and
``deck_sha256``. The deck is looked for as recorded, then beside the trace; ``--deck`` overrides
both. A deck whose SHA-256 differs from the recorded one is used with a warning.
"""

from __future__ import annotations

import os

import click

from x3dpd.api.figures import Scene, scene_from_model
from x3dpd.api.traces import TraceInfo, sha256_file, trace_info
from x3dpd.errors import InputError
from x3dpd.units import labels_for

DECK_HELP = "Deck of the run (default: the one the trace's sidecar records)."


def find_deck(info: TraceInfo, deck: str | None) -> str:
    """Path of the deck behind ``info``'s trace (``deck`` when given)."""
    if deck:
        if not os.path.isfile(deck):
            raise InputError(f"--deck {deck}: no such file")
        return deck
    recorded = info.deck_path or ""
    if recorded:
        here = os.path.dirname(os.path.abspath(info.path))
        abspath = info.meta.get("deck_abspath")
        for cand in (
            recorded,
            abspath,
            os.path.join(here, recorded),
            os.path.join(here, os.path.basename(recorded)),
        ):
            if cand and os.path.isfile(cand):
                return cand
    raise InputError(
        f"{info.path}: the sidecar records deck {recorded or '(none)'!r}, which is "
        f"not found here or beside the trace; pass --deck DECK"
    )


def load_scene(trace: str, deck: str | None) -> tuple[TraceInfo, object, Scene]:
    """Sidecar, model and :class:`Scene` of ``trace``."""
    from x3dpd.api.decks import build_model, read_deck

    info = trace_info(trace)
    path = find_deck(info, deck)
    if info.deck_sha256 and sha256_file(path) != info.deck_sha256:
        click.echo(
            f"x3dpd: warning: {path} differs from the deck that made {trace} (SHA-256); "
            f"drawing its geometry anyway",
            err=True,
        )
    model = build_model(read_deck(path))
    units = labels_for(getattr(model, "units", None))
    scene = scene_from_model(model, info.node_ids, units)
    if scene.unplaced:
        click.echo(
            f"x3dpd: warning: {scene.unplaced} wall vertices can move but neither they "
            f"nor their rigid master node are traced; they are drawn at their deck "
            f"coordinates (add the master node to the deck's TRACE card)",
            err=True,
        )
    return info, model, scene
