"""Steady-state amplitude and phase of a sine-driven response, measured over whole drive cycles.

The criterion (docs/design-guide.md, "Steady state"):

* **Per cycle.** The response sampled at >= 200 points per drive period T = 2 pi / w is
  resampled (cubic spline) onto 256 points spanning exactly each whole drive cycle
  [t_k, t_k + T), and its Fourier coefficients give ``x = m + a cos(th) + b sin(th) + ...``
  with th = w (t - t0) the drive's phase (the drive is F sin(th)). The cycle's phasor is
  P_k = b + i a = X e^{i phi}: x = m + X sin(th + phi), X the fundamental amplitude and phi the
  phase of the response relative to the force (negative: a lag). Velocity is treated the same
  way. Harmonics drop out over a whole cycle; the sampling need not line up with the cycles.
* **Windows.** Consecutive cycles are grouped in windows of W cycles; a window's phasor is the
  mean of its cycles' phasors, its spread the standard deviation of their amplitudes divided by
  their mean (cycle-to-cycle scatter: 0 for a periodic response, large for a chaotic one).
* **Convergence.** With D_w = P_w - P_{w-1} the change between consecutive windows and
  r = D_w / D_{w-1}, a transient that dies geometrically (a linear structure's free vibration
  seen once per window, any beating included since r is complex) still has
  ``tail = |D_w| |r| / |1 - r|`` to go. A regular response (spread <= ``tol``) has converged when
  both |D_w| and the tail are within ``tol`` of |P_w| (when |r| >= 1 the tail is taken as
  infinite). An irregular one (spread > ``tol``: chaotic impacts, several coexisting motions)
  has converged, and is flagged irregular, when |D_w| and |D_{w-1}| are both within the
  statistical scatter of two window means, 2 sqrt(2) s / sqrt(W) with s the cycle-to-cycle
  standard deviation. Every window
  before ``min_windows`` counts as transient and is discarded.
* **Settled over the run** (both kinds, besides the window test). Neighbouring windows alone
  accept a state still drifting toward its attractor: an impact damper's transient is neither
  geometric nor quiet (a single sphere on the report's beam chatters for ~300 cycles before it
  locks onto its periodic motion, and a few quiet windows in that chatter passed the test 11 %
  from the periodic amplitude). So the run's last 3k whole windows (k = windows // 3) form three
  blocks with mean phasors B1, B2, B3; with the allowance a = max(tol, 2 sqrt(2) s / sqrt(k W))
  (s the last block's cycle-to-cycle scatter) the point has settled when |B3 - B2| <= a |B3|
  and either |B2 - B1| <= a |B3| or the drift dies geometrically, rho = (B3 - B2) / (B2 - B1),
  with the last block's remaining distance to the limit |B3 - B2| |rho| / |1 - rho| <= a |B3|.
  A state must thus have held over the last two thirds of the run, whatever the start.
* **Extrapolation** (``extrapolate=True``, the default). A linear structure's free vibration
  e^{lambda t} seen once per drive cycle is a geometric sequence: the cycle phasors of a linear
  response obey P_k = P_inf + u r^k + v conj(r)^k with r = e^{lambda T}, so their differences
  satisfy D_{k+2} = a1 D_{k+1} - a2 D_k with real a1, a2 (Prony's method). Fitting a1, a2 by
  least squares over the last two windows gives r and the limit P_inf long before the transient
  has died (a lightly damped beam, zeta = 0.3 %, needs ~6.5 s to come within 1 % by itself). The
  point has converged by extrapolation when the limits from the last two pairs of windows agree
  within ``tol``, the recurrence fits (residual < 1 %) and both roots lie inside the unit circle;
  the reported amplitude and phase are then |P_inf| and arg P_inf (``extrapolated`` is set, and
  the last window's measured numbers are kept beside them). A response that is not linear enough
  for the recurrence (particles that impact) fails the fit and falls back to the measured
  criterion above, where the particles' own damping shortens the transient.
* **Cap.** A point that has not converged after ``max_cycles`` stops there, flagged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from x3dpd.errors import InputError


#: Relative changes below this are the cycle fits' floating-point noise: no change at all.
ROUNDOFF = 1e-9


@dataclass(frozen=True)
class SteadyState:
    """The measured steady state of one drive point (the last window's numbers).

    ``amplitude`` fundamental displacement amplitude X; ``phase_deg`` phi [deg] (x = m + X sin(th +
    phi)); ``velocity`` fundamental velocity amplitude; ``acceleration`` = w^2 X; ``peak`` half the
    peak-to-peak displacement (harmonics included); ``mean`` the mean position m; ``spread``
    cycle-to-cycle scatter of the amplitude (std / mean); ``change`` |D_w| / |P_w|; ``tail`` the
    estimated remaining relative change; ``cycles`` drive cycles run; ``converged`` met the
    criterion before the cap; ``irregular`` converged only in the statistical sense;
    ``dissipated_per_cycle`` ledger energy dissipated per cycle over the last window (when fed).
    """

    amplitude: float
    phase_deg: float
    velocity: float
    acceleration: float
    peak: float
    mean: float
    spread: float
    change: float
    tail: float
    cycles: int
    converged: bool
    irregular: bool
    t_end: float
    dissipated_per_cycle: dict = field(default_factory=dict)
    extrapolated: bool = False
    measured_amplitude: float = math.nan
    measured_phase_deg: float = math.nan


#: Largest relative residual of the Prony recurrence for a response to count as linear.
PRONY_RESIDUAL = 0.01


def prony_limit(phasors) -> tuple[complex, float, float]:
    """Limit of P_k = P_inf + u r^k + v conj(r)^k from its last terms (module docstring).

    Returns (P_inf, relative residual of the recurrence fit, largest |root|); a sequence whose
    differences are round-off returns its last term.
    """
    p = np.asarray(phasors, dtype=complex)
    d = np.diff(p)
    scale = abs(p[-1]) or 1.0
    if np.max(np.abs(d)) < ROUNDOFF * scale:
        return complex(p[-1]), 0.0, 0.0
    a = np.column_stack([d[1:-1], -d[:-2]])
    b = d[2:]
    a_real = np.concatenate([a.real, a.imag])
    b_real = np.concatenate([b.real, b.imag])
    (a1, a2), *_ = np.linalg.lstsq(a_real, b_real, rcond=None)
    residual = float(np.linalg.norm(a_real @ [a1, a2] - b_real) / (np.linalg.norm(b_real) or 1.0))
    r1, r2 = np.roots([1.0, -a1, a2]).astype(complex)
    rmax = float(max(abs(r1), abs(r2)))
    if rmax >= 1.0 or abs(r1 - r2) < 1e-9:
        return complex(p[-1]), residual, max(rmax, 1.0)
    # D_a = u + v, D_b = u r1 + v r2 for the last two differences; the rest sums geometrically
    d_a, d_b = d[-2], d[-1]
    v = (d_b - r1 * d_a) / (r2 - r1)
    u = d_a - v
    rest = u * r1**2 / (1 - r1) + v * r2**2 / (1 - r2)
    return complex(p[-1] + rest), residual, rmax


#: Points per cycle of the uniform resampling the phasor is computed on.
CYCLE_POINTS = 256


def fit_cycle(
    t: np.ndarray, x: np.ndarray, omega: float, t0: float, lo: float
) -> tuple[complex, float]:
    """Fundamental of ``x`` over the drive cycle [lo, lo + T): returns (b + i a, m).

    ``x = m + a cos(w (t - t0)) + b sin(w (t - t0)) + harmonics``. The samples (which need not
    fall on the cycle's ends, and must reach a little past both) are interpolated by a cubic
    spline onto CYCLE_POINTS points spaced uniformly over exactly one period, and a, b, m are
    their discrete Fourier coefficients. Every cycle is thus measured by the same operator --
    which keeps a linear transient's cycle phasors exactly geometric (the extrapolation relies
    on it) -- with an interpolation error of O((w h)^4) for a sample spacing h.
    """
    from scipy.interpolate import CubicSpline

    period = 2.0 * math.pi / omega
    tj = lo + period * np.arange(CYCLE_POINTS) / CYCLE_POINTS
    xj = CubicSpline(t, x)(tj)
    th = omega * (tj - t0)
    a = 2.0 * float(np.mean(xj * np.cos(th)))
    b = 2.0 * float(np.mean(xj * np.sin(th)))
    return complex(b, a), float(np.mean(xj))


class SteadyStateMonitor:
    """Feeds on a response as it is computed; says when its steady state has been measured.

    Parameters
    ----------
    omega : drive circular frequency w [rad/s].
    t0 : drive time origin (the force is F sin(w (t - t0))) [s].
    t_start : start of the first cycle measured [s] (the point's start time).
    window : W, cycles per window.
    tol : relative tolerance of the criterion (module docstring).
    min_windows : windows discarded as transient at least (>= 3: two changes are compared).
    max_cycles : the cap.
    """

    def __init__(
        self,
        omega: float,
        t0: float,
        t_start: float,
        *,
        window: int = 5,
        tol: float = 0.01,
        min_windows: int = 3,
        max_cycles: int = 600,
        extrapolate: bool = True,
    ):
        self.omega = float(omega)
        self.t0 = float(t0)
        self.period = 2.0 * math.pi / self.omega
        self.t_start = float(t_start)
        self.window = int(window)
        self.tol = float(tol)
        self.min_windows = max(3, int(min_windows))
        self.max_cycles = int(max_cycles)
        self.extrapolate = bool(extrapolate)
        self.limit: complex | None = None
        self._t: list[np.ndarray] = []
        self._x: list[np.ndarray] = []
        self._v: list[np.ndarray] = []
        self._e: list[np.ndarray] = []
        self._ledger_names: tuple[str, ...] = ()
        self._ledger_lo: list[np.ndarray] = []
        self._ledger_hi: list[np.ndarray] = []
        self.phasors: list[complex] = []
        self.vphasors: list[complex] = []
        self.means: list[float] = []
        self.peaks: list[float] = []
        self.done = False
        self.converged = False
        self.irregular = False

    # -- feeding ----------------------------------------------------------------------------
    def feed(self, time, x, v=None, ledger: dict | None = None) -> bool:
        """Add samples (times [s], displacement, velocity) and cumulative ledger columns.

        ``ledger`` maps names to cumulative energies sampled at the same times (e.g. the energy
        dissipated so far). Returns True once the point is finished (converged, or capped).
        """
        self._t.append(np.asarray(time, dtype=float))
        self._x.append(np.asarray(x, dtype=float))
        self._v.append(np.asarray(v if v is not None else np.zeros_like(x), dtype=float))
        ledger = ledger or {}
        self._ledger_names = tuple(ledger)
        self._e.append(
            np.column_stack([np.asarray(ledger[k], float) for k in ledger])
            if ledger
            else np.zeros((len(self._t[-1]), 0))
        )
        t = np.concatenate(self._t)
        x = np.concatenate(self._x)
        v = np.concatenate(self._v)
        e = np.concatenate(self._e)
        while not self.done:
            k = len(self.phasors)
            lo = self.t_start + k * self.period
            hi = lo + self.period
            if t.size < 3 or t[-3] < hi:
                break
            i_lo = max(0, int(np.searchsorted(t, lo, side="right")) - 3)
            i_hi = int(np.searchsorted(t, hi)) + 3
            ts, xs, vs = t[i_lo:i_hi], x[i_lo:i_hi], v[i_lo:i_hi]
            if ts[0] > lo + 0.05 * self.period:  # a run's first sample is one interval in
                raise InputError("steady state: samples are missing at the start of a drive cycle")
            inside = (ts >= lo) & (ts < hi)
            if np.count_nonzero(inside) < 20:
                raise InputError(
                    f"steady state: {np.count_nonzero(inside)} samples in a drive "
                    "cycle; record more often (>= 200 per cycle)"
                )
            p, m = fit_cycle(ts, xs, self.omega, self.t0, lo)
            pv, _ = fit_cycle(ts, vs, self.omega, self.t0, lo)
            self.phasors.append(p)
            self.vphasors.append(pv)
            self.means.append(m)
            self.peaks.append(0.5 * float(xs[inside].max() - xs[inside].min()))
            self._ledger_lo.append(np.array([np.interp(lo, t, c) for c in e.T]))
            self._ledger_hi.append(np.array([np.interp(hi, t, c) for c in e.T]))
            self._judge()
            # keep a few samples before the next cycle for its interpolation
            keep = max(0, int(np.searchsorted(t, hi, side="right")) - 3)
            t, x, v, e = t[keep:], x[keep:], v[keep:], e[keep:]
        self._t, self._x, self._v, self._e = [t], [x], [v], [e]
        return self.done

    # -- the criterion ------------------------------------------------------------------------
    def _windows(self) -> int:
        return len(self.phasors) // self.window

    def _window(self, w: int, seq) -> np.ndarray:
        return np.asarray(seq[w * self.window : (w + 1) * self.window])

    def _judge(self) -> None:
        n = len(self.phasors)
        if n % self.window == 0 and self._windows() >= self.min_windows:
            change, tail, noise, spread = self._change()
            if self.extrapolate and self._extrapolated():
                self.done = self.converged = True
            elif spread > self.tol:
                if change <= noise and self._previous_change() <= noise and self._settled():
                    self.done = self.converged = self.irregular = True
            elif change <= self.tol and tail <= self.tol and self._settled():
                self.done = self.converged = True
        if n >= self.max_cycles:
            self.done = True

    def _extrapolated(self) -> bool:
        """Limits from the last two pairs of windows agree, and the recurrence fits."""
        n, w = len(self.phasors), self.window
        now, res_now, r_now = prony_limit(self.phasors[n - 2 * w :])
        before, res_before, r_before = prony_limit(self.phasors[n - 3 * w : n - w])
        ok = (
            max(res_now, res_before) < PRONY_RESIDUAL
            and max(r_now, r_before) < 1.0
            and abs(now - before) <= self.tol * abs(now)
        )
        if ok:
            self.limit = now
        return ok

    def _blocks(self, count: int) -> list[np.ndarray]:
        """The last ``count`` x k whole windows' cycle phasors in ``count`` blocks of k =
        windows // count windows each (empty when there are fewer windows than blocks)."""
        k, w = self._windows() // count, self.window
        if k < 1:
            return []
        first = self._windows() - count * k
        return [
            np.asarray(self.phasors[(first + j * k) * w : (first + (j + 1) * k) * w])
            for j in range(count)
        ]

    def _settled(self) -> bool:
        """No drift left beyond tol over the run's last two thirds (module docstring).

        Three blocks of k = windows // 3 whole windows end the run; with B_j their mean phasors,
        D1 = B2 - B1, D2 = B3 - B2 and the allowance a = max(tol, 2 sqrt(2) s / sqrt(k W))
        (s: the last block's cycle-to-cycle scatter, relative to |B3|), the run has settled
        when |D2| <= a |B3| and either |D1| <= a |B3| or the drift dies geometrically from
        block to block, rho = D2 / D1, with the last block's remaining distance to the limit
        |D2| |rho| / |1 - rho| <= a |B3|.
        """
        blocks = self._blocks(3)
        if not blocks:
            return False
        b1, b2, b3 = (complex(np.mean(b)) for b in blocks)
        scale = abs(b3) or 1.0
        d1, d2 = abs(b2 - b1) / scale, abs(b3 - b2) / scale
        if d2 < ROUNDOFF:
            return True
        k = len(blocks[0]) // self.window
        scatter = float(np.std(np.abs(blocks[2]))) / scale
        allowance = max(self.tol, 2.0 * math.sqrt(2.0) * scatter / math.sqrt(k * self.window))
        if d2 > allowance:
            return False
        if d1 <= allowance:
            return True
        rho = (b3 - b2) / (b2 - b1)
        return d2 * abs(rho) / abs(1.0 - rho) <= allowance

    def _previous_change(self) -> float:
        w = self._windows() - 2
        p = [complex(np.mean(self._window(i, self.phasors))) for i in (w - 1, w)]
        return abs(p[1] - p[0]) / (abs(p[1]) or 1.0)

    def _change(self) -> tuple[float, float, float]:
        w = self._windows() - 1
        p = [complex(np.mean(self._window(i, self.phasors))) for i in (w - 2, w - 1, w)]
        scale = abs(p[2]) or 1.0
        d1, d2 = p[1] - p[0], p[2] - p[1]
        change = abs(d2) / scale
        if change < ROUNDOFF:
            return 0.0, 0.0, 0.0, 0.0
        r = d2 / d1 if d1 != 0 else math.inf
        tail = (abs(d2) * abs(r) / abs(1 - r) / scale) if abs(r) < 1 else math.inf
        amps = np.abs(self._window(w, self.phasors))
        spread = float(np.std(amps)) / scale
        noise = 2.0 * math.sqrt(2.0) * spread / math.sqrt(self.window)
        return change, tail, noise, spread

    # -- the answer ---------------------------------------------------------------------------
    def result(self) -> SteadyState:
        """The last whole window's steady state (or the cycles so far, if fewer)."""
        n = len(self.phasors)
        if n == 0:
            raise ValueError("steady state: no whole drive cycle was computed")
        w = self._windows() - 1
        lo, hi = (w * self.window, (w + 1) * self.window) if w >= 0 else (0, n)
        ph = np.asarray(self.phasors[lo:hi])
        p = complex(np.mean(ph))
        amps = np.abs(ph)
        if w >= 2:
            change, tail, _, _ = self._change()
        else:
            change = tail = math.inf
        t_hi = self.t_start + hi * self.period
        measured = p
        if self.limit is not None:
            p = self.limit
        return SteadyState(
            extrapolated=self.limit is not None,
            measured_amplitude=abs(measured),
            measured_phase_deg=math.degrees(math.atan2(measured.imag, measured.real)),
            amplitude=abs(p),
            phase_deg=math.degrees(math.atan2(p.imag, p.real)),
            velocity=abs(complex(np.mean(self.vphasors[lo:hi]))),
            acceleration=self.omega**2 * abs(p),
            peak=float(np.mean(self.peaks[lo:hi])),
            mean=float(np.mean(self.means[lo:hi])),
            spread=float(np.std(amps) / np.mean(amps)) if np.mean(amps) > 0 else 0.0,
            change=change,
            tail=tail,
            cycles=n,
            converged=self.converged,
            irregular=self.irregular,
            t_end=t_hi,
            dissipated_per_cycle={
                name: float(self._ledger_hi[hi - 1][j] - self._ledger_lo[lo][j]) / (hi - lo)
                for j, name in enumerate(self._ledger_names)
            },
        )
