"""Hertz-Mindlin tangential contact (x3dpd.physics.mindlin) and the tangential-law seam.

A steel sphere hits a rigid floor obliquely at 10 in/s, at the report's step (5e-7 s, decks/
beam_*.inp), and the rebound is compared with closed forms computed here:

* gross sliding (large angles): the contact point's tangential velocity changes by the
  rigid-body impulse, v_t' = v_t - mu (1 + e) (1 + m R^2/I) v_n, for every tangential law;
* no energy is created by the Mindlin spring at any angle (mindlin_rescale/force): the
  tangential and rotational energy after the impact is not above the tangential energy
  before. (The normal rebound is the Hertz law's, whose velocity Verlet integration at 23
  steps per contact returns e = 1.0004 head-on at this step: a normal-law property, the
  same under every tangential law, measured separately.)
* at intermediate angles the contact point's tangential velocity reverses, as Maw, Barber &
  Fawcett (1976) found and Coulomb friction cannot reproduce; the rebound matches a slow,
  obviously correct reference: the same Mindlin rules on a sphere whose normal motion is the
  Hertz ODE, integrated with a step 100 times finer. The step loop converges to it at first
  order (the stick-slip switches): slip out/in at 10 deg 0.533, 0.469, 0.452 at dt = 5e-7,
  1.25e-7, 3.125e-8 s, reference 0.447 -- at the report's step the tangential spring
  (period ~ 0.6 of the contact) is under-resolved, and x3dpd check says so;
* a restart in the middle of the contact continues bit for bit (the history is in the dump).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest


from contact_reference import hertz_mindlin_impact
from factories import (
    BOX_FRICTION_LOOP,
    BOX_LOOP,
    HOOKE_PLANE_LOOP,
    STEEL_E,
    STEEL_NU,
    STEEL_R,
    floor_deck,
    pair_deck,
    sphere_mass,
)

import x3dpd

DT = 5e-7  # the report's step (decks/beam_64.inp DTMAX)
V = 10.0  # impact speed [in/s]
MU = 0.3
M = sphere_mass()
INERTIA = 0.4 * M * STEEL_R**2
#: 1 + m R^2 / I of a solid sphere
SPIN = 1.0 + M * STEEL_R**2 / INERTIA


#: A HOOKE stiffness for the damped impacts [lbf/in]: a 27 us contact, 54 steps at DT.
KN = 1.0e4
#: floor_deck's sphere and its spectator, and pair_deck's far floor: the box scenes' loops by
#: law (BOX_LOOP when mu = 0); on HOOKE without the spectator, the Chung & Ooi decks' loop
pytestmark = pytest.mark.rides(BOX_LOOP, *BOX_FRICTION_LOOP.values(), HOOKE_PLANE_LOOP["mindlin"])


def _impact(law, degrees, *, mu=MU, t_end=8e-5, dt=DT, hooke_e=None, **kw):
    """Rebound of the sphere (node 5) from the floor: (v_n in, v_t in, contact-point slip
    out, normal speed out, kinetic energy in, kinetic energy out). ``hooke_e``: the HOOKE law
    (k_n = KN) with that restitution instead of Hertz."""
    vn = V * math.cos(math.radians(degrees))
    vt = V * math.sin(math.radians(degrees))
    # on HOOKE without the spectator: the loop of the Chung & Ooi decks (one sphere, a plane)
    deck = floor_deck(dt=dt, velocity=(vt, -vn, 0.0), mu=mu, spectator=hooke_e is None)
    if hooke_e is not None:
        from x3dpd.deck.cards import Hooke

        deck = dataclasses.replace(deck, hooke=(Hooke(deck.pdmp[0].nodlim, KN, hooke_e),))
    res = x3dpd.run(deck, tmax=t_end, friction=law, **kw)
    v = res.trace.velocity[-1, 0]
    w = res.trace.spin[-1, 0]
    slip = v[0] + w[2] * STEEL_R  # contact point at -R y: v_x + w_z R
    # the tangential and rotational kinetic energy before and after
    ke_in = 0.5 * M * vt * vt
    ke_out = 0.5 * M * (v[0] ** 2 + v[2] ** 2) + 0.5 * INERTIA * float(w @ w)
    return vn, vt, slip, v[1], ke_in, ke_out, res


@pytest.mark.parametrize("law", ["coulomb", "regularized", "mindlin"])
def test_gross_sliding_matches_the_rigid_body_impulse(law):
    """80 deg: the contact slides throughout (v_t/v_n = 5.7 > mu (1 + e) (1 + mR^2/I) = 2.1),
    so the tangential impulse is mu times the normal one, (1 + e) m v_n, whatever the law."""
    vn, vt, slip, vn_out, *_ = _impact(law, 80.0)
    e = vn_out / vn
    expected = vt - MU * (1.0 + e) * SPIN * vn
    print(f"\n{law}: e = {e:.7f}, slip out {slip:.9f} in/s, closed form {expected:.9f}")
    assert e == pytest.approx(1.0, abs=1e-4)
    assert slip == pytest.approx(expected, rel=1e-3)


def _mindlin_reference(degrees, mu=MU, steps_per_dt=100):
    """The same Mindlin rules (x3dpd.physics.mindlin's docstring: force history, rescaled on
    unloading, Coulomb limit) on the rigid-body equations of a sphere on a rigid floor, with
    the Hertz normal force, by symplectic Euler at DT/100 (tests/contact_reference.py): the
    contact point's slip and the normal speed after the impact."""
    slip, vn_out, _ = hertz_mindlin_impact(
        M,
        STEEL_R,
        STEEL_E,
        STEEL_NU,
        mu,
        V * math.cos(math.radians(degrees)),
        V * math.sin(math.radians(degrees)),
        DT / steps_per_dt,
    )
    return slip, vn_out


