"""The multi-mode fit on a real impact test: tests/fixtures/frf/measurement.uff (pyuff's
measured accelerances, three FRFs 0-1000 Hz at 1 Hz; provenance in tests/fixtures/frf/README.md).
Nothing is known of the structure beyond the file, so the modes are checked for being physically
consistent: the peaks a peak-pick finds, damping ratios of a lightly damped metal part with
their standard errors, the FRFs synthesised from the modes against the measured ones, the
frequency ratios of the free-free beam they turn out to be -- and the driving point that the
file's labels name but its data deny."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.signal import find_peaks

from cli_helpers import run_cli
from x3dpd.testlab.modal_fit import fit_set, frf_set

FIXTURE = Path(__file__).resolve().parents[1] / "fixtures" / "frf" / "measurement.uff"
BAND = (20.0, 1000.0)
#: beta_r L of a free-free uniform Euler-Bernoulli beam (cos(bL) cosh(bL) = 1), modes 1-6
BETA_L = np.array(
    [4.730040745, 7.853204624, 10.995607838, 14.137165491, 17.278759657, 20.420352245]
)


def test_six_modes_of_a_real_impact_test_are_physically_consistent():
    """Measured: 51.52, 142.18, 278.67, 460.40, 687.17, 958.53 Hz (standard errors 0.0005-0.005
    Hz), zeta 1.2e-4 to 3.4e-4 (mode 1's +- 37 %, the others' +- 0.5-2 %), RMS misfit 4.2 %,
    6.5 %, 8.7 % of the three FRFs' RMS (the peaks, narrower than the lines, carry most of it);
    frequency ratios within 0.18 % of a free-free beam's."""
    fs = frf_set([str(FIXTURE)])
    assert fs.roving == "reference" and fs.points == [(1, 1), (2, 1), (3, 1)]
    band, _, fit = fit_set(fs, 6, BAND)
    f = fs.frequency
    sel = (f >= band[0]) & (f <= band[1])
    # the same peaks as a peak-pick of the summed magnitudes (10 dB prominence), each mode
    # within half a line of its peak's line
    peaks, _ = find_peaks(20 * np.log10(np.sum(np.abs(fs.h[:, sel]), axis=0)), prominence=10)
    assert len(peaks) == 6
    assert np.all(np.abs(fit.fn - f[sel][peaks]) <= 0.5)
    assert np.all(fit.fn_se < 0.01)
    # damping of a lightly damped metal structure, each ratio known to better than +- 50 %
    assert np.all((fit.zeta > 5e-5) & (fit.zeta < 5e-3))
    assert np.all(fit.zeta_se < 0.5 * fit.zeta)
    # the FRFs synthesised from the six modes and the residual terms match the measured ones:
    # RMS difference below 10 % of each FRF's RMS over the band
    assert np.all(fit.misfit < 0.10)
    rms = np.linalg.norm(fit.model - fs.h[:, sel], axis=1) / np.linalg.norm(fs.h[:, sel], axis=1)
    assert np.allclose(rms, fit.misfit, rtol=1e-12)
    # a free-free uniform beam: f_r / f_1 = (beta_r / beta_1)^2 within 0.5 %
    ratio = (fit.fn / fit.fn[0]) / (BETA_L / BETA_L[0]) ** 2
    assert np.max(np.abs(ratio - 1)) < 0.005
    # the FRF labelled response 1:x / hammer 1:x: modal constants of alternating sign and a
    # negative rigid-body inertance -- the two ends of a free-free beam, not a driving point
    assert list(np.sign(fit.constants[fs.driving])) == [1, -1, 1, -1, 1, -1]
    assert fit.lower[fs.driving] < 0


def test_the_command_refuses_to_scale_shapes_by_a_driving_point_that_is_not_one(tmp_path, capsys):
    out = tmp_path / "fit"
    assert run_cli("fit", FIXTURE, "--modes", 6, "--band", "20:1000", "--out", out) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert str(FIXTURE) in err
    assert "mode(s) 2 (142.178 Hz), 4 (460.398 Hz), 6 (958.533 Hz)" in err
    assert not out.exists()
