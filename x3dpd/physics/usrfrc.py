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
    sine:node=N,dof=D,amp=A,hz=F|omega=W[,phase=P][,t0=T0][,amp1=A1,ramp=TR]
                                                      F = a(t) sin(W (t - T0) + P) for t >= T0,
                                                      a = A, or A -> A1 linearly over TR s
    sweep:node=N,dof=D,amp=A,f0=F0,f1=F1,rate=R[,law=linear|log][,t0=T0][,end=hold|stop]
                                                      F = A sin(phi(t - T0)), phi = 2 pi int f
    random:node=N,dof=D,rms=R|psd=P,band=LO:HI,seed=S[,t0=T0][,period=T]
                                                      band-limited random, flat PSD over the
                                                      band (x3dpd.physics.random_signal)

The full description with units and examples is ``docs/usrfrc.md``.
"""

from __future__ import annotations

import functools
import math
import os

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.errors import UsrfrcError
from x3dpd.physics.random_signal import RandomLaw, _signal_state, attach_blocks, parse_random
from x3dpd.physics.spec_fields import (  # noqa: F401  (re-exported: the spec fields' old home)
    _choice,
    _node_dof,
    _node_ids,
    _number,
    _omega,
    _parse_pairs,
    _phase,
)

# Kind codes stored in column 0 of a force table (0 is never used, so a zero row is an error).
KIND_CONSTANT = 1
KIND_STEP = 2
KIND_SINE = 3
KIND_SWEEP_LINEAR = 4
KIND_SWEEP_LOG = 5
KIND_RANDOM = 6
#: Column 0 of the row after the last law when a table carries random signals' knots (the laws'
#: loops stop there; x3dpd.physics.random_signal).
KIND_DATA = -1

#: Meaning of the 9 columns of a force table. ``p1..p5`` per kind:
#: constant: unused; step: t0, t1 (inf when open); sine: omega [rad/s], phase [rad], t0,
#: the envelope's end amplitude A1 and ramp time TR [s] (TR 0: a constant amplitude);
#: sweep (linear/log): f0 [Hz], f1 [Hz], signed rate k [Hz/s or octaves/s], t0,
#: end (0 hold, 1 stop); random: first row of its knots, LO, HI [Hz], t0, seed (amp: RMS).
TABLE_COLUMNS = ("kind", "node_index", "dof_index", "amp", "p1", "p2", "p3", "p4", "p5")

_KEYS = {  # kind -> (required keys, optional keys)
    "constant": (("node", "dof", "amp"), ()),
    "step": (("node", "dof", "amp", "t0"), ("t1",)),
    "sine": (("node", "dof", "amp"), ("hz", "omega", "phase", "t0", "amp1", "ramp")),
    "sweep": (("node", "dof", "amp", "f0", "f1", "rate"), ("law", "t0", "end")),
    "random": None,  # x3dpd.physics.random_signal parses it
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
        if table[r, 8] > 0.0:   # the envelope: A -> A1 linearly over TR, then A1
            amp += (table[r, 7] - amp) * min(tau / table[r, 8], 1.0)
        return amp * math.sin(table[r, 4] * tau + table[r, 5])
    if kind == KIND_RANDOM:
        tau = t - table[r, 7]
        if tau < 0.0:
            return 0.0
        return amp * _signal_state(tau, table, int(table[r, 4]))[0]
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
        if table[r, 0] == KIND_DATA:
            break
        force[int(table[r, 1]), int(table[r, 2])] += _force_value(t, table, r)


@kernel
def _force_values(times, table, out):
    for j in range(times.shape[0]):
        for r in range(out.shape[1]):
            out[j, r] = _force_value(times[j], table, r)


# ---------------------------------------------------------------------------------------------
# Spec parsing (fields shared with x3dpd.physics.motion: x3dpd.physics.spec_fields)
# ---------------------------------------------------------------------------------------------


def _force_row(spec: str, node_ids: np.ndarray) -> list[float] | RandomLaw:
    what = "usrfrc spec"
    kind, colon, body = spec.strip().partition(":")
    kind = kind.strip().lower()
    if not colon or kind not in _KEYS:
        raise UsrfrcError(f"{what} {spec!r}: unknown force kind {kind!r}; expected "
                          "constant:, step:, sine:, sweep:, random: or a path to a .py user "
                          "force file")
    if kind == "random":
        return parse_random(what, spec, body, node_ids)
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
        if ("amp1" in pairs) != ("ramp" in pairs):
            raise UsrfrcError(f"{what} {spec!r}: an envelope needs both amp1 (the amplitude it "
                              "reaches) and ramp (the seconds it takes)")
        amp1 = num("amp1", pairs["amp1"]) if "amp1" in pairs else 0.0
        ramp = num("ramp", pairs["ramp"], positive=True) if "ramp" in pairs else 0.0
        return [KIND_SINE, node, dof, amp, omega, phase, t0, amp1, ramp]
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

def is_user_file(spec: str, folder: str | os.PathLike | None = None) -> bool:
    """True when ``spec`` names a user force file rather than a built-in law.

    A spec is a built-in law when it starts with ``constant:``, ``step:``, ``sine:``,
    ``sweep:`` or ``random:``; otherwise it is a file when it contains ``.py`` or is an
    existing path: relative to ``folder`` when given (a deck's USRFRC card: the deck's folder,
    whatever the working directory), else to the working directory (``--usrfrc``).
    """
    kind = spec.strip().partition(":")[0].strip().lower()
    if ":" in spec and kind in _KEYS:
        return False
    path = spec.strip()
    if folder is not None and not os.path.isabs(path):
        path = os.path.join(folder, path)
    return ".py" in spec or os.path.exists(path)


def split_specs(specs, folder: str | os.PathLike | None = None
                ) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Split specs into ``(built-in law specs, user file paths)``, keeping their order (files
    told as :func:`is_user_file` tells them, from ``folder``)."""
    specs = tuple(specs)
    return (tuple(s for s in specs if not is_user_file(s, folder)),
            tuple(s.strip() for s in specs if is_user_file(s, folder)))


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
    (m, 9) float64 array, one row per spec, columns :data:`TABLE_COLUMNS`; with ``random:``
    laws, a :data:`KIND_DATA` row and their knots follow (:func:`law_count` rows are laws).

    Raises
    ------
    UsrfrcError
        Naming the spec and the bad key, value or undefined node.
    """
    node_ids = _node_ids(model_or_node_ids)
    rows, laws = [], []
    for spec in specs:
        if ".py" in spec and is_user_file(spec):  # the caller tells files (from their folder)
            raise UsrfrcError(f"usrfrc spec {spec!r} is a user force file; "
                              "load it with load_user_force()")
        row = _force_row(spec, node_ids)
        if isinstance(row, RandomLaw):
            laws.append((len(rows), row))
            row = [KIND_RANDOM, row.node, row.dof, row.rms, 0.0, row.lo, row.hi, row.t0,
                   float(row.seed)]
        rows.append(row)
    header = [KIND_DATA] + [0.0] * (len(TABLE_COLUMNS) - 1)
    return attach_blocks(rows, laws, 4, header)


def law_count(table) -> int:
    """Number of law rows of a force table (the rows before its :data:`KIND_DATA` row)."""
    hit = np.flatnonzero(np.asarray(table)[:, 0] == KIND_DATA)
    return int(hit[0]) if hit.size else int(np.asarray(table).shape[0])


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
    m = law_count(table)
    if m and (table[:m, 1].max() >= force.shape[0]):
        raise ValueError("the force table refers to a node index outside the force array")
    _apply_forces(float(t), table, force)


def force_values(times, table) -> np.ndarray:
    """Value of every law of the table at every time: ``(len(times), m)`` [force or moment
    units], ``m`` = :func:`law_count`."""
    times = np.atleast_1d(np.asarray(times, dtype=np.float64))
    table = _check_table(table)
    out = np.empty((times.shape[0], law_count(table)))
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
