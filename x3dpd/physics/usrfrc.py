"""External nodal forces: the built-in force laws of X3D's USRFRC hook.

X3D calls the Fortran subroutine ``USRFRC`` once per step; it ADDs external forces to the nodal
force array (report AFRL-VA-WP-TR-2003-3053, Appendix C). x3dpd offers the same hook in two forms:

* built-in laws given as spec strings (``--usrfrc SPEC`` or the deck's USRFRC card), parsed by
  :func:`force_table` into a float table that :func:`_apply_forces` evaluates inside the step;
* a user file ``force.py`` defining ``usrfrc(time, coords, vels, force)``, compiled with numba by
  :func:`x3dpd.physics.user_force_file.load_user_force` so that the step calls it like a
  built-in law (that module also gathers both kinds: ``build_external_forces``).

Built-in specs (``kind:key=value,...``; ``dof`` 1..6 is X3D's numbering, 1-3 forces, 4-6 moments;
``phase`` is in degrees unless suffixed ``rad``; times in s, frequencies in Hz)::

    constant:node=N,dof=D,amp=A                       F = A
    step:node=N,dof=D,amp=A,t0=T0[,t1=T1]             F = A on [T0, T1), else 0
    sine:node=N,dof=D,amp=A,hz=F|omega=W[,phase=P][,t0=T0]
                                                      F = A sin(W (t - T0) + P) for t >= T0
    sweep:node=N,dof=D,amp=A,f0=F0,f1=F1,rate=R[,law=linear|log][,t0=T0][,end=hold|stop]
                                                      F = A sin(phi(t - T0)), phi = 2 pi int f

The full description with units and examples is ``docs/usrfrc.md``.
"""

from __future__ import annotations

import functools
import math
import os
import re

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.errors import UsrfrcError

# Kind codes stored in column 0 of a force table (0 is never used, so a zero row is an error).
KIND_CONSTANT = 1
KIND_STEP = 2
KIND_SINE = 3
KIND_SWEEP_LINEAR = 4
KIND_SWEEP_LOG = 5

#: Meaning of the 9 columns of a force table. ``p1..p5`` per kind:
#: constant: unused; step: t0, t1 (inf when open); sine: omega [rad/s], phase [rad], t0;
#: sweep (linear/log): f0 [Hz], f1 [Hz], signed rate k [Hz/s or octaves/s], t0,
#: end (0 hold, 1 stop).
TABLE_COLUMNS = ("kind", "node_index", "dof_index", "amp", "p1", "p2", "p3", "p4", "p5")

_KEYS = {  # kind -> (required keys, optional keys)
    "constant": (("node", "dof", "amp"), ()),
    "step": (("node", "dof", "amp", "t0"), ("t1",)),
    "sine": (("node", "dof", "amp"), ("hz", "omega", "phase", "t0")),
    "sweep": (("node", "dof", "amp", "f0", "f1", "rate"), ("law", "t0", "end")),
}
_TWO_PI = 2.0 * math.pi
_LN2 = math.log(2.0)


# ---------------------------------------------------------------------------------------------
# Kernels
# ---------------------------------------------------------------------------------------------

@step_kernel
def _sweep_duration(f0, f1, k, log_law):
    """Time [s] the sweep takes from ``f0`` to ``f1`` at signed rate ``k``."""
    if log_law:
        return math.log2(f1 / f0) / k
    return (f1 - f0) / k


@kernel
def _sweep_frequency(tau, f0, f1, k, log_law):
    """Instantaneous frequency [Hz] ``tau`` seconds after the sweep started (held at ``f1``)."""
    if tau <= 0.0:
        return f0
    if tau >= _sweep_duration(f0, f1, k, log_law):
        return f1
    if log_law:
        return f0 * math.exp(k * _LN2 * tau)
    return f0 + k * tau


@step_kernel
def _sweep_phase(tau, f0, f1, k, log_law):
    """Phase [rad] ``2 pi int_0^tau f(s) ds`` of a sweep, in closed form.

    linear: ``2 pi (f0 tau + k tau^2 / 2)``; log: ``2 pi f0 (2^(k tau) - 1) / (k ln 2)``;
    after the sweep ends at ``tau1`` the phase grows at ``2 pi f1`` (continuous at ``tau1``).
    """
    tau1 = _sweep_duration(f0, f1, k, log_law)
    s = min(tau, tau1)
    if log_law:
        phase = _TWO_PI * f0 * math.expm1(k * _LN2 * s) / (k * _LN2)
    else:
        phase = _TWO_PI * (f0 * s + 0.5 * k * s * s)
    if tau > tau1:
        phase += _TWO_PI * f1 * (tau - tau1)
    return phase


