# Over 400 lines: the steady-state monitor's feed, criterion and answer share its per-cycle series.
"""Steady-state amplitude and phase of a sine-driven response, measured over whole drive cycles,
with their 95 % confidence intervals.

The criterion (docs/design-guide.md, "Steady state"):

* **Per cycle.** The response sampled at >= 200 points per drive period T = 2 pi / w is
  resampled (cubic spline) onto 256 points spanning exactly each whole drive cycle
  [t_k, t_k + T), and its Fourier coefficients give ``x = m + a cos(th) + b sin(th) + ...``
  with th = w (t - t0) the drive's phase (the drive is F sin(th)). The cycle's phasor is
  P_k = b + i a = X e^{i phi}: x = m + X sin(th + phi), X the fundamental amplitude and phi the
  phase of the response relative to the force (negative: a lag). Velocity is treated the same
  way, and the ledger's energies give each cycle's dissipation E_k. Harmonics drop out over a
  whole cycle; the sampling need not line up with the cycles (x3dpd.analysis.cycle_phasors).
* **A response with particles: stop when certain enough** (``x3dpd.analysis.confidence``).
  At the end of every window of W cycles the cycle phasors' start-up transient is cut off
  (MSER-5, doubled) and the mean phasor P of the cycles kept gets a 95 % interval from their
  variance and integrated autocorrelation time (Geyer's initial monotone sequence; a run of at
  least 50 autocorrelation times). The point has converged when the transient is out and the
  amplitude's half-width is within ``tol`` of |P|; it reports |P|, arg P, the kept cycles'
  mean dissipation per cycle, and the half-widths of all three. ``irregular`` says the cycles
  scatter by more than ``tol`` (chaotic impacts: a statistical answer); a periodic response
  has a zero half-width once its transient is out.
* **Extrapolation** (``extrapolate=True``, the default, tried first). A linear structure's free
  vibration e^{lambda t} seen once per drive cycle is a geometric sequence: the cycle phasors of
  a linear response obey P_k = P_inf + u r^k + v conj(r)^k with r = e^{lambda T}, and Prony's
  method fits a1, a2 of D_{k+2} = a1 D_{k+1} - a2 D_k over the last two windows to give r and
  the limit P_inf long before the transient has died (a lightly damped beam, zeta = 0.3 %,
  needs ~6.5 s to come within 1 % by itself). The point has converged by extrapolation when
  the limits from the last two pairs of windows agree within ``tol``, the recurrence fits
  (residual < 1 %) and both roots lie inside the unit circle; the reported amplitude and phase
  are then |P_inf| and arg P_inf, with the two limits' difference as their half-width, and
  the last window's measured numbers beside them. A response with impacting particles fails
  the fit and goes by the intervals above.
* **A response without particles** (``deterministic=True``) has no scatter to average: it is
  never irregular, and converges by extrapolation or, without it, when the window-to-window
  change D_w = P_w - P_{w-1} and its geometric tail |D_w| |r| / |1 - r| (r = D_w / D_{w-1})
  are both within ``tol`` of |P_w| and the run has settled over its last two thirds (three
  blocks of windows whose mean phasors agree within ``tol``, or approach a limit
  geometrically). Its half-widths are that remaining change.
* **Cap.** A point that has not converged after ``max_cycles`` stops there, flagged, with the
  intervals its cycles give (infinite when too few).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from x3dpd.analysis.confidence import Assessment, assess, mean_interval
from x3dpd.analysis.cycle_phasors import PRONY_RESIDUAL, ROUNDOFF, fit_cycle, prony_limit
from x3dpd.errors import InputError


@dataclass(frozen=True)
class SteadyState:
    """The measured steady state of one drive point.

    ``amplitude`` fundamental displacement amplitude X and ``amplitude_hw`` its 95 % half-width;
    ``phase_deg`` phi [deg] (x = m + X sin(th + phi)) and ``phase_hw_deg``; ``velocity``
    fundamental velocity amplitude; ``acceleration`` = w^2 X; ``peak`` half the peak-to-peak
    displacement (harmonics included); ``mean`` the mean position m; ``spread`` cycle-to-cycle
    scatter of the amplitude (std / mean); ``change`` |D_w| / |P_w| of the last two windows;
    ``tail`` the estimated remaining relative change; ``cycles`` drive cycles run, of which
    ``kept`` were averaged (the rest: the start-up transient); ``converged`` met the criterion
    before the cap; ``irregular`` its cycles scatter by more than the tolerance (a statistical
    answer); ``method`` how it converged ("interval", "extrapolated", "window", "replica": a
    replica long enough to pool, or "cap");
    ``tau`` the cycles' integrated autocorrelation time [cycles]; ``dissipated_per_cycle``
    ledger energy dissipated per cycle over the kept cycles (when fed) and ``cycle_energies``
    the same per kept cycle (for the interval of a sum of them, :meth:`energy_interval`).
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
    amplitude_hw: float = math.inf
    phase_hw_deg: float = math.inf
    kept: int = 0
    method: str = "cap"
    tau: float = math.nan
    cycle_energies: dict = field(default_factory=dict, repr=False)

    def energy_interval(self, names) -> tuple[float, float]:
        """(mean, 95 % half-width) of the energy per cycle summed over the ledger columns
        ``names`` (those fed; others count as 0): a statistical answer's interval from the kept
        cycles, a deterministic one's from its remaining relative change."""
        present = [self.cycle_energies[n] for n in names if n in self.cycle_energies]
        if not present:
            return math.nan, math.nan
        total = np.sum(present, axis=0)
        if self.method in ("interval", "replica", "cap"):
            iv = mean_interval(total)
            return iv.mean, iv.half_width
        value = float(np.mean(total))
        return value, abs(value) * max(self.change, self.tail, 0.0)