def test_the_contact_point_reverses_at_intermediate_angles():
    """45 deg (normalised angle 2(1-nu)/(2-nu) tan(theta)/mu = 2.7): the Mindlin spring throws
    the contact point back (Maw et al.'s recoil); the slow reference gives the same slip within
    1 % of v_t at a step 16 times finer than the report's. Coulomb friction can at most stop
    the slip: rolling, slip >= 0."""
    vn, vt, slip, vn_out, *_ = _impact("mindlin", 45.0, dt=DT / 16)
    ref_slip, ref_vn = _mindlin_reference(45.0)
    print(f"\nmindlin 45 deg: slip out / in {slip / vt:.5f}, reference {ref_slip / vt:.5f}")
    assert ref_slip < -0.3 * vt  # the reference itself recoils (-0.36 v_t)
    assert slip == pytest.approx(ref_slip, abs=1e-2 * vt)
    assert vn_out == pytest.approx(ref_vn, rel=1e-3)
    _, _, coulomb_slip, *_ = _impact("regularized", 45.0)
    assert coulomb_slip > -1e-6 * vt


@pytest.mark.parametrize("degrees", [10.0, 45.0])
def test_small_and_large_slip_against_the_reference(degrees):
    """Partial slip at 10 deg (sticks, slides at the end) and the recoil at 45: the step
    loop's Mindlin spring against the reference, within 1 % of v_t at DT/16."""
    vn, vt, slip, *_ = _impact("mindlin", degrees, dt=DT / 16)
    ref_slip, _ = _mindlin_reference(degrees)
    assert slip == pytest.approx(ref_slip, abs=1e-2 * vt)


def test_an_elastic_mindlin_impact_never_creates_energy():
    """Every 10 deg from 10 to 80 and at 89, with friction (sliding) and with mu = 10 (sticking
    throughout), at the report's step: the tangential and rotational kinetic energy after the
    impact is not above the tangential energy before, to 1e-6 of the impact's energy. (A
    displacement-history spring, U = k_t xi^2/2 with k_t growing while the contact loads,
    creates energy; the force history with the unloading rescale cannot.)"""
    worst = -math.inf
    for mu in (MU, 10.0):
        for degrees in [*range(10, 90, 10), 89]:
            *_, ke_in, ke_out, _ = _impact("mindlin", float(degrees), mu=mu, t_end=6e-5)
            worst = max(worst, (ke_out - ke_in) / (0.5 * M * V * V))
            assert ke_out <= ke_in + 1e-6 * 0.5 * M * V * V, (mu, degrees)
    print(f"\nlargest change of the tangential energy {worst:.2e} of the impact's")


def test_a_damped_mindlin_impact_never_creates_energy():
    """Under the HOOKE law (e 0.5) the spring has its dashpot c_t = c_n sqrt(k_t/k_n)
    (x3dpd.physics.hooke.tangential_damping): at every 10 deg from 10 to 80 and at 89, sliding
    (mu 0.3) and sticking (mu 10), the tangential and rotational energy after the impact is not
    above the tangential energy before (to 1e-6 of the impact's energy), and sticking, the
    dashpot dissipates: the tangential motion keeps less than with the undamped spring
    (e = 1)."""
    total = 0.5 * M * V * V
    for mu in (MU, 10.0):
        for degrees in [*range(10, 90, 10), 89]:
            *_, ke_in, ke_out, _ = _impact("mindlin", float(degrees), mu=mu, hooke_e=0.5)
            assert ke_out <= ke_in + 1e-6 * total, (mu, degrees)
    *_, ke_in, damped, _ = _impact("mindlin", 10.0, mu=10.0, hooke_e=0.5)
    *_, ke_in, undamped, _ = _impact("mindlin", 10.0, mu=10.0, hooke_e=1.0)
    print(
        f"\nsticking at 10 deg: tangential energy kept {damped / ke_in:.4f} damped, "
        f"{undamped / ke_in:.4f} undamped"
    )
    assert damped < undamped - 0.05 * ke_in  # measured 0.716 against 0.796 of ke_in


