"""x3dpd's Python API: run decks, check them, read their results (docs/python-api.md).

>>> import x3dpd
>>> result = x3dpd.run("decks/impact_wall.inp")          # doctest: +SKIP
>>> result.trace.velocity[-1, -1]                         # doctest: +SKIP

The command line is a thin layer over these functions; sweeps and studies use them too.
"""

from __future__ import annotations

import os

from x3dpd.api.config import DEFAULT_FRICTION, RunConfig, run_config
from x3dpd.api.deck_step import FittedStep, fit_time_step, soft_step, softened
from x3dpd.api.results import Chunk, FinalState, RunResult
from x3dpd.api.runner import run
from x3dpd.errors import DeckError, InputError, TraceError, UnstableRunError, X3dpdError
from x3dpd.io.energy import EnergyData, read_energy
from x3dpd.io.trace import TraceData, read_trace
from x3dpd.physics.tangential_laws import TANGENTIAL_LAWS

#: The tangential laws a run can select (``run(friction=...)``, ``x3dpd run --friction``): the
#: registry's names (x3dpd.physics.tangential_laws), so that a law's registration line is all
#: it takes to offer it.
FRICTION_LAWS = tuple(TANGENTIAL_LAWS)


def load_deck(path: str | os.PathLike, *, temperature=None):
    """Read a deck file into typed cards (:class:`x3dpd.deck.Deck`); ``temperature`` (not None:
    ``"850F"``, or a number on the scale of the deck's UNITS card) replaces its TEMPERATURE
    card's operating temperature.

    Raises :class:`DeckError` (``FILE:LINE:COL: CARD: message``) on the first bad token, and
    :class:`InputError` for a temperature without a TEMPERATURE card to apply it to.
    """
    from x3dpd.api.run_options import read_deck_file
    from x3dpd.deck.temperature_card import with_temperature

    deck = read_deck_file(os.fspath(path))
    return deck if temperature is None else with_temperature(deck, temperature)


def build(deck, *, usrfrc=(), motion=(), temperature=None):
    """The model of a deck (path or :class:`~x3dpd.deck.Deck`): the arrays the solver runs;
    ``temperature`` (not None) the operating temperature over its TEMPERATURE card's."""
    from x3dpd.deck import Deck
    from x3dpd.deck.temperature_card import with_temperature
    from x3dpd.model.build import build_model

    if not isinstance(deck, Deck):
        deck = load_deck(deck)
    if temperature is not None:
        deck = with_temperature(deck, temperature)
    return build_model(deck, usrfrc=tuple(usrfrc), motion=tuple(motion))


def check(deck, *, usrfrc=(), motion=(), steps_per_contact: int | None = None, temperature=None):
    """What ``x3dpd check`` reports for a deck: a :class:`x3dpd.model.check.CheckReport`
    (``errors``, ``warnings``, ``time_step``, ``exit_status`` ...).

    Raises :class:`DeckError` / :class:`InputError` when the deck cannot be read or built.
    """
    from x3dpd.model.check import check_model
    from x3dpd.model.timestep import STEPS_PER_CONTACT

    model = build(deck, usrfrc=usrfrc, motion=motion, temperature=temperature)
    return check_model(
        model, steps_per_contact=steps_per_contact or STEPS_PER_CONTACT, usrfrc=usrfrc
    )


def rules_of_thumb(deck, *, usrfrc=(), motion=(), drive=None):
    """The report's rules of thumb for a deck (path, Deck or built model): a list of
    :class:`x3dpd.model.rules_of_thumb.RuleNote` (code, value, text, section) -- turn-on level,
    clearance, mass ratio, mode separation. ``drive`` (a :class:`~x3dpd.model.rules_of_thumb.
    DriveEstimate`) replaces the estimate of the deck's USRFRC drive."""
    from x3dpd.model.model import Model
    from x3dpd.model.rules_of_thumb import rules_of_thumb as rules

    model = deck if isinstance(deck, Model) else build(deck, usrfrc=usrfrc, motion=motion)
    return rules(model, usrfrc=usrfrc, drive=drive)


__all__ = [
    "Chunk",
    "DEFAULT_FRICTION",
    "DeckError",
    "EnergyData",
    "FRICTION_LAWS",
    "FinalState",
    "FittedStep",
    "InputError",
    "RunConfig",
    "RunResult",
    "TraceData",
    "TraceError",
    "UnstableRunError",
    "X3dpdError",
    "build",
    "check",
    "fit_time_step",
    "load_deck",
    "rules_of_thumb",
    "read_energy",
    "read_trace",
    "run",
    "run_config",
    "soft_step",
    "softened",
]
