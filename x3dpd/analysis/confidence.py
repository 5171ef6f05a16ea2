"""95 % confidence intervals of a steady state's mean from a correlated per-cycle series.

A sweep point measures one number per drive cycle -- the response's fundamental phasor P_k,
the energy dissipated over the cycle E_k -- and reports their mean over the cycles it keeps. A
damper with impacting particles scatters from cycle to cycle, and the cycles are correlated (a
bed remembers its arrangement for several cycles), so the mean's uncertainty is not s/sqrt(n).
The estimator (docs/design-guide.md, "Steady state"):

1. **Start-up transient out: MSER-5, doubled** (White, "An effective truncation heuristic for
   bias reduction in simulation output", Simulation 69 (1997) 323-334). The series is grouped
   in groups of ``MSER_GROUP`` (5) cycles, counted from its end, with means Z_0 .. Z_{J-1}; for
   each truncation d = 0 .. J // 2

   .. math::  \\mathrm{MSER}(d) = \\frac{1}{(J - d)^2} \\sum_{j=d}^{J-1} |Z_j - \\bar Z_d|^2

   (complex: the phasor's scatter in the plane, amplitude and phase at once) trades the bias of
   keeping early groups against the noise of dropping them; d* is its first minimum. The
   transient is out when d* < J // 2 (a minimum on the boundary: still drifting). Scatter
   below ``QUIET`` (1e-6) of the mean counts as none, so a response that locks onto a
   periodic motion has MSER 0 from the lock on and is cut exactly there. Otherwise MSER stops
   where the transient is as small as one group's noise -- fine for a mean's error, too much
   for its interval, which a long run makes much narrower than one group's noise -- so twice
   d* groups are dropped: an exponentially decaying transient is then smaller again by the
   factor it decayed over the first d* (measured on synthetic series: coverage 0.73 -> 0.95
   with a transient of 10 noise levels, ``tests/analysis/test_confidence.py``).
2. **The variance of the mean: Geyer's initial monotone sequence** (Geyer, "Practical Markov
   chain Monte Carlo", Statistical Science 7 (1992) 473-483). Over the n cycles kept, with
   autocovariances c_k of a real series y, Gamma_m = c_{2m} + c_{2m+1} summed while positive
   and made non-increasing, sigma^2 = -c_0 + 2 sum Gamma_m, and the integrated autocorrelation
   time tau = sigma^2 / (2 c_0) (at least 1/2, independent cycles). The interval needs a run
   of at least ``RUN_LENGTH`` (50) tau cycles: shorter, tau itself is not known well enough.
3. **The interval.** With n_eff = n / (2 tau) the mean's standard error is sqrt(c_0 / n_eff)
   and the 95 % half-width t_{0.975, n_eff - 1} times that (Student's t). For the phasor, the
   cycles are projected onto the mean P's direction (amplitude, u_k = Re(P_k conj P)/|P|) and
   across it (phase, v_k = Im(P_k conj P)/|P|, its half-width / |P| in radians), each with its
   own tau, the run length taken from the larger: the delta method for |P| and arg P, exact to
   first order in the scatter.

A sequential stop (a point ends once the half-width is within tolerance) makes the interval a
little narrower than its level on average; on synthetic AR(1) series of cycle-to-cycle
correlation 0 .. 0.95, with and without a start-up transient, the intervals covered the true
mean in 92-95 % of 300 runs each (tests/analysis/test_confidence.py checks 0.9 and above).
Where the cycles' correlation oscillates -- a bed whose structure beats with the drive, high
cycles followed by low ones -- the initial sequence stops at the first negative lobe and the
interval is conservative: on 8 spheres in the beam cavity at 36 Hz the mean half-width was 3x
what 20 seeds' spread gives (every seed's interval held the others' mean;
tests/design/test_interval_coverage.py, ``-m validate``). Overlapping batch means, which do see
the negative lobes (1.7x there), covered only 0.89 of strongly correlated AR(1) series when a
point stops as soon as it is within tolerance: a wide interval is the safer error. A series
that does not scatter (a periodic response) has a zero half-width once its transient is out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Cycles per MSER group (MSER-5).
MSER_GROUP = 5
#: An interval needs at least this many integrated autocorrelation times of kept cycles ...
RUN_LENGTH = 50
#: ... and at least this many kept cycles.
MIN_KEPT = 20
#: Two-sided 95 %.
LEVEL = 0.95
#: Scatter below this (relative to the mean) is the cycle fits' interpolation error (~1e-8,
#: x3dpd.analysis.cycle_phasors.fit_cycle): none at all.
QUIET = 1e-6


def mser_truncation(series, group: int = MSER_GROUP) -> tuple[int, bool]:
    """(cycles to drop, transient out) of a per-cycle series (complex or real): twice MSER's
    truncation (module docstring, step 1), or once when the groups it keeps do not scatter
    (a response that locked onto a periodic motion: nothing is left to decay). The groups are
    counted from the series' end; a partial group at its start is dropped with the truncation.
    Scatter below QUIET of the mean counts as none (the cycle fits' interpolation error is
    ~1e-8 of the amplitude), so a quiet tail has MSER 0 from its first group on."""
    z = np.asarray(series)
    groups = z.shape[0] // group
    if groups < 2:
        return z.shape[0], False
    first = z.shape[0] - groups * group
    means = z[first:].reshape(groups, group).mean(axis=1)
    best, best_d = math.inf, 0
    for d in range(groups // 2 + 1):
        kept = means[d:]
        centre = kept.mean()
        excess = np.abs(kept - centre) ** 2 - (QUIET * abs(centre)) ** 2
        stat = float(np.sum(np.maximum(excess, 0.0))) / (groups - d) ** 2
        if stat < best:
            best, best_d = stat, d
    cut = best_d * (1 if best == 0.0 else 2)
    return min(z.shape[0], first + cut * group), best_d < groups // 2


def autocorrelation_time(series) -> float:
    """The integrated autocorrelation time tau of a real series by Geyer's initial monotone
    sequence (module docstring, step 2): the variance of its mean is 2 tau c_0 / n. 1/2 for
    independent values, and for a series that does not vary."""
    y = np.asarray(series, dtype=float)
    n = y.shape[0]
    d = y - y.mean()
    spectrum = np.fft.rfft(d, 2 * n)
    acov = np.fft.irfft(spectrum * np.conj(spectrum))[:n] / n
    if acov[0] <= 0.0:
        return 0.5
    total, previous = 0.0, math.inf
    for m in range(n // 2):
        gamma = acov[2 * m] + acov[2 * m + 1]
        if gamma <= 0.0:
            break
        previous = min(previous, gamma)
        total += previous
    return max(0.5, (2.0 * total - acov[0]) / (2.0 * acov[0]))


def cycles_for_interval(tau: float) -> float:
    """Kept cycles an interval of a series of integrated autocorrelation time ``tau`` [cycles]
    needs (module docstring, step 2): RUN_LENGTH tau, and at least MIN_KEPT; NaN for NaN."""
    return max(RUN_LENGTH * tau, MIN_KEPT) if tau == tau else math.nan


def t_quantile(dof: float) -> float:
    """Student's t at (1 + LEVEL) / 2 with ``dof`` degrees of freedom (at least 1)."""
    from scipy.stats import t

    return float(t.ppf(0.5 + 0.5 * LEVEL, max(dof, 1.0)))


