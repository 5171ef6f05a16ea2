"""The files of a run: paths, the trace sidecar's run description, restart dumps and the checks
that a dump belongs to the run that resumes from it (docs/running.md, "Restart").

A run that writes files writes, side by side: the trace ``<stem>.trace.txt`` (report Appendix E
format) and its sidecar ``.json``, the energy ledger ``<stem>.energy.csv`` and the restart dump
``<trace>.restart.npz`` (every TREST of simulated time, on Ctrl-C and at the end of the run, so
that a finished run can be extended with a later TMAX).
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import fields, is_dataclass, replace
from pathlib import Path

import numpy as np

from x3dpd.errors import InputError, Pos


def default_paths(
    deck_path: str, trace: str | None = None, energy: str | None = None
) -> tuple[str, str, str]:
    """(trace, energy, restart dump) paths of a run of ``deck_path``.

    The trace defaults to ``<deck stem>.trace.txt`` in the current directory; the energy file to
    the trace's name with ``.trace.txt`` replaced by ``.energy.csv`` (else ``+ .energy.csv``);
    the dump is always ``<trace>.restart.npz``.
    """
    trace = trace or f"{Path(deck_path).stem}.trace.txt"
    if energy:
        pass
    elif trace.endswith(".trace.txt"):
        energy = trace[: -len(".trace.txt")] + ".energy.csv"
    else:
        energy = trace + ".energy.csv"
    return trace, energy, trace + ".restart.npz"


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


_POSITION_FIELDS = frozenset(
    {"pos", "positions", "slave_positions", "path", "value_pos", "node_pos", "housing_pos"}
)
#: Cards added to the language later: absent, they leave the key of older decks unchanged.
_ABSENT_IS_OLD = frozenset(
    {
        "units",
        "hooke",
        "analytic_walls",
        "modal",
        "wallmat",
        "friction",
        "plates",
        "temperature",
        "unit_records",
    }
)


def _plain(obj):
    """Cards as nested tuples of (field, value), positions left out; floats as repr."""
    if isinstance(obj, Pos):
        return None  # where a value stands is not what it is
    if isinstance(obj, np.ndarray):
        return hashlib.sha256(np.ascontiguousarray(obj).tobytes()).hexdigest()
    if is_dataclass(obj) and not isinstance(obj, type):
        out = (type(obj).__name__,)
        for f in fields(obj):
            value = getattr(obj, f.name)
            if f.name in _POSITION_FIELDS or (f.name in _ABSENT_IS_OLD and value is None):
                continue
            out += (
                _analytic_plain(value) if f.name == "analytic_walls" else ((f.name, _plain(value)),)
            )
        return out
    if isinstance(obj, (tuple, list)):
        return tuple(_plain(v) for v in obj)
    if isinstance(obj, float):
        return repr(obj)
    return obj


def _analytic_plain(walls) -> tuple:
    """The analytic wall records in the form the CYLINDER card had before shapes were
    registered -- a field ``cylinders`` of ``Cylinder(set_id, node_a, node_b, radius)`` --
    one field per shape (``capsules`` ...), so restart dumps of earlier runs keep their key."""
    from x3dpd.geometry.shapes import BY_SHAPE_NAME

    groups: dict[str, list] = {}
    for w in walls:
        shape = BY_SHAPE_NAME[w.shape]
        names = ("set_id",) + tuple(n.lower() for n in shape.node_fields + shape.param_fields)
        values = (w.set_id,) + tuple(w.nodes) + tuple(repr(float(v)) for v in w.params)
        groups.setdefault(w.shape, []).append((w.shape.capitalize(),) + tuple(zip(names, values)))
    return tuple((f"{name}s", tuple(records)) for name, records in groups.items())


def user_file_hashes(specs) -> dict[str, str]:
    """SHA-256 of each user force file among ``specs`` (their content matters on restart)."""
    from x3dpd.io.trace import sha256_file
    from x3dpd.physics.usrfrc import is_user_file

    out = {}
    for s in specs:
        if is_user_file(s) and os.path.isfile(s):
            out[s] = sha256_file(s)
    return out


def sidecar_status(trace_path: str) -> str | None:
    """The ``status`` a trace's sidecar records (None without a readable sidecar)."""
    try:
        with open(trace_path + ".json", encoding="utf-8") as f:
            return json.load(f).get("status")
    except (OSError, ValueError, AttributeError):
        return None


def require_dump(dump_path: str, asked_by: str) -> None:
    """Refuse a resume whose restart dump does not exist (before anything is compiled)."""
    if not os.path.exists(dump_path):
        raise InputError(
            f"{asked_by} asks to resume from {dump_path}, which does not exist (it "
            "is written every TREST of simulated time, on Ctrl-C and at the end of "
            "a run). Run without --restart and with IREST = 0 to start from t0"
        )


