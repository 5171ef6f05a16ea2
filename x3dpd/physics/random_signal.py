"""Band-limited random excitation: a periodic random signal (a multisine with random phases)
with a flat one-sided power spectral density over a band, for USRFRC forces and base motion.

Spec (``--usrfrc``/USRFRC card, and ``--motion``)::

    random:node=N,dof=D,rms=R|psd=P,band=LO:HI,seed=S[,t0=0][,period=16][,ramp=0 (motion)]

The signal, with tau = t - t0 [s] and period T [s], is

.. math::

    s(\\tau) = \\sum_{l} A \\sin(2 \\pi f_l \\tau + \\varphi_l), \\qquad
    f_l = l / T, \\quad LO \\le f_l \\le HI, \\quad l \\ge 1,

with ``L`` lines on the grid ``1/T`` [Hz], phases ``phi_l = 2 pi U_l`` where ``U_l`` are the
first ``L`` doubles of numpy's PCG64 generator seeded with ``S``
(``numpy.random.default_rng(S).random(L)``), and one amplitude ``A = sqrt(2 P / T)`` for all
lines: each line carries the power ``A^2 / 2 = P / T``, the one-sided PSD ``P`` times the line
spacing, so the signal's PSD over any whole period is exactly ``P`` at every line of the band and
its RMS is ``sqrt(P L / T)`` (``rms=R`` sets ``P = R^2 T / L``). The signal repeats every ``T``
seconds.

For a force (USRFRC), F(t) = s(tau) for t >= t0 and 0 before, in force units (P in
force^2/Hz). For base motion (``--motion``) ``s`` is the **acceleration** u'' of the driven DOF
(P in (length/s^2)^2/Hz; LO > 0); the displacement and velocity are its exact integrals,
u = sum -A / w_l^2 sin(.), u' = sum A / w_l (-cos(.)) (no drift: every line has w_l > 0).

Evaluation: the signal and its first two derivatives are tabulated exactly (an inverse real FFT
of the line spectrum times 1, i w, -w^2) at N knots per period, N = ceil(8 HI T) (8 knots per
period of the highest line), and evaluated between knots by the quintic Hermite polynomial that
matches value, slope and curvature at both ends (:func:`_signal_state`). Its derivatives are
the polynomial's own, so u, u', u'' of a motion are consistent (C2), and the interpolation
errs by at most 5e-6 of a line's amplitude in the value, 2e-5 in the slope and 2e-4 in the
curvature at HI (less below). The value at a time depends on that time alone -- never on how a
run is cut into chunks or restarted -- and the same spec gives the same table, byte for byte.

The knots live in the law table itself, after the law rows (:func:`attach_blocks`): a marker row
says where the law rows end, then each signal's block: a row ``[N, rate, 1/rate, 0 ...]``
(``rate = N / T`` knots per second) and one row ``[s_j, s'_j, s''_j, 0 ...]`` per knot, each
signal normalised to unit RMS (the law row's amplitude column holds the RMS, another column the
block's first row). One knot per row wastes columns but needs no integer division in the step
(a lookup costs two row reads); the loops over a table's laws stop at the marker row.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from x3dpd._jit import step_kernel
from x3dpd.errors import UsrfrcError
from x3dpd.physics.spec_fields import _node_dof, _number, _parse_pairs

#: Knots per period of the band's highest line.
OVERSAMPLE = 8
#: Default period T of the signal [s] (line spacing 1/T = 0.0625 Hz).
DEFAULT_PERIOD = 16.0
#: Most knots a signal may use (one table row each: 72 MiB in a force table).
MAX_KNOTS = 2 ** 20

_REQUIRED = ("node", "dof", "band", "seed")
_OPTIONAL = ("rms", "psd", "t0", "period")


@dataclass(frozen=True)
class RandomLaw:
    """One parsed random spec: where it acts, its band and level, and its knots.

    ``rms`` [signal units] and ``psd`` [units^2/Hz] are the realised values (over a period);
    ``knots`` (N, 3) holds s, s', s'' of the unit-RMS signal (the acceleration's integrals for a
    motion, ``integrate``) at ``tau = j / rate``.
    """

    node: int
    dof: int
    rms: float
    psd: float
    lo: float
    hi: float
    seed: int
    t0: float
    period: float
    ramp: float
    lines: int
    rate: float
    knots: np.ndarray

    def block(self, ncol: int) -> np.ndarray:
        """This signal's rows in a law table of ``ncol`` columns (module docstring)."""
        n = self.knots.shape[0]
        out = np.zeros((n + 1, ncol))
        out[0, :3] = float(n), self.rate, 1.0 / self.rate
        out[1:, :3] = self.knots
        return out


