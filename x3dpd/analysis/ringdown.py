"""Damping ratio versus amplitude from a free ring-down (report Sections 4.1 and 6.1, Figure 6).

The report's method, step by step:

1. the envelope A(t) of the ring-down is the modulus of the analytic signal (Hilbert transform,
   :func:`scipy.signal.hilbert`);
2. ln A(t) is fitted by a least-squares cubic spline over several pieces (knots every few cycles)
   whose neighbours share value *and slope* where they meet
   (:func:`scipy.interpolate.make_lsq_spline` -- a cubic spline is C2 at its knots, which is the
   report's "forced to have the same slope");
3. the local slope gives the local logarithmic decrement over one damped period T_d,

       delta(t) = -T_d d(ln A)/dt,        zeta = delta / sqrt(4 pi^2 + delta^2),

   which is exact for a linear oscillator
   (A = A0 exp(-zeta w_n t), T_d = 2 pi / (w_n sqrt(1-zeta^2)))
   and the equivalent viscous damping ratio at amplitude A for a nonlinear one;
4. the amplitude is expressed as an acceleration in dB re 1 g: a = w^2 A for a displacement
   envelope, 20 log10(a / g).

The unwrapped Hilbert phase, fitted by a spline the same way, gives the instantaneous frequency
w(t) used for T_d and for the displacement-to-acceleration factor. The first and last
``trim_cycles`` cycles are dropped: the Hilbert transform of a finite record rings at its ends.

**Each level's 95 % interval** (``zeta_ci``): the spline is a linear least-squares fit
y = B c of ln A, so its slope at t is a linear function d(t)^T c of the coefficients, whose
covariance is White's sandwich (B^T B)^-1 B^T diag(r_i^2) B (B^T B)^-1 n / (n - p) for
independent residuals r_i whose variance may change along the record (the noise of ln A grows
as A decays). The residuals of a dense record are correlated over about a cycle (the
particles' impacts, the envelope's ripple), so the covariance is scaled by 2 tau, tau the
residuals' integrated autocorrelation time (x3dpd.analysis.confidence.autocorrelation_time),
and the
half-width of zeta is t_{0.975, n/(2 tau) - p} sqrt(d^T Cov d) (2 pi / w) dzeta/ddelta, with
dzeta/ddelta = 4 pi^2 / (4 pi^2 + delta^2)^(3/2). A linear oscillator's exact decay has
residuals of round-off and an interval of nothing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from x3dpd.errors import InputError

#: Standard gravity in the report's units [in/s^2].
G_IN_S2 = 386.1


@dataclass(frozen=True)
class Ringdown:
    """Damping versus amplitude along a ring-down, one row per evaluation time.

    ``time`` [s]; ``amplitude`` the fitted envelope of the analysed signal (its units);
    ``frequency_hz`` the instantaneous frequency; ``amplitude_g`` the acceleration amplitude
    [g] (w^2 A / g for a displacement, A / g for an acceleration); ``amplitude_db`` = 20 log10 of
    it (dB re 1 g); ``zeta`` the damping ratio (fraction, not %) and ``zeta_ci`` its 95 %
    half-width (module docstring).
    """

    time: np.ndarray
    amplitude: np.ndarray
    frequency_hz: np.ndarray
    amplitude_g: np.ndarray
    amplitude_db: np.ndarray
    zeta: np.ndarray
    zeta_ci: np.ndarray | None = None

    def columns(self) -> dict[str, np.ndarray]:
        """The rows as named columns, in the order ``ringdown.csv`` writes them."""
        return {
            "time": self.time,
            "amplitude": self.amplitude,
            "frequency_hz": self.frequency_hz,
            "amplitude_g": self.amplitude_g,
            "amplitude_db": self.amplitude_db,
            "zeta": self.zeta,
            "zeta_percent": 100.0 * self.zeta,
            "zeta_ci_percent": 100.0 * self._ci(),
        }

    def _ci(self) -> np.ndarray:
        return self.zeta_ci if self.zeta_ci is not None else np.full_like(self.zeta, np.nan)


def hilbert_envelope(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Envelope |x + i H[x]| and unwrapped phase of a decaying zero-mean signal (Hilbert).

    The FFT-based transform is circular and a record's ends are abrupt, and any jump in the
    envelope or the slope leaks into the whole record. So the record (cut at upward zero
    crossings, :func:`zero_crossing_span`) is extended on both sides by signals whose
    envelope keeps decaying away from it, as a two-sided ring-down would: before the start,
    its point reflection through the zero crossing, -x(t0 - t) (value and slope continue;
    reflecting through the first sample instead would add a DC offset that leaks); after the end,
    its last cycle repeated, each copy scaled by the last two cycles' amplitude ratio. Both
    extensions fade to zero over their far half; they are cut off afterwards.
    """
    from scipy.signal import hilbert

    x = np.asarray(x, dtype=float)
    n = x.size
    before = -x[:0:-1] * _fade(n - 1)[::-1]
    after = _continued_decay(x, n) * _fade(n)
    analytic = hilbert(np.concatenate([before, x, after]))[n - 1 : 2 * n - 1]
    return np.abs(analytic), np.unwrap(np.angle(analytic))


