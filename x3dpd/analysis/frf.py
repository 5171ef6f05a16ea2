"""Frequency response functions and spectra from sampled drive and response histories (Welch).

With the one-sided auto and cross spectral densities of the drive x and a response y estimated by
Welch's method (``n_d`` windowed segments, averaged; :func:`scipy.signal.csd`),

.. math::

    H_1 = G_{xy} / G_{xx}, \\qquad H_2 = G_{yy} / G_{yx}, \\qquad
    \\gamma^2 = |G_{xy}|^2 / (G_{xx} G_{yy})

(``G_xy = 2 E[X* Y] / T``: ``H_1`` is unbiased by noise on the response, ``H_2`` by noise on the
drive; ``H_1 <= H_2`` in magnitude, equal where the coherence is 1). The 95 % confidence region of
the true FRF around ``H_1`` is the circle of radius

.. math::

    r^2 = \\frac{2}{n - 2} F_{2, n-2; 0.05} (1 - \\gamma^2) \\frac{G_{yy}}{G_{xx}}

in the complex plane: ``|H| - r <= |H_true| <= |H| + r`` and the phase within
``asin(r / |H|)`` (Bendat & Piersol, *Random Data*, Chapter 9: the F-distribution region of a
frequency response estimate, after Goodman), with ``n`` the equivalent number of independent
averages. Overlapping segments are not independent: Welch's estimate has the variance of
``n = n_d / (1 + 2 sum_j (1 - j/n_d) rho_j^2)`` independent ones, with ``rho_j`` the
correlation of the window with itself shifted by j segment steps (0.167 for Hann at 50 %
overlap: n = 0.95 n_d; :func:`equivalent_averages`).

The normalised random error of ``|H_1|`` is ``sqrt(1 - gamma^2) / (|gamma| sqrt(2 n))``
(Bendat & Piersol, Chapter 9, its table of random errors). Frequencies in Hz, spectral
densities in units^2/Hz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from x3dpd.errors import InputError

#: Response quantities of an FRF and the power of (i w) that turns a displacement FRF into each.
QUANTITY_ORDER = {"displacement": 0, "velocity": 1, "acceleration": 2}


@dataclass(frozen=True)
class FrfEstimate:
    """H1, H2 and the coherence between one drive and ``m`` responses.

    Arrays are ``(nf,)`` (``frequency``, ``gxx``) or ``(m, nf)`` (the rest); ``n_segments`` is the
    number of Welch segments averaged, ``n_effective`` the equivalent independent averages.
    """

    frequency: np.ndarray
    gxx: np.ndarray
    gyy: np.ndarray
    gxy: np.ndarray
    n_segments: int
    n_effective: float
    nperseg: int
    noverlap: int
    window: str
    fs: float

    @property
    def h1(self) -> np.ndarray:
        """``G_xy / G_xx`` (m, nf)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.gxy / self.gxx

    @property
    def h2(self) -> np.ndarray:
        """``G_yy / G_yx`` (m, nf); G_yx = conj(G_xy)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.gyy / np.conj(self.gxy)

    @property
    def coherence(self) -> np.ndarray:
        """``|G_xy|^2 / (G_xx G_yy)`` in [0, 1] (m, nf)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.clip(np.abs(self.gxy) ** 2 / (self.gxx * self.gyy), 0.0, 1.0)

    def confidence_radius(self, level: float = 0.95) -> np.ndarray:
        """Radius ``r`` (m, nf) of the ``level`` confidence circle of the true FRF around H1
        (module docstring); needs more than 2 equivalent averages."""
        from scipy.stats import f as f_dist

        n = self.n_effective
        if n <= 2.0:
            raise InputError(
                f"FRF confidence: {n:.2f} equivalent averages; more than 2 are "
                "needed (a longer record or shorter segments)"
            )
        fq = f_dist.ppf(level, 2, n - 2.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            r2 = 2.0 / (n - 2.0) * fq * (1.0 - self.coherence) * self.gyy / self.gxx
        return np.sqrt(np.maximum(r2, 0.0))

    def random_error(self) -> np.ndarray:
        """Normalised random error of ``|H1|``: sqrt(1 - g^2) / (|g| sqrt(2 n)) (m, nf)."""
        g2 = self.coherence
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.sqrt(1.0 - g2) / np.sqrt(g2 * 2.0 * self.n_effective)

    def divided(self, factor) -> FrfEstimate:
        """The estimate for the response whose spectrum is this one's divided by ``factor``
        (nf,) complex: G_xy / factor, G_yy / |factor|^2 (the coherence is unchanged) -- e.g. a
        central difference's gain sinc(w dt) taken out (:func:`central_difference`)."""
        factor = np.asarray(factor)
        return FrfEstimate(
            self.frequency,
            self.gxx,
            self.gyy / np.abs(factor) ** 2,
            self.gxy / factor,
            self.n_segments,
            self.n_effective,
            self.nperseg,
            self.noverlap,
            self.window,
            self.fs,
        )


def central_difference(signal, fs: float) -> np.ndarray:
    """The derivative of a signal sampled at ``fs`` [Hz] by central differences,
    ``(y[n+1] - y[n-1]) fs / 2`` (one-sided at the two ends). Its gain differs from ``i w`` by
    :func:`difference_gain`, a real factor to divide its spectra by (exact for a stationary
    signal).

    The derivative is taken before the segments are windowed, so that the estimate of an
    acceleration from a velocity sees the same window as the drive; multiplying the velocity's
    windowed spectrum by i w instead would add the window's derivative, a leakage of relative
    size ~ 1 / (f T_segment).
    """
    return np.gradient(np.asarray(signal, dtype=float), 1.0 / fs)


def difference_gain(frequency, fs: float) -> np.ndarray:
    """``sin(w / fs) / (w / fs)`` at ``frequency`` [Hz]: the central difference's gain over
    ``i w`` (:func:`central_difference`; 1 - (w / fs)^2 / 6 at low frequency, 0 at Nyquist)."""
    return np.sinc(2.0 * np.asarray(frequency, dtype=float) / fs)


def check_window(window, option: str = "--window"):
    """``window`` when :func:`scipy.signal.get_window` knows it (a name such as ``hann``, or
    a tuple with its parameters); else an InputError naming ``option`` and the value."""
    from scipy.signal import get_window

    try:
        get_window(window, 16)
    except (ValueError, TypeError) as exc:
        why = "" if str(exc).startswith("Invalid window name") else f" ({exc})"
        raise InputError(
            f"{option} {window!r}: not a window scipy.signal.get_window knows{why}; "
            "e.g. hann, hamming, blackman, flattop, boxcar (rectangular)"
        ) from None
    return window


def welch_segments(n: int, nperseg: int, noverlap: int) -> int:
    """Number of segments Welch's method averages over ``n`` samples."""
    return 0 if n < nperseg else (n - nperseg) // (nperseg - noverlap) + 1


def equivalent_averages(window, nperseg: int, noverlap: int, n_segments: int) -> float:
    """Independent averages equivalent to ``n_segments`` overlapping windowed segments (Welch
    1967): ``n_d / (1 + 2 sum_j (1 - j / n_d) rho_j^2)``, ``rho_j`` = the window's overlap
    correlation at a shift of j steps."""
    from scipy.signal import get_window

    w = np.asarray(get_window(window, nperseg) if isinstance(window, str) else window, float)
    step = nperseg - noverlap
    denom = float(np.sum(w * w))
    total = 1.0
    for j in range(1, n_segments):
        shift = j * step
        if shift >= nperseg:
            break
        rho = float(np.sum(w[shift:] * w[: nperseg - shift])) / denom
        total += 2.0 * (1.0 - j / n_segments) * rho * rho
    return n_segments / total


#: the shortest Welch segment [samples]
MIN_SEGMENT = 8


def _check_welch(n: int, fs: float, nperseg: int, noverlap: int | None) -> int:
    if not (np.isfinite(fs) and fs > 0):
        raise InputError(f"sampling rate must be a positive number, got {fs!r}")
    if nperseg < MIN_SEGMENT:
        raise InputError(f"segment length {nperseg} samples: at least {MIN_SEGMENT} are needed")
    if noverlap is None:
        noverlap = nperseg // 2
    if not 0 <= noverlap < nperseg:
        raise InputError(
            f"overlap {noverlap} samples: expected 0 <= overlap < segment length {nperseg}"
        )
    if n < nperseg:
        raise InputError(
            f"the record holds {n} samples ({n / fs:.4g} s), fewer than one "
            f"segment of {nperseg} ({nperseg / fs:.4g} s); give a shorter segment"
        )
    return noverlap


def estimate_frf(
    drive,
    responses,
    fs: float,
    *,
    nperseg: int,
    noverlap: int | None = None,
    window="hann",
    detrend="constant",
) -> FrfEstimate:
    """H1, H2 and coherence between ``drive`` (n,) and ``responses`` (n,) or (m, n).

    ``fs`` [Hz] is the sampling rate; ``nperseg`` samples per Welch segment (the frequency
    resolution is fs / nperseg), ``noverlap`` (default half a segment), ``window`` any
    :func:`scipy.signal.get_window` name, ``detrend`` as scipy's (``"constant"`` removes each
    segment's mean).
    """
    from scipy.signal import csd, welch

    x = np.asarray(drive, dtype=float)
    y = np.atleast_2d(np.asarray(responses, dtype=float))
    if x.ndim != 1 or y.shape[1] != x.shape[0]:
        raise InputError(f"drive ({x.shape}) and responses ({y.shape}) must share their length")
    noverlap = _check_welch(x.shape[0], fs, nperseg, noverlap)
    opts = dict(fs=fs, window=window, nperseg=nperseg, noverlap=noverlap, detrend=detrend)
    freq, gxx = welch(x, **opts)
    _, gyy = welch(y, axis=-1, **opts)
    _, gxy = csd(x[None, :], y, axis=-1, **opts)
    nseg = welch_segments(x.shape[0], nperseg, noverlap)
    return FrfEstimate(
        freq,
        gxx,
        gyy,
        gxy,
        nseg,
        equivalent_averages(window, nperseg, noverlap, nseg),
        nperseg,
        noverlap,
        str(window),
        float(fs),
    )


def power_spectrum(
    signal,
    fs: float,
    *,
    nperseg: int,
    noverlap: int | None = None,
    window="hann",
    detrend="constant",
) -> tuple[np.ndarray, np.ndarray]:
    """One-sided PSD [units^2/Hz] of ``signal`` by Welch's method: ``(frequency, psd)``."""
    from scipy.signal import welch

    x = np.asarray(signal, dtype=float)
    noverlap = _check_welch(x.shape[0], fs, nperseg, noverlap)
    return welch(x, fs=fs, window=window, nperseg=nperseg, noverlap=noverlap, detrend=detrend)


def amplitude_spectrum(signal, fs: float, *, window="hann") -> tuple[np.ndarray, np.ndarray]:
    """Single-sided amplitude spectrum of the whole record (one FFT, the report's Fig. 10):
    ``(frequency, amplitude)``, a sine of amplitude A at a bin frequency reads A (the window's
    coherent gain divided out; the mean removed)."""
    from scipy.signal import get_window

    x = np.asarray(signal, dtype=float)
    if x.ndim != 1 or x.shape[0] < 8:
        raise InputError("amplitude spectrum: a 1-D record of at least 8 samples is needed")
    w = get_window(window, x.shape[0])
    spec = np.fft.rfft((x - x.mean()) * w)
    amp = 2.0 * np.abs(spec) / np.sum(w)
    amp[0] *= 0.5
    return np.fft.rfftfreq(x.shape[0], 1.0 / fs), amp


def third_octave_bands(lo: float, hi: float) -> list[tuple[float, float, float]]:
    """Base-10 third-octave bands (centre 1000 * 10^(k/10) Hz, edges centre * 10^(+-1/20))
    lying wholly inside [lo, hi]: ``[(lower, centre, upper), ...]``."""
    out = []
    for k in range(-40, 30):
        centre = 1000.0 * 10.0 ** (k / 10.0)
        a, b = centre * 10.0 ** (-0.05), centre * 10.0**0.05
        if a >= lo and b <= hi:
            out.append((a, centre, b))
    return out


def band_mean(frequency, values, lo: float, hi: float) -> float:
    """Mean of ``values`` over the frequencies in [lo, hi] (a band level of a PSD)."""
    f = np.asarray(frequency)
    sel = (f >= lo) & (f <= hi)
    if not np.any(sel):
        raise InputError(f"no frequency line in the band {lo:g}-{hi:g} Hz")
    return float(np.mean(np.asarray(values)[..., sel], axis=-1))