@dataclass(frozen=True)
class MeanInterval:
    """The mean of a per-cycle series over the cycles kept and its 95 % half-width
    (``math.inf``: too short a run for an interval); ``tau`` its integrated autocorrelation
    time [cycles]."""

    mean: float
    half_width: float
    tau: float


def mean_interval(series) -> MeanInterval:
    """The mean of a real series and its 95 % half-width (module docstring, steps 2 and 3)."""
    y = np.asarray(series, dtype=float)
    n = y.shape[0]
    mean = float(np.mean(y)) if n else math.nan
    if n < MIN_KEPT:
        return MeanInterval(mean, math.inf, math.nan)
    spread = float(np.std(y, ddof=1))
    if spread <= QUIET * (abs(mean) or 1.0):
        return MeanInterval(mean, 0.0, 0.5)
    tau = autocorrelation_time(y)
    if n < RUN_LENGTH * tau:
        return MeanInterval(mean, math.inf, tau)
    n_eff = n / (2.0 * tau)
    return MeanInterval(mean, t_quantile(n_eff - 1.0) * spread / math.sqrt(n_eff), tau)


@dataclass(frozen=True)
class PhasorInterval:
    """The mean phasor P of the kept cycles: ``amplitude`` |P| and its 95 % half-width,
    ``phase`` arg P [rad] and its half-width [rad]; ``tau`` the larger of the two series'
    integrated autocorrelation times [cycles]."""

    mean: complex
    amplitude_hw: float
    phase_hw: float
    tau: float

    @property
    def amplitude(self) -> float:
        return abs(self.mean)

    @property
    def phase(self) -> float:
        return math.atan2(self.mean.imag, self.mean.real)


def phasor_interval(phasors) -> PhasorInterval:
    """The mean phasor of a series of cycle phasors and its amplitude and phase half-widths
    (module docstring, step 3)."""
    z = np.asarray(phasors, dtype=complex)
    mean = complex(np.mean(z)) if z.size else complex(math.nan)
    if not abs(mean) > 0.0:
        return PhasorInterval(mean, math.inf, math.inf, math.nan)
    unit = np.conj(mean) / abs(mean)
    along = mean_interval((z * unit).real)
    across = mean_interval((z * unit).imag)
    tau = max(along.tau, across.tau)
    if not (along.half_width < math.inf and across.half_width < math.inf):
        return PhasorInterval(mean, math.inf, math.inf, tau)
    return PhasorInterval(mean, along.half_width, across.half_width / abs(mean), tau)


@dataclass(frozen=True)
class Assessment:
    """Where a per-cycle phasor series stands: ``settled`` (its transient out), the
    ``interval`` of its mean over the cycles kept, and ``truncation`` (cycles dropped as
    transient)."""

    settled: bool
    interval: PhasorInterval
    truncation: int

    def within(self, tol: float) -> bool:
        """Settled, with the amplitude's half-width within ``tol`` of the amplitude."""
        iv = self.interval
        return self.settled and iv.amplitude_hw <= tol * iv.amplitude


def assess(phasors) -> Assessment:
    """The transient's truncation, then the interval of the rest (module docstring)."""
    z = np.asarray(phasors, dtype=complex)
    cut, out = mser_truncation(z)
    return Assessment(out, phasor_interval(z[cut:]), cut)