def _fade(m: int) -> np.ndarray:
    """1 over the first half, a half cosine down to 0 over the second half (m samples)."""
    w = np.ones(m)
    half = m // 2
    w[half:] = 0.5 * (1.0 + np.cos(np.pi * np.arange(m - half) / max(m - half - 1, 1)))
    return w


def _continued_decay(x: np.ndarray, m: int) -> np.ndarray:
    """m samples continuing ``x`` past its end: its last cycle, decaying cycle by cycle."""
    up = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0)) + 1
    if up.size < 3:
        return np.zeros(m)
    last, prev = x[up[-2] : up[-1]], x[up[-3] : up[-2]]
    q = min(1.0, float(np.sqrt(np.mean(last**2) / np.mean(prev**2))))
    copies = int(np.ceil(m / last.size))
    return np.concatenate([last * q ** (j + 1) for j in range(copies)])[:m]


def zero_crossing_span(x: np.ndarray) -> slice:
    """From the first to the last upward zero crossing of ``x`` (the whole record if < 2)."""
    up = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0)) + 1
    if up.size < 2:
        return slice(0, x.size)
    return slice(int(up[0]), int(up[-1]) + 1)


def _lsq_spline(t: np.ndarray, y: np.ndarray, piece: float):
    """Least-squares cubic spline through (t, y) with interior knots every ``piece`` seconds."""
    from scipy.interpolate import make_lsq_spline

    k = 3
    n_pieces = max(1, int(round((t[-1] - t[0]) / piece)))
    interior = np.linspace(t[0], t[-1], n_pieces + 1)[1:-1]
    knots = np.r_[[t[0]] * (k + 1), interior, [t[-1]] * (k + 1)]
    return make_lsq_spline(t, y, knots, k=k)


