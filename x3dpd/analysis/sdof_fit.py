"""A single-mode (SDOF) model fitted to a measured FRF near one mode (report Section 8.2, Table 4).

The model of a response of order q (0 displacement, 1 velocity, 2 acceleration) per unit of
excitation is

.. math::

    H(f) = (i \\omega)^q \\frac{R}{\\omega_n^2 - \\omega^2 + 2 i \\zeta \\omega_n \\omega},
    \\qquad \\omega = 2 \\pi f, \\; \\omega_n = 2 \\pi f_n,

the receptance of a mass m on a spring k = m w_n^2 and a damper c = 2 zeta m w_n, driven by a force
S per unit of excitation: R = S / m. One FRF fixes f_n, zeta and R only; the effective mass and
the force scale are split by giving one of them (S = 1 when the FRF is per unit force: m = 1 / R;
a known mass m: S = R m, what the report did to turn 200 mV RMS at the shaker into the drive force
of Table 4).

The fit (:func:`fit_sdof`) minimises the relative complex residual
``(H_model - H) / |H|`` over the band (:func:`scipy.optimize.least_squares`), the right weighting
for noise proportional to the response, from a start read off the data: the peak of
``|H / (i w)^q|`` for f_n, the half-power width for zeta, the peak height for R. Standard errors
are those of the linearised least squares, ``s^2 (J^T J)^-1`` with ``s^2`` the residual variance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from x3dpd.errors import InputError


def sdof_frf(frequency, fn: float, zeta: float, residue: float, order: int) -> np.ndarray:
    """The model FRF (module docstring) at ``frequency`` [Hz]."""
    w = 2.0 * np.pi * np.asarray(frequency, dtype=float)
    wn = 2.0 * np.pi * fn
    return (1j * w) ** order * residue / (wn * wn - w * w + 2j * zeta * wn * w)


@dataclass(frozen=True)
class SdofFit:
    """Fitted ``fn`` [Hz], ``zeta``, ``residue`` R = S / m, their standard errors, the RMS
    relative residual, the band [Hz] and number of points used, and the response order q."""

    fn: float
    zeta: float
    residue: float
    fn_se: float
    zeta_se: float
    residue_se: float
    residual: float
    band: tuple[float, float]
    n_points: int
    order: int

    def model(self, frequency) -> np.ndarray:
        return sdof_frf(frequency, self.fn, self.zeta, self.residue, self.order)

    def deck_values(
        self, *, mass: float | None = None, force_scale: float | None = None
    ) -> dict[str, float]:
        """``mass``, ``force_scale``, ``stiffness`` m w_n^2 and ``damping`` 2 zeta m w_n, from the
        given mass or force scale (default: force scale 1, the FRF is per unit force)."""
        if mass is not None and force_scale is not None:
            raise InputError("give the effective mass or the force scale, not both")
        if mass is not None:
            if not mass > 0:
                raise InputError(f"the effective mass must be > 0, got {mass!r}")
            force_scale = self.residue * mass
        else:
            force_scale = 1.0 if force_scale is None else force_scale
            if force_scale == 0 or not math.isfinite(force_scale):
                raise InputError(
                    f"the force scale must be a finite non-zero number, got {force_scale!r}"
                )
            mass = force_scale / self.residue
        if mass <= 0:
            raise InputError(
                f"the fit gives a negative mass {mass:.4g} for force scale "
                f"{force_scale:g}: the FRF's sign is reversed (drive and response "
                "in opposite directions); give a negative force scale (--force-scale "
                f"{-force_scale:g})"
            )
        wn = 2.0 * math.pi * self.fn
        return {
            "mass": mass,
            "force_scale": force_scale,
            "stiffness": mass * wn * wn,
            "damping": 2.0 * self.zeta * mass * wn,
        }


def _start(f: np.ndarray, hd: np.ndarray) -> tuple[float, float, float]:
    """f_n, zeta, R read off a receptance ``hd``: its peak, half-power width and height."""
    mag = np.abs(hd)
    k = int(np.argmax(mag))
    fn = float(f[k])
    half = mag[k] / math.sqrt(2.0)
    lo = k
    while lo > 0 and mag[lo] > half:
        lo -= 1
    hi = k
    while hi < mag.size - 1 and mag[hi] > half:
        hi += 1
    width = float(f[hi] - f[lo])
    zeta = min(max(0.5 * width / fn, 1e-4), 0.5) if width > 0 else 0.02
    wn = 2.0 * math.pi * fn
    # at resonance hd = R / (2 i zeta wn^2): R = -Im(hd) 2 zeta wn^2
    residue = -float(np.imag(hd[k])) * 2.0 * zeta * wn * wn
    if residue == 0.0:
        residue = float(mag[k]) * 2.0 * zeta * wn * wn
    return fn, zeta, residue


def fit_sdof(frequency, h, *, order: int, band: tuple[float, float] | None = None) -> SdofFit:
    """Fit the single-mode model to ``h`` (complex, at ``frequency`` [Hz]) over ``band``.

    ``order`` is the response's order q (0, 1, 2). Raises :class:`InputError` for a band outside
    the data or with fewer than 5 points.
    """
    from scipy.optimize import least_squares

    f = np.asarray(frequency, dtype=float)
    h = np.asarray(h, dtype=complex)
    if order not in (0, 1, 2):
        raise InputError(f"response order must be 0, 1 or 2, got {order!r}")
    lo, hi = band if band is not None else (float(f[0]), float(f[-1]))
    if not lo < hi:
        raise InputError(f"fit band {lo:g}:{hi:g} Hz: expected LO < HI")
    if hi <= f[0] or lo >= f[-1]:
        raise InputError(
            f"fit band {lo:g}:{hi:g} Hz lies outside the data ({f[0]:g} .. {f[-1]:g} Hz)"
        )
    sel = (f >= lo) & (f <= hi) & (f > 0) & (np.abs(h) > 0)
    if np.count_nonzero(sel) < 5:
        raise InputError(
            f"fit band {lo:g}:{hi:g} Hz holds {np.count_nonzero(sel)} usable "
            "points; at least 5 are needed"
        )
    f, h = f[sel], h[sel]
    hd = h / (2j * np.pi * f) ** order
    x0 = np.array(_start(f, hd))
    weight = 1.0 / np.abs(h)

    def residuals(p):
        r = (sdof_frf(f, p[0], p[1], p[2], order) - h) * weight
        return np.concatenate([r.real, r.imag])

    scale = np.array([x0[0], x0[1], abs(x0[2])])
    sol = least_squares(
        residuals,
        x0,
        x_scale=scale,
        method="trf",
        bounds=([f[0] * 0.5, 1e-6, -np.inf], [f[-1] * 2.0, 0.99, np.inf]),
        xtol=1e-14,
        ftol=1e-14,
        gtol=1e-14,
        max_nfev=2000,
    )
    res = sol.fun
    dof = max(res.size - 3, 1)
    s2 = float(res @ res) / dof
    try:
        cov = np.linalg.inv(sol.jac.T @ sol.jac) * s2
        se = np.sqrt(np.maximum(np.diag(cov), 0.0))
    except np.linalg.LinAlgError:
        se = np.full(3, np.nan)
    rms = float(np.sqrt(np.mean(np.abs(res[: f.size] + 1j * res[f.size :]) ** 2)))
    return SdofFit(
        float(sol.x[0]),
        float(sol.x[1]),
        float(sol.x[2]),
        float(se[0]),
        float(se[1]),
        float(se[2]),
        rms,
        (float(lo), float(hi)),
        int(f.size),
        order,
    )