def load_dump(dump_path: str, *, asked_by: str, sim, key: str, options: dict, model) -> dict:
    """Load the restart dump, refuse it when it belongs to another setup, restore the state.

    ``asked_by`` names what asked for the restart (``"--restart"``, ``"the deck's IREST = 1"``);
    ``options`` are the run's options that must equal the dump's (usrfrc, motion, friction,
    user file contents). Returns the dump's metadata.
    """
    from x3dpd.io.restart import load_restart
    from x3dpd.solver.state import State

    require_dump(dump_path, asked_by)
    arrays, meta = load_restart(dump_path)
    diffs = []
    if meta.get("deck_key") != key:
        diffs.append("the deck's cards differ (only TMAX, TREST and IREST may change)")
    if meta.get("dt") != sim.dt:
        diffs.append(f"dt {sim.dt!r} s (the dump's is {meta.get('dt')!r})")
    if meta.get("itrac") != sim.itrac:
        diffs.append(f"ITRAC {sim.itrac} (the dump's is {meta.get('itrac')})")
    old = meta.get("options", {})
    defaults = {"usrfrc_mode": "add", "step": "fixed"}
    for name in ("usrfrc", "motion", "friction", "usrfrc_files", "usrfrc_mode", "step"):
        theirs = old.get(name, defaults.get(name))
        if theirs != options[name]:
            label = {
                "usrfrc_files": "user force file contents",
                "step": "the step (auto: chosen by accuracy; fixed: --dt or DTMAX)",
                "usrfrc_mode": "--usrfrc replacing or adding to the deck's USRFRC",
            }.get(name, f"--{name}")
            diffs.append(f"{label}: {options[name]!r} (the dump's: {theirs!r})")
    if diffs:
        raise InputError(
            f"cannot resume from {dump_path}: it was written by a different "
            f"setup: " + "; ".join(diffs) + ". Resume with the dump's deck and "
            "options, or start anew without --restart (IREST = 0)"
        )
    try:
        state = State.from_arrays(arrays)
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(
            f"{dump_path}: the restart dump does not hold a solver state ({exc})"
        ) from None
    if state.x.shape != (model.n_nodes, 3):
        raise InputError(
            f"{dump_path}: the restart dump holds {state.x.shape[0]} nodes, the "
            f"deck {model.n_nodes}"
        )
    if options["step"] == "auto":  # the driver's level and step record too
        sim.restore(state, meta.get("variable_step"))
    else:
        sim.restore(state)  # the state carries the audit's energy scale too
    return meta


def check_writable(path: str, what: str) -> None:
    """Refuse, before any work, an output path whose folder does not exist or is a file."""
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InputError(f"{what} {path}: the folder {folder} does not exist")
    if os.path.isdir(path):
        raise InputError(f"{what} {path} is a folder, not a file")
    if not os.access(folder, os.W_OK):
        raise InputError(f"{what} {path}: the folder {folder} is not writable")


def open_outputs(trace_path, energy_path, sim, sidecar, meta, columns, *, overwrite: bool):
    """The trace and energy writers, new or resumed at the dump's offsets."""
    from x3dpd.io.energy import EnergyWriter, copy_backup
    from x3dpd.io.trace import TraceWriter

    ids = sim.model.node_ids[sim.trace_nodes]
    units = sidecar.get("units")
    if meta is None:
        if os.path.lexists(energy_path) and not overwrite:
            raise InputError(
                f"energy file {energy_path} already exists; pass --overwrite to "
                f"replace it (the old one is kept as {energy_path}.bak) or choose "
                "another --energy path"
            )
        writer = TraceWriter(trace_path, ids, sidecar, overwrite=overwrite, units=units)
        try:
            ewriter = EnergyWriter(energy_path, columns, overwrite=overwrite)
        except BaseException:
            writer.close("interrupted")
            raise
        return writer, ewriter
    tr, en = meta["trace"], meta["energy"]
    complete = sidecar_status(trace_path) == "complete"
    writer = TraceWriter(
        trace_path,
        ids,
        sidecar,
        overwrite=overwrite,
        units=units,
        append_at=(int(tr["bytes"]), int(tr["blocks"])),
    )
    try:
        if (
            complete
            and overwrite
            and os.path.isfile(energy_path)
            and os.path.getsize(energy_path) > int(en["bytes"])
        ):
            copy_backup(energy_path)
        ewriter = EnergyWriter(energy_path, columns, append_at=(int(en["bytes"]), int(en["rows"])))
    except BaseException:
        writer.close("interrupted")
        raise
    return writer, ewriter