class SteadyStateMonitor:
    """Feeds on a response as it is computed; says when its steady state has been measured.

    Parameters
    ----------
    omega : drive circular frequency w [rad/s].
    t0 : drive time origin (the force is F sin(w (t - t0))) [s].
    t_start : start of the first cycle measured [s] (the point's start time).
    window : W, cycles per window.
    tol : relative tolerance of the criterion (module docstring).
    min_windows : windows run at least before a point may converge (>= 3).
    max_cycles : the cap.
    extrapolate : allow the Prony limit (module docstring).
    deterministic : a response without particles: no statistical answer (module docstring).
    replica_cycles : one replica of several (x3dpd.design.replicas): it may also stop once its
        transient is out and it kept this many cycles, its mean then pooled by the replicas'
        spread ("replica").
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
        deterministic: bool = False,
        replica_cycles: int | None = None,
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
        self.deterministic = bool(deterministic)
        self.replica_cycles = replica_cycles
        self.limit: complex | None = None
        #: the limits of the last two pairs of windows, when extrapolated
        self.limits: tuple[complex, complex] | None = None
        self.assessment: Assessment | None = None
        self.method = "cap"
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
            if self.extrapolate and self._extrapolated():
                self.done = self.converged = True
                self.method = "extrapolated"
            elif self.deterministic:
                change, tail, _, _ = self._change()
                if change <= self.tol and tail <= self.tol and self._settled():
                    self.done = self.converged = True
                    self.method = "window"
            else:
                # with particles, even a response that hardly scatters from cycle to cycle may
                # wander over many (a bed's slow rearrangements): only the interval decides
                self.assessment = assess(self.phasors)
                if self.assessment.within(self.tol):
                    self.done = self.converged = True
                    self.method = "interval"
                elif (
                    self.replica_cycles is not None
                    and self.assessment.settled
                    and n - self.assessment.truncation >= self.replica_cycles
                ):
                    self.done = self.converged = True
                    self.method = "replica"
        if len(self.phasors) >= self.max_cycles:
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
            self.limits = (now, before)
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
    def _tau(self, interval) -> float:
        """The integrated autocorrelation time of the cycles [cycles]: the interval's, or -- a
        capped point whose transient is out but whose run was too short for an interval --
        the assessment's estimate over its kept cycles (what an interval would need: 50 of
        them, x3dpd.analysis.confidence); NaN while the transient is in."""
        if interval is not None:
            return float(interval.tau)
        if self.assessment is not None and self.assessment.settled:
            return float(self.assessment.interval.tau)
        return math.nan

    def result(self) -> SteadyState:
        """The steady state: over the cycles kept after the transient for a statistical answer
        (and a capped point with particles), else over the last whole window (module
        docstring)."""
        n = len(self.phasors)
        if n == 0:
            raise ValueError("steady state: no whole drive cycle was computed")
        w = self._windows() - 1
        lo, hi = (w * self.window, (w + 1) * self.window) if w >= 0 else (0, n)
        change = tail = math.inf
        if w >= 2:
            change, tail, _, _ = self._change()
        statistical = not self.deterministic and self.method in ("interval", "replica", "cap")
        interval = None
        if statistical:
            if self.assessment is None or self.method == "cap":
                self.assessment = assess(self.phasors[:hi])
            kept = self.method in ("interval", "replica")
            lo = self.assessment.truncation if kept else lo
            interval = self.assessment.interval if kept else None
            if (
                self.method == "cap"
                and self.assessment.settled
                and self.assessment.interval.amplitude_hw < math.inf
            ):
                # capped, but long enough for an interval: the kept cycles' mean with it;
                # otherwise the last window, the least biased by a transient
                lo, interval = self.assessment.truncation, self.assessment.interval
        ph = np.asarray(self.phasors[lo:hi])
        measured = complex(np.mean(ph))
        p = self.limit if self.limit is not None else measured
        amp = abs(p)
        if interval is not None:
            amp_hw, phase_hw = interval.amplitude_hw, interval.phase_hw
        elif self.limits is not None:
            amp_hw = abs(self.limits[0] - self.limits[1])
            phase_hw = amp_hw / amp if amp > 0 else math.inf
        elif statistical:
            amp_hw = phase_hw = math.inf
        else:
            amp_hw = amp * max(change, tail)
            phase_hw = max(change, tail)
        amps = np.abs(ph)
        names = self._ledger_names
        energies = {
            name: np.array([self._ledger_hi[k][j] - self._ledger_lo[k][j] for k in range(lo, hi)])
            for j, name in enumerate(names)
        }
        return SteadyState(
            extrapolated=self.limit is not None,
            measured_amplitude=abs(measured),
            measured_phase_deg=math.degrees(math.atan2(measured.imag, measured.real)),
            amplitude=amp,
            phase_deg=math.degrees(math.atan2(p.imag, p.real)),
            velocity=abs(complex(np.mean(self.vphasors[lo:hi]))),
            acceleration=self.omega**2 * amp,
            peak=float(np.mean(self.peaks[lo:hi])),
            mean=float(np.mean(self.means[lo:hi])),
            spread=float(np.std(amps) / np.mean(amps)) if np.mean(amps) > 0 else 0.0,
            change=change,
            tail=tail,
            cycles=n,
            converged=self.converged,
            irregular=self.converged
            and self.method in ("interval", "replica")
            and float(np.std(amps) / np.mean(amps)) > self.tol,
            t_end=self.t_start + hi * self.period,
            dissipated_per_cycle={name: float(np.mean(e)) for name, e in energies.items()},
            amplitude_hw=amp_hw,
            phase_hw_deg=math.degrees(phase_hw),
            kept=hi - lo,
            method=self.method if self.converged else "cap",
            tau=self._tau(interval),
            cycle_energies=energies,
        )
