"""``x3dpd fit`` (one mode) on a band with too few lines and on an FRF of reversed sign -- issue 33
items 11 and 24: the error names the file, says how many lines the band holds and the minimum,
and for a reversed sign what to pass; the fit then works with it."""

from __future__ import annotations

import math
import re

import numpy as np

from cli_helpers import run_cli
from x3dpd.io.measured import write_frf_csv

M, K, ZETA = 1.87646e-4, 11.4823, 0.02  # Table 4's beam at 2 % damping
FN = math.sqrt(K / M) / (2 * math.pi)  # 39.37 Hz


def _accelerance(f, scale=1.0):
    w = 2 * np.pi * f
    return -(w**2) * scale / (K - M * w * w + 2j * ZETA * math.sqrt(K * M) * w)


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert err.startswith("x3dpd: error: ") and "\n" not in err, err
    return err


def test_a_band_with_too_few_lines_names_the_file_and_the_minimum(tmp_path, capsys):
    """0.2 Hz lines: 142.2-142.8 Hz holds 4 of them (142.2, 142.4, 142.6, 142.8), one short."""
    f = np.round(np.arange(100.0, 200.0001, 0.2), 10)
    csv = tmp_path / "m.csv"
    write_frf_csv(csv, f, _accelerance(f), quantity="acceleration")
    out = tmp_path / "fit"
    assert run_cli("fit", csv, "--band", "142.2:142.8", "--out", out) == 2
    err = _one_error_line(capsys)
    assert err == (
        f"x3dpd: error: {csv}: --band 142.2:142.8 Hz holds 4 usable line(s) of the file's 501 "
        "(0.2 Hz apart); a fit needs at least 5: widen the band"
    )
    assert not out.exists()
    assert run_cli("fit", csv, "--band", "142.3:142.35", "--out", out) == 2
    assert "holds 0 usable line(s)" in _one_error_line(capsys)
    assert run_cli("fit", csv, "--band", "142.2:143.0", "--out", out, "--quiet") == 0


def test_a_reversed_sign_says_which_force_scale_to_pass(tmp_path, capsys):
    """Drive and response in opposite directions: refused with the exact option (the negative
    of the force scale given), nothing written; with it, the beam's mass, stiffness and damping
    come back (noiseless: within 0.5 %, in fact 1e-9)."""
    f = np.linspace(30.0, 50.0, 201)
    csv = tmp_path / "reversed.csv"
    write_frf_csv(csv, f, -_accelerance(f), quantity="acceleration")
    out = tmp_path / "fit"
    assert run_cli("fit", csv, "--out", out) == 2
    err = _one_error_line(capsys)
    assert str(csv) in err and "sign is reversed" in err and err.endswith("pass --force-scale -1")
    assert not out.exists()
    assert run_cli("fit", csv, "--force-scale", 0.3, "--out", out) == 2
    assert _one_error_line(capsys).endswith("pass --force-scale -0.3")
    assert run_cli("fit", csv, "--force-scale", -1, "--out", out, "--quiet") == 0
    text = (out / "fit.txt").read_text()
    mass = float(re.search(r"\$   m = (\S+),", text).group(1))
    stiffness = float(re.search(r"k = m wn\^2 = (\S+),", text).group(1))
    assert abs(mass / M - 1) < 0.005 and abs(stiffness / K - 1) < 0.005
    # the effective mass given instead: the force scale comes out negative, no error
    assert run_cli("fit", csv, "--mass", M, "--out", tmp_path / "m", "--quiet") == 0
    assert "force scale S = -1" in (tmp_path / "m" / "fit.txt").read_text()


def test_a_band_without_the_resonance_says_the_fit_extrapolates(tmp_path, capsys):
    """Table 4's beam at 2 %: fn = sqrt(K / M) / 2 pi = 39.37 Hz. Fitted over 50-60 Hz, where
    it has no resonance, exact data still give fn back, but a measured FRF's would not: the fit
    says fn lies outside the band. Over 35-45 Hz it says nothing of the kind."""
    f = np.round(np.arange(20.0, 80.0001, 0.1), 10)
    csv = tmp_path / "m.csv"
    write_frf_csv(csv, f, _accelerance(f), quantity="acceleration")
    assert run_cli("fit", csv, "--band", "50:60", "--out", tmp_path / "off") == 0
    said = capsys.readouterr().out
    fn = float(re.search(r"fn ([0-9.]+) Hz", said).group(1))
    assert abs(fn / FN - 1) < 1e-4
    assert f"the fitted natural frequency {fn:.6g} Hz lies outside the band 50-60 Hz" in said
    assert run_cli("fit", csv, "--band", "35:45", "--out", tmp_path / "on") == 0
    assert "lies outside the band" not in capsys.readouterr().out
