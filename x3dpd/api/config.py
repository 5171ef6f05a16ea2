"""One run, configured once: :class:`RunConfig`, built by :func:`run_config` from a deck and the
options of :func:`x3dpd.run` (docs/python-api.md).

Every default a run has is resolved here, once, and every option checked here, before anything
is compiled or written (the resolutions: x3dpd.api.run_options). Whatever runs a deck --
``x3dpd run``, a sweep point, a ring-down, a study's setting -- builds one and hands it on; the
steps of a run (x3dpd.api.run_steps, run_record) read it and resolve nothing again. The options
and what they resolve to:

* ``tmax`` [s]: the deck's TMAX; ``dt`` [s] or ``"auto"``: the deck's DTMAX, or ``"auto"`` (a
  step chosen by accuracy in DTMIN ... DTMAX) when its DTMIN < DTMAX; ``itrac``: the deck's
  ITRAC (with ``"auto"`` every ITRAC x DTMAX of simulated time); ``trace_nodes`` (node ids, or
  ``"structure"``): the TRACE card's;
* ``usrfrc``, ``motion`` (specs, docs/usrfrc.md), ``usrfrc_mode`` (``"replace"`` the deck's
  USRFRC card, or ``"add"`` to it), ``usrfrc_python``; ``friction``: the deck's FRICTION card's
  tangential law, else :data:`DEFAULT_FRICTION` (a name of x3dpd.physics.tangential_laws);
  ``temperature``: the deck's TEMPERATURE card's operating temperature (``"850F"``, or a number
  on the UNITS card's scale: the card's OPERATING replaced, x3dpd.deck.temperature_card);
* ``trace``, ``energy``, ``overwrite``, ``restart``, ``command``: the files (none without
  ``trace``); ``keep_trace``: the rows in memory; ``initial_state``: an earlier run's
  ``final_state`` to continue from;
* ``stop`` (every ``stop_every`` rows), ``progress``, ``on_compile``, ``handle_signals``: the
  callbacks; ``penetration_limit`` (:data:`PENETRATION_LIMIT`), ``energy_tolerance``
  (:data:`ENERGY_TOLERANCE`), ``threads`` (1, or ``"auto"``): the checks and the threads.

Bad options raise :class:`~x3dpd.errors.InputError` (a bad deck
:class:`~x3dpd.errors.DeckError`).
"""

from __future__ import annotations

import inspect
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from x3dpd.api.loop import STOP_CHECK_ROWS
from x3dpd.api.outputs import deck_key
from x3dpd.api.results import FinalState
from x3dpd.api.run_options import (
    DEFAULT_FRICTION,
    Files,
    Step,
    build_scene,
    check_initial_state,
    output_files,
    read_deck_file,
    step_counts,
    tangential_law,
    time_step,
    trace_interval,
    traced_nodes,
)
from x3dpd.api.safety import initial_penetration_error
from x3dpd.deck.temperature_card import with_temperature
from x3dpd.errors import InputError
from x3dpd.solver.threads import thread_count

__all__ = [
    "DEFAULT_FRICTION",
    "ENERGY_TOLERANCE",
    "Files",
    "PENETRATION_LIMIT",
    "RunConfig",
    "Step",
    "run_config",
]

#: The energy audit's default tolerance, a fraction of the energy scale (``energy_tolerance``).
ENERGY_TOLERANCE = 0.05
#: The default penetration limit, a fraction of the radius (``penetration_limit``).
PENETRATION_LIMIT = 0.25
#: How a run's ``usrfrc`` treats the deck's USRFRC card.
USRFRC_MODES = ("replace", "add")
#: The options that change the model a run builds (the rest reuse it, :meth:`RunConfig.replace`).
MODEL_OPTIONS = frozenset({"usrfrc", "usrfrc_mode", "motion", "temperature"})


