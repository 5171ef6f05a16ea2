"""Where a frequency response peaks, from as few points as possible (``--freq auto:LO:HI``).

A designer reads the peak amplitude, its frequency and the half-power band, not a grid. The
search (docs/design-guide.md, "The peak, not a grid"):

1. **Coarse pass.** ``COARSE`` (4) frequencies spread evenly over [LO, HI], ends included.
2. **A fitted resonance curve.** Near a resonance a single mode dominates, and a single mode's
   amplitude is exactly

   .. math::  \\frac{1}{X^2} = \\frac{(k - m\\omega^2)^2 + (c\\omega)^2}{F^2}
              = c_0 + c_1 u + c_2 u^2, \\qquad u = f^2,

   a quadratic in u: three points determine it, with no iteration and whatever the damping.
   It is fitted by weighted least squares to the (up to) ``FIT_POINTS`` (4) measured points
   nearest the current estimate of the peak (the highest point at first), each weighted by its
   interval (the delta method: sigma(1/X^2) = 2 sigma_X / X^3, sigma_X = amplitude_ci / 1.96,
   at least the tolerance's share of X). Its minimum u* = -c_1 / (2 c_2) is the peak, X* =
   (c_0 - c_1^2 / (4 c_2))^(-1/2) its amplitude, and 1/X^2 = 2/X*^2 at u* +/- sqrt(1/(X*^2 c_2))
   the half-power band.
3. **Refinement.** The next point is the fitted peak f* = sqrt(u*). The search has converged
   when a refit moves f* by at most ``resolution`` and a measured point lies within
   ``resolution`` of it: then the fitted curve and the points agree where it matters. A linear
   SDOF converges after one refinement point (the fit is exact); a damper's broad, slightly
   skewed peak in two or three.
4. **The edges.** A peak whose fit lies outside [LO, HI] (the response still rising at an
   edge) is reported at that edge and flagged: widen the band.

The peak's frequency half-width comes from the fit's covariance by the delta method
(sigma_u*^2 = g^T C g, g = d u*/d(c_0, c_1, c_2)); with exactly three points it has no
residual to tell the fit's error, and the points' own intervals carry it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Points of the coarse pass, ends included.
COARSE = 4
#: Measured points the resonance curve is fitted to (the nearest to the peak).
FIT_POINTS = 3


@dataclass(frozen=True)
class Peak:
    """A found peak: ``frequency_hz`` and its 95 % half-width ``frequency_ci``, ``amplitude``
    X* of the fitted curve and ``amplitude_ci``, the half-power band ``band_lo_hz`` ..
    ``band_hi_hz`` (NaN where the fitted curve does not come down to X*/sqrt 2 within reach),
    ``converged`` (the refinement settled, inside the band), ``at_edge`` (the response still
    rises at LO or HI) and the ``points`` it used."""

    frequency_hz: float
    frequency_ci: float
    amplitude: float
    amplitude_ci: float
    band_lo_hz: float
    band_hi_hz: float
    converged: bool
    at_edge: bool
    points: int


def coarse_frequencies(lo: float, hi: float, count: int = COARSE) -> list[float]:
    """The coarse pass: ``count`` frequencies evenly over [lo, hi], ends included [Hz]."""
    return [float(f) for f in np.linspace(lo, hi, count)]


@dataclass(frozen=True)
class _Fit:
    coef: np.ndarray  # c0, c1, c2 of 1/X^2 = c0 + c1 u + c2 u^2 (u = (f / f_ref)^2)
    cov: np.ndarray
    f_ref: float

    def peak_u(self) -> float:
        c0, c1, c2 = self.coef
        return -c1 / (2.0 * c2) if c2 > 0.0 else math.nan

    def value(self, u: float) -> float:
        c0, c1, c2 = self.coef
        return c0 + c1 * u + c2 * u * u


def _fit(points: list[tuple[float, float, float]], near: float, tol: float) -> _Fit | None:
    """The resonance curve of the FIT_POINTS points nearest ``near`` [Hz] (module docstring)."""
    pts = sorted(points, key=lambda p: abs(p[0] - near))[:FIT_POINTS]
    if len(pts) < 3:
        return None
    f = np.array([p[0] for p in pts])
    x = np.array([p[1] for p in pts])
    hw = np.array([p[2] for p in pts])
    f_ref = float(near)
    u = (f / f_ref) ** 2
    sigma_x = np.maximum(np.where(np.isfinite(hw), hw / 1.96, 0.0), tol * x)
    y = 1.0 / x**2
    sigma_y = np.maximum(2.0 * sigma_x / x**3, 1e-300)
    a = np.column_stack([np.ones_like(u), u, u * u]) / sigma_y[:, None]
    b = y / sigma_y
    coef, *_ = np.linalg.lstsq(a, b, rcond=None)
    cov = np.linalg.pinv(a.T @ a)
    dof = len(pts) - 3
    if dof > 0:  # the scatter about the curve, when the points tell it
        chi2 = float(np.sum((a @ coef - b) ** 2)) / dof
        cov = cov * max(chi2, 1.0)
    return _Fit(coef, cov, f_ref)


@dataclass(frozen=True)
class PeakSearch:
    """The search over [``lo``, ``hi``] Hz (module docstring): ``resolution`` [Hz] how close the
    fitted peak must settle, ``max_points`` the budget, ``tol`` the relative tolerance the
    points are computed to (their least uncertainty)."""

    lo: float
    hi: float
    resolution: float
    max_points: int = 7
    tol: float = 0.01

    def next_frequencies(self, points: list[tuple[float, float, float]]) -> list[float]:
        """The frequencies to run next, given the (frequency, amplitude, amplitude_ci) points
        run so far: the coarse pass first, then one refinement point at a time; [] when the
        search is done (converged, at an edge, or out of budget)."""
        done = {round(p[0], 9) for p in points}
        coarse = [f for f in coarse_frequencies(self.lo, self.hi) if round(f, 9) not in done]
        if coarse:
            return coarse
        if len(points) >= self.max_points:
            return []
        peak = self.peak(points)
        if peak.converged or peak.at_edge:
            return []
        f = min(max(peak.frequency_hz, self.lo), self.hi)
        if any(abs(f - p[0]) <= 0.25 * self.resolution for p in points):
            # the fit wants a point where one is: bisect towards the higher neighbour
            f = self._bisect(points)
        return [] if f is None else [f]

    def _bisect(self, points) -> float | None:
        pts = sorted(points)
        k = int(np.argmax([p[1] for p in pts]))
        side = [pts[j] for j in (k - 1, k + 1) if 0 <= j < len(pts)]
        if not side:
            return None
        other = max(side, key=lambda p: p[1])
        f = 0.5 * (pts[k][0] + other[0])
        return None if abs(f - pts[k][0]) < 0.25 * self.resolution else f

    def _estimate(self, pts):
        """(fitted peak frequency, the fit) of points, or None: fitted about the highest point,
        then about the peak that fit gives (module docstring, step 2)."""
        best = max(pts, key=lambda p: p[1])
        fit = _fit(pts, best[0], self.tol)
        if fit is None or not (math.isfinite(fit.peak_u()) and fit.peak_u() > 0.0):
            return None
        f1 = fit.f_ref * math.sqrt(fit.peak_u())
        refit = _fit(pts, f1, self.tol)
        if refit is not None and math.isfinite(refit.peak_u()) and refit.peak_u() > 0.0:
            fit = refit
        return fit.f_ref * math.sqrt(fit.peak_u()), fit

    def peak(self, points: list[tuple[float, float, float]]) -> Peak:
        """The peak the points give (module docstring, steps 2-4). It has converged when a
        measured point lies within ``resolution`` of the fitted peak and the points without
        that one fit the same peak (within ``resolution``, and its amplitude within the
        tolerance): the last refinement changed nothing that matters."""
        pts = sorted(points)
        best = max(pts, key=lambda p: p[1])
        n = len(pts)
        est = self._estimate(pts)
        if est is None:
            return Peak(
                best[0],
                math.inf,
                best[1],
                best[2],
                math.nan,
                math.nan,
                False,
                best[0] in (pts[0][0], pts[-1][0]),
                n,
            )
        f_new, fit = est
        at_edge = f_new < self.lo or f_new > self.hi
        f_peak = min(max(f_new, self.lo), self.hi)
        u_star = (f_peak / fit.f_ref) ** 2
        y_min = fit.value(u_star)
        amp = 1.0 / math.sqrt(y_min) if y_min > 0.0 else best[1]
        c0, c1, c2 = fit.coef
        # delta method: u* = -c1 / (2 c2); y* = c0 - c1^2 / (4 c2)
        g_u = np.array([0.0, -1.0 / (2.0 * c2), c1 / (2.0 * c2 * c2)])
        g_y = np.array([1.0, -c1 / (2.0 * c2), c1 * c1 / (4.0 * c2 * c2)])
        sd_u = math.sqrt(max(float(g_u @ fit.cov @ g_u), 0.0))
        sd_y = math.sqrt(max(float(g_y @ fit.cov @ g_y), 0.0))
        f_ci = 1.96 * fit.f_ref**2 * sd_u / (2.0 * f_new)
        amp_ci = 1.96 * 0.5 * sd_y / y_min**1.5 if y_min > 0.0 else math.inf
        half = math.sqrt(y_min / c2) if y_min > 0 else math.nan
        band_lo = fit.f_ref * math.sqrt(u_star - half) if u_star - half > 0 else math.nan
        band_hi = fit.f_ref * math.sqrt(u_star + half) if math.isfinite(half) else math.nan
        nearest = min(pts, key=lambda p: abs(p[0] - f_new))
        settled = False
        if abs(nearest[0] - f_new) <= self.resolution and n > 3:
            before = self._estimate([p for p in pts if p is not nearest])
            if before is not None:
                f_before, fit_before = before
                y_before = fit_before.value((f_before / fit_before.f_ref) ** 2)
                amp_before = 1.0 / math.sqrt(y_before) if y_before > 0.0 else math.inf
                settled = abs(f_before - f_new) <= self.resolution and abs(amp_before - amp) <= max(
                    self.tol * amp, amp_ci
                )
        return Peak(
            f_peak, f_ci, amp, amp_ci, band_lo, band_hi, settled and not at_edge, at_edge, n
        )
