"""The single-mode fit of ``x3dpd fit`` (x3dpd.analysis.sdof_fit) on FRFs made here from the
SDOF's closed form, without and with 5 % noise, and the spectral helpers of x3dpd.analysis.frf."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.analysis.frf import (
    amplitude_spectrum,
    central_difference,
    difference_gain,
    equivalent_averages,
)
from x3dpd.analysis.sdof_fit import fit_sdof
from x3dpd.errors import InputError

M, K, ZETA = 1.87646e-4, 11.4823, 0.02  # the report's Table 4 beam, 2 % damping
FN = math.sqrt(K / M) / (2 * math.pi)  # 39.37 Hz
F = np.linspace(30.0, 50.0, 201)  # 0.1 Hz lines, 12 half-power widths


def sdof(f, order, m=M, k=K, zeta=ZETA, scale=1.0):
    """(i w)^q S / (k - m w^2 + i c w), c = 2 zeta sqrt(k m): receptance, mobility, accelerance."""
    w = 2 * np.pi * np.asarray(f)
    c = 2 * zeta * math.sqrt(k * m)
    return (1j * w) ** order * scale / (k - m * w * w + 1j * c * w)


@pytest.mark.parametrize("order", [0, 1, 2])
def test_noiseless_fit_recovers_the_sdof(order):
    fit = fit_sdof(F, sdof(F, order), order=order)
    values = fit.deck_values()  # force scale 1: an FRF per unit force
    assert abs(fit.fn / FN - 1) < 0.005
    assert abs(fit.zeta / ZETA - 1) < 0.005
    assert abs(values["mass"] / M - 1) < 0.005
    assert abs(values["stiffness"] / K - 1) < 0.005
    assert abs(values["damping"] / (2 * ZETA * math.sqrt(K * M)) - 1) < 0.005
    assert fit.residual < 1e-6


def test_mass_or_force_scale_splits_the_residue():
    # an FRF per volt: 0.3 lbf per volt on the mass M
    fit = fit_sdof(F, sdof(F, 2, scale=0.3), order=2, band=(35.0, 45.0))
    by_mass = fit.deck_values(mass=M)
    assert abs(by_mass["force_scale"] / 0.3 - 1) < 0.005
    by_scale = fit.deck_values(force_scale=0.3)
    assert abs(by_scale["mass"] / M - 1) < 0.005
    with pytest.raises(InputError, match="not both"):
        fit.deck_values(mass=M, force_scale=0.3)


def test_five_percent_noise_stays_within_four_standard_errors():
    """H (1 + e), e complex Gaussian with RMS |e| = 5 % (0.05 / sqrt(2) per component).

    Bound: the fit minimises the relative residual, for which this noise is white with
    variance s^2 = 0.05^2 / 2 per component; to first order the estimate's covariance is
    s^2 (J^T J)^-1 with J the Jacobian of the relative residual (re and im stacked) at the true
    parameters -- computed here from the closed form by central differences. Four standard
    errors (a 6e-5 chance per parameter for a Gaussian estimate) bound each error; they come to
    0.06 % of fn, 3.1 % of zeta and 1.1 % of the mass here (201 points over 12 half-power
    widths). Measured with this seed: -0.007 %, -0.41 %, +0.19 % (of R = 1 / m)."""
    order = 2
    rng = np.random.default_rng(2003)
    noise = 0.05 * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / math.sqrt(2)
    h_true = sdof(F, order)
    fit = fit_sdof(F, h_true * (1 + noise), order=order)
    p0 = np.array([FN, ZETA, 1 / M])  # fn, zeta, R = 1 / m

    def rel(p):
        wn = 2 * np.pi * p[0]
        w = 2 * np.pi * F
        h = (1j * w) ** order * p[2] / (wn * wn - w * w + 2j * p[1] * wn * w)
        r = (h - h_true) / np.abs(h_true)
        return np.concatenate([r.real, r.imag])

    jac = np.empty((2 * F.size, 3))
    for j in range(3):
        dp = np.zeros(3)
        dp[j] = 1e-6 * p0[j]
        jac[:, j] = (rel(p0 + dp) - rel(p0 - dp)) / (2 * dp[j])
    sigma = np.sqrt(np.diag(np.linalg.inv(jac.T @ jac)) * 0.05**2 / 2)
    got = np.array([fit.fn, fit.zeta, fit.residue])
    assert np.all(np.abs(got - p0) < 4 * sigma), (got - p0) / sigma
    bound = 4 * sigma / p0
    assert bound[0] < 0.001 and bound[1] < 0.04 and bound[2] < 0.015  # the stated bounds
    # the fit's own standard errors estimate the same spread (within 25 %)
    np.testing.assert_allclose([fit.fn_se, fit.zeta_se, fit.residue_se], sigma, rtol=0.25)
    assert abs(fit.residual - 0.05) < 0.01  # the residual is the noise level


def test_fit_band_errors():
    h = sdof(F, 0)
    with pytest.raises(InputError, match="outside the data"):
        fit_sdof(F, h, order=0, band=(60.0, 80.0))
    with pytest.raises(InputError, match="usable points"):
        fit_sdof(F, h, order=0, band=(39.0, 39.25))


def test_amplitude_spectrum_reads_a_sines_amplitude():
    fs, n = 1000.0, 4000
    t = np.arange(n) / fs
    f, amp = amplitude_spectrum(0.7 * np.sin(2 * np.pi * 37.25 * t) + 0.2, fs)
    k = int(np.argmax(amp))
    assert f[k] == 37.25 and abs(amp[k] / 0.7 - 1) < 1e-3  # on a bin: the window's gain out


def test_central_difference_gain():
    fs = 1000.0
    t = np.arange(20000) / fs
    for hz in (10.0, 150.0, 300.0):
        v = np.sin(2 * np.pi * hz * t)
        a = central_difference(v, fs)[1:-1]
        exact = 2 * np.pi * hz * np.cos(2 * np.pi * hz * t[1:-1])
        # (v[n+1] - v[n-1]) fs / 2 = sin(w / fs) fs cos(w t): exactly the gain times i w
        np.testing.assert_allclose(a, exact * difference_gain(hz, fs), atol=1e-9 * exact.max())


def test_equivalent_averages_of_hann_at_half_overlap():
    # rho_1 = 1/6 for a Hann window at 50 % overlap (Welch 1967): n = n_d / (1 + 2 (1 - 1/n_d) / 36)
    n_d = 19
    want = n_d / (1 + 2 * (1 - 1 / n_d) / 36)
    assert abs(equivalent_averages("hann", 4000, 2000, n_d) / want - 1) < 1e-3
