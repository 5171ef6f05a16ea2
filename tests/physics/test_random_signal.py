"""Band-limited random excitation (``random:`` USRFRC law and ``--motion random:``) against its
definition: the multisine of docs/usrfrc.md summed here line by line, its PSD per third-octave band,
its RMS, the consistency of a base motion's u, u', u'', reproducibility and bad specs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.errors import UsrfrcError
from x3dpd.physics.motion import (
    motion_count,
    motion_history,
    motion_rows,
    motion_table,
    prescribed_mask,
)
from x3dpd.physics.usrfrc import force_table, force_values, law_count

IDS = np.array([1, 2, 7])
LO, HI, PERIOD, SEED = 10.0, 150.0, 4.0, 11


def multisine(t, lo, hi, period, seed, psd, integrate=0):
    """The documented signal: lines l / T in [LO, HI], phases 2 pi U_l (PCG64 U_l), amplitude
    sqrt(2 P / T); ``integrate`` = 2 gives its double integral (the motion's displacement),
    1 its single integral."""
    lines = np.arange(math.ceil(lo * period), math.floor(hi * period) + 1)
    lines = lines[lines >= 1]
    phases = 2 * np.pi * np.random.default_rng(seed).random(lines.size)
    w = 2 * np.pi * lines / period
    amp = math.sqrt(2 * psd / period)
    arg = np.outer(t, w) + phases
    if integrate == 0:
        return np.sin(arg) @ np.full(w.size, amp)
    if integrate == 1:
        return -np.cos(arg) @ (amp / w)
    return -np.sin(arg) @ (amp / w**2)


def periodogram_bands(signal, fs, lo, hi):
    """Per third-octave band inside [LO, HI]: (centre, band-mean one-sided PSD) of a record that
    holds whole periods (a rectangular window is then exact: every line falls on a bin)."""
    n = signal.size
    spec = np.fft.rfft(signal)
    psd = 2.0 * np.abs(spec) ** 2 / (n * fs)
    f = np.fft.rfftfreq(n, 1 / fs)
    out = []
    for k in range(-20, 10):
        centre = 1000.0 * 10 ** (k / 10)
        a, b = centre * 10**-0.05, centre * 10**0.05
        if a >= lo and b <= hi:
            out.append((centre, psd[(f >= a) & (f < b)].mean()))
    return out


def test_force_is_the_documented_multisine():
    spec = f"random:node=2,dof=1,psd=2e-4,band={LO}:{HI},seed={SEED},period={PERIOD}"
    t = np.linspace(0.0, 9.0, 7001)  # more than two periods: it repeats
    got = force_values(t, force_table([spec], IDS))[:, 0]
    want = multisine(t, LO, HI, PERIOD, SEED, 2e-4)
    # quintic Hermite between 8 knots per period of the highest line: 5e-6 of a line's
    # amplitude (module docstring); the lines' errors add up to ~1e-5 of the RMS
    assert np.max(np.abs(got - want)) < 1e-4 * want.std()


@pytest.mark.parametrize("level", ["psd=2e-4", "rms=0.25"])
def test_realised_psd_per_third_octave_and_rms(level):
    spec = f"random:node=1,dof=3,{level},band=20:400,seed=5,period=2"
    fs = 2000.0
    t = np.arange(int(2 * fs)) / fs  # exactly one period
    x = force_values(t, force_table([spec], IDS))[:, 0]
    lines = math.floor(400 * 2) - math.ceil(20 * 2) + 1
    psd = 2e-4 if level.startswith("psd") else 0.25**2 * 2 / lines
    bands = periodogram_bands(x, fs, 20.0, 400.0)
    assert len(bands) >= 10
    for centre, level_psd in bands:
        assert abs(level_psd / psd - 1) < 0.10, (centre, level_psd / psd)
        # every line has the same power over a period: only the interpolation (1e-5) and the
        # band edges' partial lines are left
        assert abs(level_psd / psd - 1) < 0.01, (centre, level_psd / psd)
    rms = math.sqrt(psd * lines / 2)
    assert abs(x.std() / rms - 1) < 1e-3


def test_motion_u_v_a_are_the_integrals_of_the_random_acceleration():
    spec = f"random:node=7,dof=2,psd=4.0,band={LO}:{HI},seed={SEED},period={PERIOD}"
    table = motion_table([spec], IDS)
    t = np.linspace(0.3, 5.0, 4001)
    u, v, a = (c[:, 0] for c in motion_history(t, table))
    for got, integrate in ((a, 0), (v, 1), (u, 2)):
        want = multisine(t, LO, HI, PERIOD, SEED, 4.0, integrate)
        # 8 knots per period of 150 Hz: u'' errs by at most 2e-4 of a line (the curvature of
        # the quintic), u and u' far less
        assert np.max(np.abs(got - want)) < 1e-3 * want.std(), integrate
    # u' and u'' are the quintic's own derivatives: central differences of u agree to their
    # truncation error, h^2/6 max|u'''| and h^2/12 max|u''''| (bounded by the sums of the
    # lines' amplitudes A w and A w^2; twice that for the quintic's own higher derivatives), plus
    # the second difference's rounding, 4 eps max|u| / h^2, under 1e-6 of the RMS here
    h = 1e-5
    lines = np.arange(math.ceil(LO * PERIOD), math.floor(HI * PERIOD) + 1)
    w = 2 * np.pi * lines / PERIOD
    amp = math.sqrt(2 * 4.0 / PERIOD)
    up, um = (motion_history(t + s, table)[0][:, 0] for s in (h, -h))
    np.testing.assert_allclose((up - um) / (2 * h), v, rtol=0, atol=2 * h**2 / 6 * np.sum(amp * w))
    np.testing.assert_allclose(
        (up - 2 * u + um) / h**2,
        a,
        rtol=0,
        atol=2 * h**2 / 12 * np.sum(amp * w**2) + 1e-6 * a.std(),
    )


def test_motion_rests_before_t0_and_ramps_in():
    base = "random:node=7,dof=1,rms=3,band=5:50,seed=1,t0=0.5"
    t = np.array([0.0, 0.25, 0.5])
    u, v, a = (c[:, 0] for c in motion_history(t, motion_table([base], IDS)))
    assert u[0] == u[1] == u[2] and v[0] == v[1] == 0.0 and a[0] == a[1] == 0.0
    u, v, _ = (c[:, 0] for c in motion_history(t, motion_table([base + ",ramp=0.2"], IDS)))
    assert u[0] == u[1] == u[2] == 0.0 and v[2] == 0.0


def test_same_seed_same_bytes_other_seed_other_signal():
    spec = "random:node=1,dof=1,rms=1,band=1:200,seed={}"
    a = force_table([spec.format(3)], IDS)
    b = force_table([spec.format(3)], IDS)
    c = force_table([spec.format(4)], IDS)
    assert a.tobytes() == b.tobytes()
    t = np.linspace(0, 1, 101)
    assert not np.array_equal(force_values(t, a), force_values(t, c))


def test_tables_keep_their_laws_apart_from_the_knots():
    specs = [
        "sine:node=1,dof=1,amp=2,hz=3",
        "random:node=2,dof=2,rms=1,band=1:20,seed=0",
        "constant:node=7,dof=3,amp=5",
    ]
    table = force_table(specs, IDS)
    assert law_count(table) == 3 and table.shape[0] > 3
    v = force_values([0.1, 0.2], table)
    assert v.shape == (2, 3)
    np.testing.assert_array_equal(v[:, 2], [5.0, 5.0])
    np.testing.assert_allclose(v[:, 0], 2 * np.sin(2 * np.pi * 3 * np.array([0.1, 0.2])))
    motions = motion_table(
        ["node=1,dof=1,amp=0.1,hz=5", "random:node=2,dof=3,rms=1,band=1:20,seed=0"], IDS
    )
    assert motion_count(motions) == 2 and motions.shape[0] > 2
    assert motion_rows(motions).shape == (2, 8)
    assert prescribed_mask(motions, 3).sum() == 2


@pytest.mark.parametrize(
    "spec, message",
    [
        ("random:node=1,dof=1,rms=1,band=1:20", "missing required key(s) seed"),
        ("random:node=1,dof=1,rms=1,psd=1,band=1:20,seed=1", "exactly one of rms="),
        ("random:node=1,dof=1,band=1:20,seed=1", "exactly one of rms="),
        ("random:node=1,dof=1,rms=1,band=20:10,seed=1", "band='20:10'"),
        ("random:node=1,dof=1,rms=1,band=20,seed=1", "expected LO:HI"),
        ("random:node=1,dof=1,rms=1,band=1:20,seed=-3", "seed='-3'"),
        ("random:node=1,dof=1,rms=-1,band=1:20,seed=1", "rms='-1'"),
        ("random:node=1,dof=1,rms=1,band=10.01:10.02,seed=1,period=1", "no line of the grid"),
        ("random:node=1,dof=1,rms=1,band=1:20000,seed=1,period=100", "knots"),
        ("random:node=3,dof=1,rms=1,band=1:20,seed=1", "node=3 is not defined"),
    ],
)
def test_bad_force_specs_are_named(spec, message):
    with pytest.raises(UsrfrcError) as err:
        force_table([spec], IDS)
    assert message in str(err.value) and spec in str(err.value)


@pytest.mark.parametrize(
    "spec, message",
    [
        ("random:node=1,dof=1,rms=1,band=0:20,seed=1", "0 < LO < HI"),
        ("random:node=1,dof=1,rms=1,band=1:20,seed=1,ramp=-1", "ramp='-1'"),
    ],
)
def test_bad_motion_specs_are_named(spec, message):
    with pytest.raises(UsrfrcError) as err:
        motion_table([spec], IDS)
    assert message in str(err.value)


def test_a_dof_driven_twice_is_refused():
    with pytest.raises(UsrfrcError, match="already driven"):
        motion_table(["node=1,dof=1,amp=1,hz=2", "random:node=1,dof=1,rms=1,band=1:9,seed=1"], IDS)
