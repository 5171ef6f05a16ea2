"""Resuming ``x3dpd run`` from a restart dump: what identifies a run's setup, the check that a
dump belongs to it, and the command line that resumes it (docs/running.md, "Restart")."""

from __future__ import annotations

import hashlib
import json
import os
import shlex
from dataclasses import fields, is_dataclass, replace
from typing import TYPE_CHECKING

from x3dpd.errors import InputError

if TYPE_CHECKING:
    from x3dpd.cli.run import RunOptions


def deck_key(deck) -> str:
    """SHA-256 of the deck's cards (their values, in file order), with TMAX, TREST and IREST
    masked: what must not change between a restart dump and the run that resumes from it.

    Comments, spacing, number spelling and card positions do not count; ending later (TMAX),
    dumping at another interval (TREST) and switching IREST to 1 (X3D's way of asking for a
    restart) are allowed.
    """
    par = deck.parameters
    if par is not None:
        par = replace(par, tmax=0.0, trest=0.0, irest=0)
    plain = _plain(replace(deck, parameters=par, path="<deck>"))
    return hashlib.sha256(repr(plain).encode("utf-8")).hexdigest()


_POSITION_FIELDS = frozenset({"pos", "positions", "slave_positions", "path"})


def _plain(obj):
    """Cards as nested tuples of (field, value), positions left out; floats as repr."""
    if is_dataclass(obj) and not isinstance(obj, type):
        return (type(obj).__name__,) + tuple(
            (f.name, _plain(getattr(obj, f.name))) for f in fields(obj)
            if f.name not in _POSITION_FIELDS)
    if isinstance(obj, (tuple, list)):
        return tuple(_plain(v) for v in obj)
    if isinstance(obj, float):
        return repr(obj)
    return obj


def user_file_hashes(specs) -> dict[str, str]:
    """SHA-256 of each user force file among ``specs`` (their content matters on restart)."""
    from x3dpd.io.trace import sha256_file
    from x3dpd.physics.usrfrc import is_user_file

    out = {}
    for s in specs:
        if is_user_file(s) and os.path.isfile(s):
            out[s] = sha256_file(s)
    return out


def resume_command(opts: RunOptions) -> str:
    """The arguments that resume this run from its restart dump."""
    args = [opts.deck, "--restart"]
    if opts.trace:
        args += ["--trace", opts.trace]
    if opts.energy:
        args += ["--energy", opts.energy]
    for spec in opts.usrfrc:
        args += ["--usrfrc", spec]
    for spec in opts.motion:
        args += ["--motion", spec]
    if opts.usrfrc_python:
        args.append("--usrfrc-python")
    if opts.dt is not None:
        args += ["--dt", repr(opts.dt)]
    if opts.tmax is not None:
        args += ["--tmax", repr(opts.tmax)]
    if opts.friction != "regularized":
        args += ["--friction", opts.friction]
    return shlex.join(args)


def sidecar_status(trace_path: str) -> str | None:
    try:
        with open(trace_path + ".json", encoding="utf-8") as f:
            return json.load(f).get("status")
    except (OSError, ValueError, AttributeError):
        return None


def load_dump(dump_path, opts, sim, key, options, model) -> dict:
    """Load the restart dump, refuse it when it belongs to another setup, restore the state."""
    from x3dpd.io.restart import load_restart
    from x3dpd.solver.state import State

    if not os.path.exists(dump_path):
        why = "--restart" if opts.restart else "the deck's IREST = 1"
        raise InputError(f"{why} asks to resume from {dump_path}, which does not exist (it is "
                         "written every TREST of simulated time and on Ctrl-C). Run without "
                         "--restart and with IREST = 0 to start from t0")
    arrays, meta = load_restart(dump_path)
    diffs = []
    if meta.get("deck_key") != key:
        diffs.append("the deck's cards differ (only TMAX, TREST and IREST may change)")
    if meta.get("dt") != sim.dt:
        diffs.append(f"dt {sim.dt!r} s (the dump's is {meta.get('dt')!r})")
    if meta.get("itrac") != sim.itrac:
        diffs.append(f"ITRAC {sim.itrac} (the dump's is {meta.get('itrac')})")
    old = meta.get("options", {})
    for name in ("usrfrc", "motion", "friction", "usrfrc_files"):
        if old.get(name) != options[name]:
            label = {"usrfrc_files": "user force file contents"}.get(name, f"--{name}")
            diffs.append(f"{label}: {options[name]!r} (the dump's: {old.get(name)!r})")
    if diffs:
        raise InputError(f"cannot resume from {dump_path}: it was written by a different "
                         f"setup: " + "; ".join(diffs) + ". Resume with the dump's deck and "
                         "options, or start anew without --restart (IREST = 0)")
    try:
        state = State.from_arrays(arrays)
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{dump_path}: the restart dump does not hold a solver state "
                         f"({exc})") from None
    if state.x.shape != (model.n_nodes, 3):
        raise InputError(f"{dump_path}: the restart dump holds {state.x.shape[0]} nodes, the "
                         f"deck {model.n_nodes}")
    sim.restore(state)   # the state carries the audit's energy scale too
    return meta