def _band(what, spec, text, positive_low):
    lo_text, colon, hi_text = text.partition(":")
    if not colon:
        raise UsrfrcError(f"{what} {spec!r}: band={text!r}: expected LO:HI in Hz")
    lo = _number(what, spec, "band", lo_text)
    hi = _number(what, spec, "band", hi_text, positive=True)
    if lo < 0.0 or (positive_low and lo <= 0.0) or hi <= lo:
        need = "0 < LO < HI" if positive_low else "0 <= LO < HI"
        why = " (a base motion's displacement is the acceleration / w^2)" if positive_low else ""
        raise UsrfrcError(f"{what} {spec!r}: band={text!r}: expected {need} [Hz]{why}")
    return lo, hi


def _seed(what, spec, text):
    try:
        seed = int(text.strip())
    except ValueError:
        seed = -1
    if not 0 <= seed < 2 ** 53:
        raise UsrfrcError(f"{what} {spec!r}: seed={text!r}: expected an integer 0 .. 2^53 - 1")
    return seed


def parse_random(what: str, spec: str, body: str, node_ids: np.ndarray, *,
                 motion: bool = False) -> RandomLaw:
    """Parse the ``key=value`` part of a ``random:`` spec and synthesise its knots.

    ``motion=True`` reads a base motion (the level is the acceleration's; ``ramp`` allowed;
    LO > 0). Raises :class:`UsrfrcError` naming the spec and the bad key or value.
    """
    optional = _OPTIONAL + (("ramp",) if motion else ())
    pairs = _parse_pairs(what, spec, body, _REQUIRED, optional)
    node, dof = _node_dof(what, spec, pairs, node_ids)
    if ("rms" in pairs) == ("psd" in pairs):
        raise UsrfrcError(f"{what} {spec!r}: give exactly one of rms= (RMS over the band) or "
                          "psd= (one-sided PSD, units^2/Hz)")
    lo, hi = _band(what, spec, pairs["band"], motion)
    seed = _seed(what, spec, pairs["seed"])
    t0 = _number(what, spec, "t0", pairs["t0"]) if "t0" in pairs else 0.0
    period = (_number(what, spec, "period", pairs["period"], positive=True)
              if "period" in pairs else DEFAULT_PERIOD)
    ramp = _number(what, spec, "ramp", pairs["ramp"]) if "ramp" in pairs else 0.0
    if ramp < 0.0:
        raise UsrfrcError(f"{what} {spec!r}: ramp={pairs['ramp']!r}: expected a duration >= 0 [s]")
    # lines l / T in [LO, HI]; the relative slack keeps a band edge on the grid inside the band
    first = max(1, math.ceil(lo * period * (1.0 - 1e-12)))
    last = math.floor(hi * period * (1.0 + 1e-12))
    if last < first:
        raise UsrfrcError(f"{what} {spec!r}: no line of the grid 1/period = {1.0 / period:g} Hz "
                          f"falls in band {lo:g}:{hi:g} Hz; widen the band or give a longer "
                          "period=")
    n = math.ceil(OVERSAMPLE * hi * period)
    if n > MAX_KNOTS:
        raise UsrfrcError(f"{what} {spec!r}: period {period:g} s at {OVERSAMPLE} knots per period "
                          f"of {hi:g} Hz needs {n} knots (at most {MAX_KNOTS}); give a shorter "
                          "period=")
    lines = last - first + 1
    if "rms" in pairs:
        rms = _number(what, spec, "rms", pairs["rms"], positive=True)
        psd = rms * rms * period / lines
    else:
        psd = _number(what, spec, "psd", pairs["psd"], positive=True)
        rms = math.sqrt(psd * lines / period)
    knots = synthesize(first, last, period, n, seed, integrate=motion)
    return RandomLaw(node=node, dof=dof, rms=rms, psd=psd, lo=lo, hi=hi, seed=seed, t0=t0,
                     period=period, ramp=ramp, lines=lines, rate=n / period, knots=knots)


def synthesize(first: int, last: int, period: float, n: int, seed: int, *,
               integrate: bool = False) -> np.ndarray:
    """``(n, 3)`` knots s, s', s'' of the unit-RMS multisine with lines ``first .. last`` / period.

    ``integrate=True``: the multisine is the second derivative; the knots are then its double
    integral u (and u', u'' = the multisine), with no constant or linear term.
    """
    lines = last - first + 1
    phases = 2.0 * math.pi * np.random.default_rng(seed).random(lines)
    amp = math.sqrt(2.0 / lines)                       # unit RMS: L A^2 / 2 = 1
    omega = 2.0 * math.pi * np.arange(first, last + 1) / period
    # A sin(w t + phi) = Re[A e^{i(phi - pi/2)} e^{i w t}]; irfft divides by n, a line counts
    # twice (its negative frequency): X_l = n A / 2 e^{i(phi - pi/2)}
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    line = 0.5 * n * amp * np.exp(1j * (phases - 0.5 * math.pi))
    if integrate:
        line = -line / (omega * omega)
    knots = np.empty((n, 3))
    for k, factor in enumerate((1.0, 1j * omega, -omega * omega)):
        spectrum[first:last + 1] = line * factor
        knots[:, k] = np.fft.irfft(spectrum, n)
    return knots