@dataclass(frozen=True)
class RunConfig:
    """Everything one run does, resolved and checked (:func:`run_config` builds it;
    :func:`x3dpd.run` runs it). Fields are the options of :func:`x3dpd.run` with every default
    filled in, and what they resolve to:

    ``deck`` (a Deck, as given: at its own TEMPERATURE card's temperature), ``deck_path``,
    ``model`` (built, at ``temperature`` when one is asked for; the deck's USRFRC card dropped
    when ``usrfrc`` replaces it, those specs in ``replaced``), ``key`` (the identity of the deck
    it ran, at that temperature, for restarts), ``usrfrc`` and ``motion`` (the run's force and
    motion specs), ``friction`` (the tangential law), ``tmax`` [s], ``step`` (:class:`Step`),
    ``itrac`` (steps between trace rows; DTMAX steps with an automatic step), ``steps`` (steps
    of ``step.dt`` from t0 to TMAX), ``trest_steps`` (between restart dumps, 0: none),
    ``trace_nodes`` (indices of the recorded nodes in the model), ``threads``,
    ``penetration_limit``, ``energy_tolerance``, ``usrfrc_python``, ``files`` (:class:`Files`,
    None: the run writes nothing), ``keep_trace``, ``initial_state``, and the callbacks ``stop``
    (every ``stop_every`` rows), ``progress``, ``on_compile``, ``handle_signals``.
    """

    deck: object = field(repr=False)
    deck_path: str
    model: object = field(repr=False)
    key: str = field(repr=False)
    usrfrc: tuple[str, ...]
    motion: tuple[str, ...]
    replaced: tuple[str, ...]
    friction: str
    tmax: float
    step: Step
    itrac: int
    steps: int
    trest_steps: int
    trace_nodes: tuple[int, ...] = field(repr=False)
    threads: int
    penetration_limit: float
    energy_tolerance: float
    usrfrc_python: bool
    files: Files | None
    keep_trace: bool
    initial_state: FinalState | None = field(repr=False)
    stop: Callable | None = field(repr=False)
    stop_every: int
    progress: Callable | None = field(repr=False)
    on_compile: Callable | None = field(repr=False)
    handle_signals: bool
    #: the options given to run_config, every one (what :meth:`replace` starts from)
    asked: dict = field(repr=False, compare=False)

    @property
    def applied(self) -> tuple[str, ...]:
        """Every force spec the run applies: the deck's card (unless replaced), then its own."""
        return tuple(self.model.usrfrc) + self.usrfrc

    def replace(self, **changes) -> RunConfig:
        """This run with some options changed (the keywords of :func:`run_config`), resolved
        and checked again. The deck is not read again, nor its model rebuilt unless ``usrfrc``,
        ``usrfrc_mode``, ``motion`` or ``temperature`` change."""
        _check_names(changes)
        options = {**self.asked, **changes}
        if MODEL_OPTIONS & changes.keys():
            return _resolve(self.deck, self.deck_path, None, options)
        built = (self.model, self.replaced, self.key)
        return _resolve(self.deck, self.deck_path, built, options)

    def starting_from(self, state: FinalState | None) -> RunConfig:
        """This run continuing from ``state`` (``result.final_state`` of an earlier run, or a
        state a tool placed; None: the deck's initial state)."""
        return self if state is self.initial_state else self.replace(initial_state=state)


def run_config(
    deck,
    *,
    tmax: float | None = None,
    dt: float | str | None = None,
    usrfrc: Sequence[str] = (),
    usrfrc_mode: str = "replace",
    motion: Sequence[str] = (),
    friction: str | None = None,
    temperature: str | float | None = None,
    trace: str | os.PathLike | None = None,
    energy: str | os.PathLike | None = None,
    overwrite: bool = False,
    restart: bool = False,
    itrac: int | None = None,
    trace_nodes: Sequence[int] | str | None = None,
    keep_trace: bool = True,
    initial_state: FinalState | None = None,
    stop: Callable | None = None,
    stop_every: int = STOP_CHECK_ROWS,
    progress: Callable | None = None,
    on_compile: Callable | None = None,
    usrfrc_python: bool = False,
    penetration_limit: float = PENETRATION_LIMIT,
    energy_tolerance: float = ENERGY_TOLERANCE,
    threads: int | str = 1,
    handle_signals: bool = False,
    command: str | None = None,
) -> RunConfig:
    """The :class:`RunConfig` of a run of ``deck`` (a deck file, or a Deck from
    :func:`x3dpd.load_deck`) with these options (the module doc lists them; docs/python-api.md
    their defaults): the deck read, its model built, every default resolved and every option
    checked. Raises DeckError / InputError; writes nothing."""
    options = {k: v for k, v in locals().items() if k != "deck"}
    from x3dpd.deck import Deck

    if isinstance(deck, Deck):
        return _resolve(deck, str(deck.path), None, options)
    return _resolve(None, os.fspath(deck), None, options)