def test_the_ledger_closes_and_books_the_spring():
    """A sticking-then-sliding impact (10 deg) at DT/16: the ledger's residual is the
    frictionless impact's (the Hertz integration's) to 1e-6 of the energy at every row -- the
    spring's energy counted as stored while the contact lasts, its losses as friction -- and
    friction dissipates what the tangential motion lost."""
    dt = DT / 16
    vn, vt, slip, vn_out, ke_in, ke_out, res = _impact("mindlin", 10.0, dt=dt, t_end=3e-5)
    *_, bare = _impact("mindlin", 10.0, mu=0.0, dt=dt, t_end=3e-5)
    e = res.energy
    total = 0.5 * M * V * V
    assert np.abs(e["residual"] - bare.energy["residual"]).max() < 1e-6 * total
    assert e["dissipated_friction"][-1] == pytest.approx(ke_in - ke_out, rel=1e-3)
    assert e["dissipated_friction"].min() > -1e-12 * total


@pytest.mark.parametrize("law", ["coulomb", "regularized", "mindlin"])
def test_the_last_step_slip_work_is_booked(law):
    """At the report's step, under every tangential law, the ledger's residual after an oblique
    impact (10 deg: sticks then slides; 45 deg) is the frictionless impact's (the Hertz
    integration's: the floor's normal does not turn, so friction leaves the normal motion
    alone) to 1e-9 of the impact's energy, and the pair impact's within 1e-5: the friction
    force's work on the step a contact ends on, -1/2 F_t,old . v_t dt, is booked (it was not:
    1.8e-4 of the energy at this step). A pair's normal turns with the tangential motion, so
    its frictionless twin's trajectory, and Hertz integration error, differ (measured 1.0e-6
    under coulomb)."""
    total = 0.5 * M * V * V
    for degrees in (10.0, 45.0):
        *_, res = _impact(law, degrees, t_end=6e-5)
        *_, bare = _impact(law, degrees, mu=0.0, t_end=6e-5)
        gap = res.energy["residual"][-1] - bare.energy["residual"][-1]
        print(f"\n{law} {degrees} deg: residual - frictionless {gap / total:.2e}")
        assert abs(gap) < 1e-9 * total
    positions = [(0.0, 0.0, 0.0), (1.7321 * STEEL_R, STEEL_R, 0.0)]
    velocities = [(V, 0.0, 0.0), (0.0, 0.0, 0.0)]
    res, bare = (
        x3dpd.run(
            pair_deck(positions, velocities, dt=DT, mu=mu, far_floor=True),
            tmax=6e-5,
            friction=law,
        )
        for mu in (MU, 0.0)
    )
    gap = res.energy["residual"][-1] - bare.energy["residual"][-1]
    print(f"{law} pair: residual - frictionless {gap / total:.2e}")
    assert abs(gap) < 1e-5 * total


def test_a_restart_in_the_middle_of_the_contact_is_bit_identical(tmp_path):
    """Straight through, and stopped 10 steps into the contact then restarted: the same
    trace bytes (the spring's force, stiffness and sliding flag are in the dump)."""
    deck = floor_deck(dt=DT, velocity=(V * math.sin(0.5), -V * math.cos(0.5), 0.0), mu=MU)
    whole, part = tmp_path / "whole.trace.txt", tmp_path / "part.trace.txt"
    x3dpd.run(deck, tmax=4e-5, friction="mindlin", trace=whole)
    x3dpd.run(deck, tmax=10 * DT, friction="mindlin", trace=part)
    x3dpd.run(deck, tmax=4e-5, friction="mindlin", trace=part, restart=True)
    assert whole.read_bytes() == part.read_bytes()


def test_a_pair_impact_never_creates_energy():
    """Two spheres, oblique (30 deg: centres R apart across the line of flight), Mindlin between
    them: the kinetic energy after is not above the energy before (1e-6), and some of it went
    into friction."""
    deck = pair_deck(
        [(0.0, 0.0, 0.0), (1.7321 * STEEL_R, STEEL_R, 0.0)],
        [(V, 0.0, 0.0), (0.0, 0.0, 0.0)],
        dt=DT,
        mu=MU,
        far_floor=True,
    )
    res = x3dpd.run(deck, tmax=6e-5, friction="mindlin")
    v, w = res.trace.velocity[-1], res.trace.spin[-1]
    ke_out = 0.5 * M * float((v * v).sum()) + 0.5 * INERTIA * float((w * w).sum())
    ke_in = 0.5 * M * V * V
    assert ke_out <= ke_in * (1.0 + 1e-6)
    assert res.energy["dissipated_friction"][-1] > 1e-6 * ke_in


def test_every_registered_tangential_and_rolling_law_provides_the_loop_api():
    from x3dpd.physics.rolling import ROLLING_LAWS
    from x3dpd.physics.tangential_laws import TANGENTIAL_LAW_API, TANGENTIAL_LAWS

    for name, law in TANGENTIAL_LAWS.items():
        missing = [a for a in (law.force, *TANGENTIAL_LAW_API) if not hasattr(law.module, a)]
        assert not missing, f"{name}: {missing}"
    for _name, module in ROLLING_LAWS.items():
        assert module is None or all(hasattr(module, a) for a in ("rolling_torque", "N_HISTORY"))