def attach_blocks(rows: list[list[float]], laws: list[tuple[int, RandomLaw]], start_col: int,
                  marker: list[float]) -> np.ndarray:
    """The law table: ``rows``, then (when there are random laws) the ``marker`` row and every
    signal's block; each random row's ``start_col`` is set to its block's first row."""
    ncol = len(marker)
    if not laws:
        return np.array(rows, dtype=np.float64).reshape(len(rows), ncol)
    at = len(rows) + 1
    blocks = []
    for r, law in laws:
        rows[r][start_col] = float(at)
        blocks.append(law.block(ncol))
        at += blocks[-1].shape[0]
    return np.vstack([np.array(rows, dtype=np.float64), np.array([marker], dtype=np.float64),
                      *blocks])


# ---------------------------------------------------------------------------------------------
# Kernels
# ---------------------------------------------------------------------------------------------

@step_kernel
def _signal_state(tau, table, start):
    """``(s, s', s'')`` at ``tau`` >= 0 [s] of the signal whose block starts at row ``start``.

    ``x = tau rate`` wrapped into one period (exactly: ``x - N k`` with both terms within a
    factor 2 of each other, Sterbenz), between knots ``j = floor(x)`` and ``j + 1`` (modulo N),
    ``q = x - j``: the quintic Hermite polynomial p(q) = sum c_k q^k with p, p', p'' equal to
    the knots' s, h s', h^2 s'' (h = 1 / rate) at q = 0 and 1.
    """
    n = table[start, 0]
    rate = table[start, 1]
    h = table[start, 2]
    x = tau * rate
    if x >= n:
        x -= n * math.floor(x / n)
        if x < 0.0:
            x += n
    fj = math.floor(x)
    q = x - fj
    j0 = int(fj)
    if j0 >= int(n):
        j0 -= int(n)
    j1 = j0 + 1
    if j1 == int(n):
        j1 = 0
    r0 = start + 1 + j0
    r1 = start + 1 + j1
    u0 = table[r0, 0]
    u1 = table[r1, 0]
    v0 = h * table[r0, 1]
    v1 = h * table[r1, 1]
    a0 = h * h * table[r0, 2]
    a1 = h * h * table[r1, 2]
    d = u1 - u0
    c2 = 0.5 * a0
    c3 = 10.0 * d - 6.0 * v0 - 4.0 * v1 - 1.5 * a0 + 0.5 * a1
    c4 = -15.0 * d + 8.0 * v0 + 7.0 * v1 + 1.5 * a0 - a1
    c5 = 6.0 * d - 3.0 * (v0 + v1) - 0.5 * (a0 - a1)
    p = u0 + q * (v0 + q * (c2 + q * (c3 + q * (c4 + q * c5))))
    dp = v0 + q * (2.0 * c2 + q * (3.0 * c3 + q * (4.0 * c4 + q * 5.0 * c5)))
    ddp = 2.0 * c2 + q * (6.0 * c3 + q * (12.0 * c4 + q * 20.0 * c5))
    return p, dp * rate, ddp * rate * rate


@step_kernel
def _random_motion_state(tau, table, amp, start, ramp):
    """``(u, u', u'')`` of a random motion row ``tau`` after its start (see module doc).

    Before the start the DOF rests at ``amp s(0)`` (at 0 with a ``ramp`` > 0). A ramp multiplies
    u by h = (1 - cos(pi tau / TR)) / 2 for tau < TR, as for the sine (x3dpd.physics.motion).
    """
    if tau < 0.0:
        if ramp > 0.0:
            return 0.0, 0.0, 0.0
        return amp * _signal_state(0.0, table, start)[0], 0.0, 0.0
    s, c, a = _signal_state(tau, table, start)
    s *= amp
    c *= amp
    a *= amp
    if tau < ramp:
        k = math.pi / ramp
        h = 0.5 * (1.0 - math.cos(k * tau))
        h1 = 0.5 * k * math.sin(k * tau)
        h2 = 0.5 * k * k * math.cos(k * tau)
        return h * s, h1 * s + h * c, h2 * s + 2.0 * h1 * c + h * a
    return s, c, a