def _check_names(changes: dict) -> None:
    unknown = sorted(set(changes) - set(_DEFAULTS))
    if unknown:
        raise TypeError(f"unexpected run option(s): {', '.join(unknown)}")


def _resolve(deck, deck_path: str, built, o: dict) -> RunConfig:
    """The RunConfig of the options ``o`` (every option of run_config): ``deck`` (None: read
    ``deck_path``) and, unless ``built`` gives them, its model, the specs it replaced and its
    key."""
    threads = thread_count(o["threads"])
    if not o["energy_tolerance"] > 0.0:
        raise InputError(
            f"energy_tolerance must be a positive fraction of the energy scale, "
            f"got {o['energy_tolerance']!r}"
        )
    if o["usrfrc_mode"] not in USRFRC_MODES:
        raise InputError(f"usrfrc_mode must be 'replace' or 'add', got {o['usrfrc_mode']!r}")
    usrfrc, motion = tuple(o["usrfrc"]), tuple(o["motion"])
    if deck is None:
        deck = read_deck_file(deck_path)
    if built is None:  # at another temperature: the card's OPERATING replaced, the deck kept
        warm = deck if o["temperature"] is None else with_temperature(deck, o["temperature"])
        built = (*build_scene(warm, usrfrc, motion, o["usrfrc_mode"]), deck_key(warm))
    model, replaced, key = built
    files = output_files(deck_path, model, o)
    tmax = o["tmax"]
    if tmax is not None and not math.isfinite(tmax):
        raise InputError(f"--tmax must be a finite number of seconds, got {tmax}")
    tmax = float(tmax if tmax is not None else model.tmax)
    fresh = o["initial_state"] is None and not (files is not None and files.resume)
    if fresh:
        err = initial_penetration_error(model, o["penetration_limit"], deck_path)
        if err is not None:
            raise err
    step = time_step(o["dt"], deck.parameters, model)
    itrac = trace_interval(o["itrac"], model)
    steps, trest_steps = step_counts(model, tmax, step.dt)
    check_initial_state(o["initial_state"], key, step)
    return RunConfig(
        deck=deck,
        deck_path=deck_path,
        model=model,
        key=key,
        usrfrc=usrfrc,
        motion=motion,
        replaced=replaced,
        friction=tangential_law(o["friction"], model),
        tmax=tmax,
        step=step,
        itrac=itrac,
        steps=steps,
        trest_steps=trest_steps,
        trace_nodes=traced_nodes(model, o["trace_nodes"]),
        threads=threads,
        penetration_limit=float(o["penetration_limit"]),
        energy_tolerance=float(o["energy_tolerance"]),
        usrfrc_python=bool(o["usrfrc_python"]),
        files=files,
        keep_trace=bool(o["keep_trace"]),
        initial_state=o["initial_state"],
        stop=o["stop"],
        stop_every=o["stop_every"],
        progress=o["progress"],
        on_compile=o["on_compile"],
        handle_signals=bool(o["handle_signals"]),
        asked=dict(o),
    )


#: Every option of run_config and its default (what an option not given resolves from).
_DEFAULTS = {
    name: p.default
    for name, p in inspect.signature(run_config).parameters.items()
    if name != "deck"
}
