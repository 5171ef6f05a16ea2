"""Parsing of ``key=value`` force and motion specs: the fields shared by the built-in USRFRC laws
(:mod:`x3dpd.physics.usrfrc`), prescribed motion (:mod:`x3dpd.physics.motion`) and random
excitation (:mod:`x3dpd.physics.random_signal`).

Every helper raises :class:`~x3dpd.errors.UsrfrcError` naming the spec and the offending key,
value or node (exit status 2).
"""

from __future__ import annotations

import math
import re

import numpy as np

from x3dpd.errors import UsrfrcError

_TWO_PI = 2.0 * math.pi


def _node_ids(model_or_node_ids) -> np.ndarray:
    """The ascending node id array of a Model or of an array-like of ids."""
    ids = np.asarray(getattr(model_or_node_ids, "node_ids", model_or_node_ids), dtype=np.int64)
    if ids.ndim != 1 or (ids.size > 1 and np.any(np.diff(ids) <= 0)) or np.any(ids < 0):
        raise ValueError("node_ids must be a 1-D array of ascending, distinct, non-negative ids")
    return ids


def _parse_pairs(what, spec, body, required, optional):
    """Split ``key=value,...`` into a dict, rejecting unknown, repeated and missing keys."""
    pairs = {}
    for item in body.split(","):
        item = item.strip()
        if not item:
            raise UsrfrcError(f"{what} {spec!r}: empty item (stray comma?)")
        key, eq, value = item.partition("=")
        key = key.strip().lower()
        if not eq or not value.strip():
            raise UsrfrcError(f"{what} {spec!r}: item {item!r} is not key=value")
        if key not in required and key not in optional:
            allowed = ", ".join(required + optional)
            raise UsrfrcError(f"{what} {spec!r}: unknown key {key!r} (allowed: {allowed})")
        if key in pairs:
            raise UsrfrcError(f"{what} {spec!r}: key {key!r} given twice")
        pairs[key] = value.strip()
    missing = [k for k in required if k not in pairs]
    if missing:
        raise UsrfrcError(f"{what} {spec!r}: missing required key(s) {', '.join(missing)}")
    return pairs


def _number(what, spec, key, text, positive=False):
    """A finite float (Fortran ``1.0d-3`` accepted); ``positive`` demands > 0."""
    try:
        value = float(text)
    except ValueError:
        try:
            value = float(text.lower().replace("d", "e"))
        except ValueError:
            value = math.nan
            if not re.fullmatch(r"\s*nan\s*", text, re.I):
                raise UsrfrcError(f"{what} {spec!r}: {key}={text!r} is not a number") from None
    if not math.isfinite(value) or (positive and value <= 0.0):
        kind = "a positive finite number" if positive else "a finite number"
        raise UsrfrcError(f"{what} {spec!r}: {key}={text!r}: expected {kind}")
    return value


def _phase(what, spec, text):
    """Phase in radians from ``90``/``90deg`` (degrees) or ``1.5708rad`` (radians)."""
    low = text.strip().lower()
    if low.endswith("rad"):
        return _number(what, spec, "phase", low[:-3])
    if low.endswith("deg"):
        low = low[:-3]
    return math.radians(_number(what, spec, "phase", low))


def _node_dof(what, spec, pairs, node_ids):
    """Resolve ``node`` (user id) to an index and ``dof`` (1..6) to a 0-based column."""
    try:
        nid = int(pairs["node"])
    except ValueError:
        raise UsrfrcError(f"{what} {spec!r}: node={pairs['node']!r} is not an integer") from None
    i = int(np.searchsorted(node_ids, nid))
    if i >= node_ids.shape[0] or node_ids[i] != nid:
        raise UsrfrcError(f"{what} {spec!r}: node={nid} is not defined in the model")
    try:
        dof = int(pairs["dof"])
    except ValueError:
        dof = 0
    if not 1 <= dof <= 6:
        meaning = (
            "1-3 displacements along x, y, z; 4-6 rotations about them"
            if what.startswith("motion")
            else "1-3 forces x, y, z; 4-6 moments about x, y, z"
        )
        raise UsrfrcError(f"{what} {spec!r}: dof={pairs['dof']!r}: expected 1..6 ({meaning})")
    return i, dof - 1


def _omega(what, spec, pairs):
    """Circular frequency [rad/s] from exactly one of ``hz`` and ``omega``."""
    if ("hz" in pairs) == ("omega" in pairs):
        raise UsrfrcError(f"{what} {spec!r}: give exactly one of hz= (Hz) or omega= (rad/s)")
    if "hz" in pairs:
        return _TWO_PI * _number(what, spec, "hz", pairs["hz"], positive=True)
    return _number(what, spec, "omega", pairs["omega"], positive=True)


def _choice(what, spec, pairs, key, choices):
    value = pairs.get(key, choices[0]).lower()
    if value not in choices:
        raise UsrfrcError(f"{what} {spec!r}: {key}={value!r}: expected one of {', '.join(choices)}")
    return choices.index(value)