@step_kernel
def _force_value(t, table, r):
    """Value at time ``t`` of the force in row ``r`` of ``table`` (see :data:`TABLE_COLUMNS`)."""
    kind = int(table[r, 0])
    amp = table[r, 3]
    if kind == KIND_CONSTANT:
        return amp
    if kind == KIND_STEP:
        if t >= table[r, 4] and t < table[r, 5]:
            return amp
        return 0.0
    if kind == KIND_SINE:
        tau = t - table[r, 6]
        if tau < 0.0:
            return 0.0
        return amp * math.sin(table[r, 4] * tau + table[r, 5])
    # sweeps
    tau = t - table[r, 7]
    if tau < 0.0:
        return 0.0
    f0, f1, k = table[r, 4], table[r, 5], table[r, 6]
    log_law = kind == KIND_SWEEP_LOG
    if table[r, 8] != 0.0 and tau > _sweep_duration(f0, f1, k, log_law):
        return 0.0
    return amp * math.sin(_sweep_phase(tau, f0, f1, k, log_law))


@kernel
def _apply_forces(t, table, force):
    """ADD every force of ``table`` at time ``t`` [s] to ``force`` (n, 6)."""
    for r in range(table.shape[0]):
        force[int(table[r, 1]), int(table[r, 2])] += _force_value(t, table, r)


@kernel
def _force_values(times, table, out):
    for j in range(times.shape[0]):
        for r in range(table.shape[0]):
            out[j, r] = _force_value(times[j], table, r)


# ---------------------------------------------------------------------------------------------
# Spec parsing (shared with x3dpd.physics.motion)
# ---------------------------------------------------------------------------------------------

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
        raise UsrfrcError(f"{what} {spec!r}: dof={pairs['dof']!r}: expected 1..6 "
                          "(1-3 forces x, y, z; 4-6 moments about x, y, z)")
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


def _force_row(spec: str, node_ids: np.ndarray) -> list[float]:
    what = "usrfrc spec"
    kind, colon, body = spec.strip().partition(":")
    kind = kind.strip().lower()
    if not colon or kind not in _KEYS:
        raise UsrfrcError(f"{what} {spec!r}: unknown force kind {kind!r}; expected "
                          "constant:, step:, sine:, sweep: or a path to a .py user force file")
    pairs = _parse_pairs(what, spec, body, *_KEYS[kind])
    node, dof = _node_dof(what, spec, pairs, node_ids)
    amp = _number(what, spec, "amp", pairs["amp"])
    num = functools.partial(_number, what, spec)
    if kind == "constant":
        return [KIND_CONSTANT, node, dof, amp, 0.0, 0.0, 0.0, 0.0, 0.0]
    if kind == "step":
        t0 = num("t0", pairs["t0"])
        t1 = num("t1", pairs["t1"]) if "t1" in pairs else math.inf
        if t1 <= t0:
            raise UsrfrcError(f"{what} {spec!r}: t1={t1:g} must be later than t0={t0:g}")
        return [KIND_STEP, node, dof, amp, t0, t1, 0.0, 0.0, 0.0]
    t0 = num("t0", pairs["t0"]) if "t0" in pairs else 0.0
    if kind == "sine":
        omega = _omega(what, spec, pairs)
        phase = _phase(what, spec, pairs["phase"]) if "phase" in pairs else 0.0
        return [KIND_SINE, node, dof, amp, omega, phase, t0, 0.0, 0.0]
    f0 = num("f0", pairs["f0"], positive=True)
    f1 = num("f1", pairs["f1"], positive=True)
    rate = num("rate", pairs["rate"], positive=True)
    if f1 == f0:
        raise UsrfrcError(f"{what} {spec!r}: f0 == f1; use sine: for a fixed frequency")
    log_law = _choice(what, spec, pairs, "law", ("linear", "log"))
    stop = _choice(what, spec, pairs, "end", ("hold", "stop"))
    k = math.copysign(rate / 60.0 if log_law else rate, f1 - f0)  # log: octaves/min -> /s
    return [KIND_SWEEP_LOG if log_law else KIND_SWEEP_LINEAR, node, dof, amp, f0, f1, k, t0,
            float(stop)]


