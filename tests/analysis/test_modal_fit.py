"""The multi-mode fit of ``x3dpd fit --modes N`` (x3dpd.analysis.lscf: poles and stabilisation;
x3dpd.analysis.lsfd: modal constants, residual terms, refined poles, standard errors,
mass-normalised shapes) on FRF sets made here by modal superposition: three modes of known
frequency, damping and mass-normalised shape at four points, the hammer at point 1, plus known
residual terms -- without noise, and with complex Gaussian noise on each FRF."""

from __future__ import annotations

import numpy as np
import pytest

from x3dpd.analysis.lscf import lscf_poles, max_order, pole_groups, select_poles
from x3dpd.analysis.lsfd import refine_modes
from x3dpd.errors import InputError

FN = np.array([40.0, 95.0, 150.0])
ZETA = np.array([0.01, 0.02, 0.015])
PHI = 3.0 * np.array([[1.0, 0.8, 0.5], [0.7, -0.4, -0.9], [0.3, -1.0, 0.6], [-0.5, 0.6, 1.1]])
LOWER = np.array([0.5, 0.3, 0.2, -0.1])
UPPER = np.array([2e-6, -1e-6, 5e-7, 1.5e-6])
F = np.linspace(20.0, 180.0, 641)  # 0.25 Hz lines: 16 to 100 lines per half-power width
BAND = (20.0, 180.0)


def frfs(order: int = 2, f=F) -> np.ndarray:
    """(i w)^q [sum_r phi_or phi_1r / (w_r^2 - w^2 + 2 i zeta_r w_r w) + L_o / (i w)^2 + U_o]
    at the four points (rows), driven at point 1."""
    w = 2 * np.pi * f
    wn = 2 * np.pi * FN
    receptance = np.zeros((4, f.size), dtype=complex)
    for r in range(3):
        receptance += np.outer(
            PHI[:, r] * PHI[0, r], 1 / (wn[r] ** 2 - w**2 + 2j * ZETA[r] * wn[r] * w)
        )
    receptance += np.outer(LOWER, 1 / (1j * w) ** 2) + UPPER[:, None]
    return receptance * (1j * w) ** order


def noisy(h: np.ndarray, level: float, seed: int) -> np.ndarray:
    """``h`` plus complex Gaussian noise of RMS ``level`` times each FRF's RMS."""
    rng = np.random.default_rng(seed)
    sigma = level * np.sqrt(np.mean(np.abs(h) ** 2, axis=1))[:, None] / np.sqrt(2)
    return h + sigma * (rng.standard_normal(h.shape) + 1j * rng.standard_normal(h.shape))


def fit(h, n_modes: int = 3, order: int = 2):
    poles = lscf_poles(F, h, band=BAND, max_order=max_order(n_modes, F.size))
    lam = select_poles(pole_groups(poles), n_modes, band=BAND)
    return refine_modes(
        F, h, np.abs(lam) / (2 * np.pi), -lam.real / np.abs(lam), order=order, driving=0, band=BAND
    )


@pytest.mark.parametrize("order", [0, 1, 2])
def test_noiseless_set_gives_the_modes_back_to_round_off(order):
    """Receptance, mobility and accelerance alike: every parameter to 1e-6 (measured: fn and
    zeta to 2e-16, shapes to 1e-12, the lower term to 5e-10, the upper one -- its column
    (i w)^q is 1e9 times the others' -- to 8e-9); the synthesis is the data to 1e-8 of its RMS
    (2e-10 measured)."""
    result = fit(frfs(order), order=order)
    phi, _ = result.shapes()
    assert np.max(np.abs(result.fn / FN - 1)) < 1e-6
    assert np.max(np.abs(result.zeta / ZETA - 1)) < 1e-6
    assert np.max(np.abs(phi - PHI)) < 1e-6 * np.max(np.abs(PHI))
    assert np.max(np.abs(result.lower - LOWER)) < 1e-6 * np.max(np.abs(LOWER))
    assert np.max(np.abs(result.upper - UPPER)) < 1e-6 * np.max(np.abs(UPPER))
    assert np.max(result.misfit) < 1e-8


