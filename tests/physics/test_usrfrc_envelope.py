"""The sine law's amplitude envelope (x3dpd.physics.usrfrc, ``amp1=A1,ramp=TR``): a sine
whose amplitude grows (or falls) linearly from A to A1 over TR seconds from T0 and then holds
A1 -- the report's Section 11.2 stall, 0.4 to 3.0 ips rms in about 5 s. Checked against the
closed form F = (A + (A1 - A) min((t - T0)/TR, 1)) sin(W (t - T0) + P), 0 before T0."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.errors import UsrfrcError
from x3dpd.physics.usrfrc import force_table, force_values

IDS = np.array([1, 9], dtype=np.int64)
T = np.linspace(-0.5, 8.0, 20001)


def values(spec):
    return force_values(T, force_table([spec], IDS))[:, 0]


@pytest.mark.parametrize("a0,a1,t0,phase", [(108.0, 810.0, 0.0, 0.0), (5.0, -1.0, 0.25, 30.0)])
def test_the_envelope_is_linear_over_the_ramp_and_then_holds(a0, a1, t0, phase):
    spec = f"sine:node=9,dof=2,amp={a0},hz=146,phase={phase},t0={t0},amp1={a1},ramp=5"
    tau = T - t0
    envelope = a0 + (a1 - a0) * np.clip(tau / 5.0, 0.0, 1.0)
    expected = np.where(
        tau >= 0, envelope * np.sin(2 * math.pi * 146 * tau + math.radians(phase)), 0
    )
    np.testing.assert_allclose(values(spec), expected, rtol=0, atol=1e-12 * max(abs(a0), abs(a1)))


def test_without_an_envelope_the_sine_is_as_before():
    plain = "sine:node=9,dof=2,amp=3.5,hz=37.21,phase=15"
    np.testing.assert_array_equal(values(plain), values(plain + ",amp1=3.5,ramp=2"))


@pytest.mark.parametrize(
    "extra,message",
    [
        (",amp1=2", "needs both amp1"),
        (",ramp=5", "needs both amp1"),
        (",amp1=2,ramp=0", "ramp"),
        (",amp1=2,ramp=-1", "ramp"),
    ],
)
def test_a_half_given_envelope_is_refused(extra, message):
    with pytest.raises(UsrfrcError, match=message):
        force_table([f"sine:node=9,dof=2,amp=1,hz=10{extra}"], IDS)
