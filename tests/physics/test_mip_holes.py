"""A multiple individual particle (MIP) damper's holes (PLATES card, HOLES walls) on a plate
moved on a prescribed sine: each hole's sphere is a single-particle impact damper.

Closed form (the symmetric motion with two impacts per cycle of an impact damper on a base of
infinite mass; Masri & Caughey, J. Appl. Mech. 33 (1966) 586, with the primary mass taken to
infinity). The plate moves as y_c = A sin(w t); the sphere flies freely (no gravity) between
the hole's ends, a free length d apart, and an impact reverses its speed relative to the plate
with restitution e (HOOKE's law: e exactly, for any impact speed). With the sphere's speed u
between impacts and the phase phi = w t1 of an impact on the top end:

* the flight over half a period:  u pi / w = 2 A sin(phi) + d,
* the impact law:                 A w cos(phi) = -u (1 - e) / (1 + e),

so that, with r = (1 - e)/(1 + e), (r u / (A w))^2 + ((pi u / w - d) / (2 A))^2 = 1: a quadratic
in u whose positive root is the motion. It is stable for free lengths of about 3 to 6 A at
e = 0.6 (an exact event-driven model of the impacts, started as these spheres are -- at rest
on the hole's bottom when the plate starts moving up -- settles on it within 12 cycles at
d = 3.5 A and 5 A; at 2.5 A and below it does not), so the test's plates have 3.5 A and 5 A.
The model's impacts last pi / omega_d = 24 us (HOOKE) against a 25 ms period, during which the
plate keeps moving: the speed and the phase agree to within 1 % and 1 degree.
"""

from __future__ import annotations

import math
import numpy as np
import pytest

import x3dpd
from x3dpd.deck import parse_deck

A, HZ, E = 0.01, 40.0, 0.6  # plate amplitude [in], drive [Hz], restitution
RADIUS, HOLE, PITCH = 0.125, 0.26, 0.4  # [in]
MASS = 7.32971e-4 * 4.0 / 3.0 * math.pi * RADIUS**3  # the sphere [lbf s^2/in]
KN = 1.0e5  # HOOKE stiffness [lbf/in]: an impact lasts pi sqrt(m / k) = 24 us
DT = 5.0e-7
FREE = (0.035, 0.05)  # the two plates' free lengths [in]: 3.5 and 5 x A


def deck_text(free=FREE, holes=4, lumped=False, start="bottom") -> str:
    """A plate of ``holes`` holes per free length in ``free``, its master node 1 moved by the
    test (``--motion``), no gravity."""
    plates = "\n".join(
        f"  set={k + 1} master=1 holes={holes} pitch={PITCH} hole={HOLE} "
        f"thickness={2 * RADIUS + d!r} size=2 end=0.05 axis=y start={start}"
        + (" lumped=yes" if lumped else "")
        for k, d in enumerate(free)
    )
    return f"""$ test: holes on a plate moved on a sine
PARAMETERS
   0.0 1.0 0.0 {DT} {DT} 0 1e9 0 5 0 1000
END
PDMP
   1 {RADIUS} 7.32971e-4 0.3 3.0e7 0.0 1.0 0.0 0.0 0.0 0.0
END
HOOKE
   1 {KN} {E}
END
NODE COORDINATES
   1 0.0 0.0 0.0
END
MASS
   1 1.0 1e20 1e20 1e20
END
BOUNDARY CONDITIONS
   1 1 1 1 3 4 5 6
END
PLATES
{plates}
END
"""


def closed_form(d: float) -> tuple[float, float]:
    """(u, phi) of the symmetric two-impact motion (module docstring), the larger root."""
    w = 2.0 * math.pi * HZ
    r = (1.0 - E) / (1.0 + E)
    a1, a2, u0 = (r / (A * w)) ** 2, (math.pi / (2.0 * A * w)) ** 2, d * w / math.pi
    u = (a2 * u0 + math.sqrt((a2 * u0) ** 2 - (a1 + a2) * (a2 * u0**2 - 1.0))) / (a1 + a2)
    phi = math.atan2((math.pi * u / w - d) / (2.0 * A), -r * u / (A * w))
    return u, phi % (2.0 * math.pi)