def test_noisy_set_within_four_standard_errors():
    """1 % noise (of each FRF's RMS; 1.0 % RMS misfit): every frequency, damping ratio, shape
    value and residual term lies within four of its stated standard errors of the truth (a 6e-5
    chance each for a Gaussian estimate). With this seed the largest is 2.8 standard errors (a
    damping ratio); the standard errors are up to 7e-6 of fn, 5e-4 of zeta and 2e-4 of the
    largest shape value."""
    result = fit(noisy(frfs(), 0.01, seed=7))
    phi, phi_se = result.shapes()
    n = 3
    cov = result.coef_cov
    se_lower = np.sqrt([cov[o, 0, n, n] for o in range(4)])
    se_upper = np.sqrt([cov[o, 0, n + 1, n + 1] for o in range(4)])
    assert np.all(np.abs(result.fn - FN) < 4 * result.fn_se)
    assert np.all(np.abs(result.zeta - ZETA) < 4 * result.zeta_se)
    assert np.all(np.abs(phi - PHI) < 4 * phi_se)
    assert np.all(np.abs(result.lower - LOWER) < 4 * se_lower)
    assert np.all(np.abs(result.upper - UPPER) < 4 * se_upper)
    # the errors are small as well as consistent: the bounds are not loose
    assert np.all(result.fn_se < 1e-5 * FN) and np.all(result.zeta_se < 2e-3 * ZETA)
    assert np.all(phi_se < 1e-3 * np.abs(PHI).max())
    assert abs(result.s2 - 1) < 0.1  # the weights are each FRF's noise level


def test_standard_errors_are_what_the_errors_are():
    """Over 24 noise draws at 5 %, the errors divided by their stated standard errors have an
    RMS of 1 if the standard errors are right. With 72 normalised errors per quantity (24 x 3
    modes) the RMS of a standard normal sample is 1 +- 8 % (one standard deviation, 1 /
    sqrt(2 K)); the bounds 0.7-1.35 are four of those below and above. Measured: fn 0.89, zeta
    0.94, shapes 0.99 (288 values)."""
    truth = frfs()
    z_fn, z_zeta, z_phi = [], [], []
    for seed in range(24):
        result = fit(noisy(truth, 0.05, seed=100 + seed))
        phi, phi_se = result.shapes()
        z_fn += list((result.fn - FN) / result.fn_se)
        z_zeta += list((result.zeta - ZETA) / result.zeta_se)
        z_phi += list(((phi - PHI) / phi_se).ravel())
    for z in (z_fn, z_zeta, z_phi):
        rms = float(np.sqrt(np.mean(np.square(z))))
        assert 0.7 < rms < 1.35, rms


def test_the_stabilisation_finds_the_three_modes_and_no_fourth():
    """At 5 % noise the three modes are stable at 16-17 orders each and any other pole at one
    (at most two allowed): asking for four modes is refused, naming the three."""
    h = noisy(frfs(), 0.05, seed=3)
    poles = lscf_poles(F, h, band=BAND, max_order=max_order(4, F.size))
    groups = pole_groups(poles)
    assert sorted(round(g.fn) for g in groups[:3]) == [40, 95, 150]
    assert min(g.n_orders for g in groups[:3]) >= 10
    assert all(g.n_orders < 3 for g in groups[3:])
    with pytest.raises(
        InputError, match=r"shows 3 stable mode\(s\) \(Hz: 40[.\d]*, 9[45][.\d]*, 150[.\d]*\)"
    ):
        select_poles(groups, 4, band=BAND)


def test_shapes_need_positive_constants_at_the_driving_point():
    """An FRF set of reversed sign gives every mode a negative constant at the driving point
    (refused, saying the sign is reversed); a driving point that is not one (here point 2's FRF
    named the driving point) gives some negative ones (refused, naming the modes)."""
    h = frfs()
    reversed_sign = fit(-h)
    with pytest.raises(InputError, match="sign is reversed"):
        reversed_sign.shapes()
    poles = lscf_poles(F, h, band=BAND, max_order=max_order(3, F.size))
    lam = select_poles(pole_groups(poles), 3, band=BAND)
    wrong = refine_modes(
        F, h, np.abs(lam) / (2 * np.pi), -lam.real / np.abs(lam), order=2, driving=1, band=BAND
    )
    with pytest.raises(InputError, match=r"mode\(s\) 2 \(95 Hz\), 3 \(150 Hz\) have a modal"):
        wrong.shapes()