def slope_half_width(spline, t: np.ndarray, y: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The 95 % half-width of a least-squares spline's slope at times ``at``, from the fit's
    residuals at (t, y) and their correlation (module docstring) [y's units per second]."""
    from scipy.interpolate import BSpline

    from x3dpd.analysis.confidence import autocorrelation_time, t_quantile

    knots, k = spline.t, spline.k
    p = knots.size - k - 1
    basis = BSpline.design_matrix(t, knots, k).toarray()
    residual = y - spline(t)
    n = t.size
    tau = autocorrelation_time(residual)
    dof = n / (2.0 * tau) - p
    if dof < 1.0:
        return np.full(at.shape, np.inf)
    # the sandwich (White's heteroscedasticity-consistent) covariance: the noise of ln A grows
    # as A decays, so one variance for the whole record overstates it early and understates
    # it late; scaled by 2 tau for the residuals' correlation and by n / (n - p)
    bread = np.linalg.pinv(basis.T @ basis)
    meat = (basis * (residual**2)[:, None]).T @ basis
    cov = bread @ meat @ bread * (2.0 * tau * n / (n - p))
    slopes = np.column_stack([BSpline(knots, np.eye(p)[j], k).derivative()(at) for j in range(p)])
    se = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", slopes, cov, slopes), 0.0))
    return t_quantile(dof) * se


#: cycles of a record's spline piece and of the trim at each end (damping_vs_amplitude)
PIECE_CYCLES = 4.0
TRIM_CYCLES = 3.0


def cycles_needed(piece_cycles: float = PIECE_CYCLES, trim_cycles: float = TRIM_CYCLES) -> float:
    """The fewest cycles a ring-down record must hold: a trim at each end, two spline pieces."""
    return 2.0 * trim_cycles + 2.0 * piece_cycles


# Over 80 lines: the report's ring-down method step by step on shared arrays.
def damping_vs_amplitude(
    time,
    signal,
    *,
    kind: str = "displacement",
    g: float = G_IN_S2,
    piece_cycles: float = PIECE_CYCLES,
    trim_cycles: float = TRIM_CYCLES,
    floor: float = 0.0,
    floor_fraction: float = 0.01,
    points_per_cycle: float = 1.0,
) -> Ringdown:
    """Ring-down -> damping ratio versus amplitude by the report's method (module docstring).

    Parameters
    ----------
    time : (T,) sample times [s], uniformly spaced.
    signal : (T,) the response about its equilibrium (zero mean when at rest).
    kind : ``"displacement"`` (amplitude converted with w^2) or ``"acceleration"``.
    g : the acceleration of gravity in the signal's units (386.1 in/s^2 for the report's decks).
    piece_cycles : length of one spline piece, in cycles of the mean frequency.
    trim_cycles : cycles dropped at each end of the record (Hilbert end effects).
    floor : envelope values at or below this are left out (noise floor, or the rest offset
        a Coulomb oscillator sticks at), in the signal's units.
    floor_fraction : envelope values below this fraction of the largest are left out too (a
        record's last 40 dB hold little but the transform's end effects and noise).
    points_per_cycle : evaluation points per cycle in the result.
    """
    t = np.asarray(time, dtype=float)
    x = np.asarray(signal, dtype=float)
    if t.ndim != 1 or t.shape != x.shape or t.size < 16:
        raise InputError("ring-down: time and signal must be 1-D arrays of the same length (>= 16)")
    if kind not in ("displacement", "acceleration"):
        raise InputError(f"ring-down: kind must be 'displacement' or 'acceleration', not {kind!r}")
    span = zero_crossing_span(x)
    t, x = t[span], x[span]
    env, phase = hilbert_envelope(x)
    duration = t[-1] - t[0]
    cycles = abs(phase[-1] - phase[0]) / (2.0 * np.pi)
    if cycles < (needed := cycles_needed(piece_cycles, trim_cycles)):
        raise InputError(
            f"ring-down: the record holds {cycles:.1f} cycles; at least {needed:.0f} are needed "
            f"({trim_cycles:g} trimmed at each end, two spline pieces)"
        )
    period = duration / cycles
    keep = (
        (t >= t[0] + trim_cycles * period)
        & (t <= t[-1] - trim_cycles * period)
        & (env > max(floor, floor_fraction * env.max()))
    )
    if np.count_nonzero(keep) < 16:
        raise InputError("ring-down: too few samples above the floor once the ends are trimmed")
    t_k = t[keep]
    # the kept samples must be one contiguous stretch: the envelope falls through the floor once
    last = np.flatnonzero(np.diff(np.flatnonzero(keep)) > 1)
    if last.size:
        t_k = t_k[: last[0] + 1]
    sel = (t >= t_k[0]) & (t <= t_k[-1])
    log_env = _lsq_spline(t[sel], np.log(env[sel]), piece_cycles * period)
    phase_fit = _lsq_spline(t[sel], phase[sel], piece_cycles * period)
    # a spline's slope is least certain in its end pieces: report from half a piece inside
    lo, hi = t_k[0] + 0.5 * piece_cycles * period, t_k[-1] - 0.5 * piece_cycles * period
    n_eval = max(2, int(points_per_cycle * (hi - lo) / period) + 1)
    te = np.linspace(lo, hi, n_eval)
    omega = np.abs(phase_fit.derivative()(te))
    amp = np.exp(log_env(te))
    delta = -log_env.derivative()(te) * 2.0 * np.pi / omega
    zeta = delta / np.sqrt(4.0 * np.pi**2 + delta**2)
    slope_hw = slope_half_width(log_env, t[sel], np.log(env[sel]), te)
    zeta_ci = slope_hw * 2.0 * np.pi / omega * 4.0 * np.pi**2 / (4.0 * np.pi**2 + delta**2) ** 1.5
    accel = amp * omega**2 if kind == "displacement" else amp
    amp_g = accel / g
    return Ringdown(
        time=te,
        amplitude=amp,
        frequency_hz=omega / (2.0 * np.pi),
        amplitude_g=amp_g,
        amplitude_db=20.0 * np.log10(amp_g),
        zeta=zeta,
        zeta_ci=zeta_ci,
    )


def rest_offset(signal: np.ndarray, cycles: int = 10) -> float:
    """Equilibrium estimate: the Hann-weighted mean of the record's last ``cycles`` cycles.

    The window keeps the decaying oscillation out of the mean (a plain mean over whole cycles of
    e^{-s t} sin(w t) is biased by ~ s / w of the amplitude); it matters, since an offset of 1 %
    of the final amplitude ripples the envelope by 1 %.
    """
    x = np.asarray(signal, dtype=float)
    tail = x[-max(2, x.size // 10) :]
    centre = float(np.median(tail))
    up = np.flatnonzero((x[:-1] < centre) & (x[1:] >= centre))
    if up.size < 2:
        return float(np.mean(tail))
    seg = x[up[max(0, up.size - 1 - cycles)] : up[-1]]
    w = np.hanning(seg.size + 2)[1:-1]
    return float(np.sum(w * seg) / np.sum(w))