def run(text: str, cycles: float, nodes):
    deck = parse_deck(text)
    return x3dpd.run(
        deck,
        tmax=cycles / HZ,
        dt=DT,
        itrac=10,
        trace_nodes=tuple(nodes),
        motion=(f"node=1,dof=2,amp={A},hz={HZ}",),
    )


def measured(t, v) -> tuple[float, float]:
    """(u, phi) of a sphere's y velocity history over whole cycles: the flight speed (the
    median |v| away from impacts) and the drive phase of its top impacts (where v turns from
    + to -), averaged on the circle."""
    u = float(np.median(np.abs(v)))
    turns = np.flatnonzero((v[:-1] > 0.5 * u) & (v[1:] < 0.5 * u))
    phases = (2.0 * math.pi * HZ * t[turns]) % (2.0 * math.pi)
    return u, float(np.angle(np.mean(np.exp(1j * phases))) % (2.0 * math.pi))


@pytest.fixture(scope="module")
def settled():
    """Two plates (free lengths FREE) of four holes, spheres at rest on the holes' bottoms,
    40 cycles: the trace of the first three spheres of the first plate, two of the second."""
    deck = parse_deck(deck_text())
    first = deck.pdmp[0].nodlim + 1
    nodes = [first, first + 1, first + 2, first + 4, first + 5]
    return run(deck_text(), 40, nodes), nodes


def test_each_hole_is_masri_and_caugheys_impact_damper(settled):
    res, _ = settled
    t = res.trace.time
    last = t >= t[-1] - 15.0 / HZ  # the last 15 cycles
    for k, d in ((0, FREE[0]), (3, FREE[1])):
        v = res.trace.velocity[last, k, 1]
        u, phi = measured(t[last], v)
        u_cf, phi_cf = closed_form(d)
        assert u == pytest.approx(u_cf, rel=0.01), (d, u, u_cf)
        assert abs((phi - phi_cf + math.pi) % (2 * math.pi) - math.pi) < math.radians(1.0)


def test_alike_holes_move_alike_and_other_free_lengths_do_not(settled):
    res, _ = settled
    y = res.trace.position[:, :, 1]
    # the holes of one plate: the same axial history, to the last bit
    assert np.array_equal(y[:, 0] - y[0, 0], y[:, 1] - y[0, 1])
    assert np.array_equal(y[:, 0] - y[0, 0], y[:, 2] - y[0, 2])
    assert np.array_equal(y[:, 3] - y[0, 3], y[:, 4] - y[0, 4])
    # another free length: another motion (speeds apart by more than 10 %)
    v = res.trace.velocity[:, :, 1]
    late = res.trace.time >= res.trace.time[-1] - 15.0 / HZ
    u0, u1 = np.median(np.abs(v[late, 0])), np.median(np.abs(v[late, 3]))
    assert abs(u1 - u0) > 0.1 * u0


def test_a_lumped_plate_moves_as_its_holes(settled):
    """``lumped=yes``: one sphere of four spheres' mass and stiffness per plate: the same
    trajectory as each of the four, and the same energy ledger (to rounding)."""
    res, nodes = settled
    lumped = parse_deck(deck_text(lumped=True))
    first = lumped.pdmp[0].nodlim + 1
    one = run(deck_text(lumped=True), 40, (first, first + 1))
    y_full = res.trace.position[:, [0, 3], 1]
    y_one = one.trace.position[:, :, 1]
    assert np.allclose(y_one - y_one[0], y_full - y_full[0], rtol=0, atol=1e-9)
    e_full, e_one = res.energy, one.energy
    scale = float(np.max(np.abs(e_full["external_work"])))
    for col in ("kinetic_translation", "dissipated_viscoelastic", "external_work"):
        assert np.allclose(e_one[col], e_full[col], rtol=0, atol=1e-9 * scale)