# ---------------------------------------------------------------------------------------------
# Public API: built-in forces
# ---------------------------------------------------------------------------------------------

def is_user_file(spec: str) -> bool:
    """True when ``spec`` names a user force file rather than a built-in law.

    A spec is a built-in law when it starts with ``constant:``, ``step:``, ``sine:`` or
    ``sweep:``; otherwise it is a file when it contains ``.py`` or is an existing path.
    """
    kind = spec.strip().partition(":")[0].strip().lower()
    if ":" in spec and kind in _KEYS:
        return False
    return ".py" in spec or os.path.exists(spec)


def split_specs(specs) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Split specs into ``(built-in law specs, user file paths)``, keeping their order."""
    specs = tuple(specs)
    return (tuple(s for s in specs if not is_user_file(s)),
            tuple(s.strip() for s in specs if is_user_file(s)))


def force_table(specs, model_or_node_ids) -> np.ndarray:
    """Parse built-in force specs into the float table the step kernel evaluates.

    Parameters
    ----------
    specs : iterable of str
        Built-in specs (see the module docstring); user files must go to :func:`load_user_force`.
    model_or_node_ids : Model or (n,) int array
        Ascending user node ids; ``node=`` values are resolved to indices into them.

    Returns
    -------
    (m, 9) float64 array, one row per spec, columns :data:`TABLE_COLUMNS`.

    Raises
    ------
    UsrfrcError
        Naming the spec and the bad key, value or undefined node.
    """
    node_ids = _node_ids(model_or_node_ids)
    rows = []
    for spec in specs:
        if is_user_file(spec):
            raise UsrfrcError(f"usrfrc spec {spec!r} is a user force file; "
                              "load it with load_user_force()")
        rows.append(_force_row(spec, node_ids))
    return np.array(rows, dtype=np.float64).reshape(len(rows), len(TABLE_COLUMNS))


def _check_table(table) -> np.ndarray:
    table = np.ascontiguousarray(table, dtype=np.float64)
    if table.ndim != 2 or table.shape[1] != len(TABLE_COLUMNS):
        raise ValueError(f"a force table has shape (m, {len(TABLE_COLUMNS)}); got {table.shape}")
    return table


def apply_forces(t: float, table: np.ndarray, force: np.ndarray) -> None:
    """ADD the forces of ``table`` at time ``t`` [s] to ``force`` (n, 6) float64, in place."""
    table = _check_table(table)
    if force.dtype != np.float64 or force.ndim != 2 or force.shape[1] != 6:
        raise ValueError(f"force must be (n, 6) float64; got {force.shape} {force.dtype}")
    if table.shape[0] and (table[:, 1].max() >= force.shape[0]):
        raise ValueError("the force table refers to a node index outside the force array")
    _apply_forces(float(t), table, force)


def force_values(times, table) -> np.ndarray:
    """Value of every table row at every time: ``(len(times), m)`` [force or moment units]."""
    times = np.atleast_1d(np.asarray(times, dtype=np.float64))
    table = _check_table(table)
    out = np.empty((times.shape[0], table.shape[0]))
    _force_values(times, table, out)
    return out


def _sweep_row(row):
    row = np.asarray(row, dtype=np.float64)
    if row.shape != (len(TABLE_COLUMNS),) or int(row[0]) not in (KIND_SWEEP_LINEAR,
                                                                  KIND_SWEEP_LOG):
        raise ValueError("expected one sweep row of a force table")
    return row[7], row[4], row[5], row[6], int(row[0]) == KIND_SWEEP_LOG


def sweep_frequency(times, row) -> np.ndarray:
    """Instantaneous frequency [Hz] of a sweep row at ``times`` [s] (``f0`` before ``t0``)."""
    t0, f0, f1, k, log_law = _sweep_row(row)
    return np.array([_sweep_frequency(t - t0, f0, f1, k, log_law)
                     for t in np.atleast_1d(np.asarray(times, dtype=np.float64))])


def sweep_phase(times, row) -> np.ndarray:
    """Phase [rad] of a sweep row at ``times`` [s], ``2 pi int_t0^t f dt`` (0 before ``t0``)."""
    t0, f0, f1, k, log_law = _sweep_row(row)
    return np.array([_sweep_phase(max(t - t0, 0.0), f0, f1, k, log_law)
                     for t in np.atleast_1d(np.asarray(times, dtype=np.float64))])
