"""LAMMPS's ``tangential linear_history`` (x3dpd.physics.linear_history), added as a module plus
its registration line (docs/engine.md, "Adding a tangential law").

Closed forms computed here: a steel sphere (R 0.0625 in) resting on a floor under gravity on
the HOOKE law sticks, and its contact point oscillates as a damped oscillator of the spring
k_t = 2(1-nu)/(2-nu) k_n and dashpot c_t = 2 zeta sqrt(m k_t) on the tangential mass m_t = 2m/7;
an oblique impact at a large angle slides throughout: the rigid-body impulse (under a damped
HOOKE law, mu int |F_N| dt). Against a slow reference: LAMMPS's sliding rule (the spring keeps
the limited force minus the dashpot's) in x3dpd's energy-consistent form (step 5 of
x3dpd.physics.linear_history) on Chung & Ooi's test 6 at partial slip. Damped gross sliding,
where LAMMPS's reset creates energy: no oblique impact gains any, and test 6 runs.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import pathlib

import numpy as np
import pytest

from contact_reference import hooke_oblique_beta
from factories import (
    BOX_FRICTION_LOOP,
    HOOKE_PLANE_LOOP,
    STEEL_NU,
    STEEL_R,
    floor_deck,
    sphere_mass,
)
from processes import x3dpd as run_process

import x3dpd
from x3dpd.deck.cards import Body, Hooke

ROOT = pathlib.Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("chung_ooi", ROOT / "tools" / "chung_ooi.py")
co = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(co)

M = sphere_mass()
INERTIA = 0.4 * M * STEEL_R**2
KN = 1.0e4  # HOOKE k_n [lbf/in]
G = 386.1  # [in/s^2]
LAW = "linear_history"
#: HOOKE floors without the spectator ride the Chung & Ooi decks' loops; the Hertz floor with
#: it (the gross-sliding impulse) the box scenes' loop of this law
pytestmark = pytest.mark.rides(*HOOKE_PLANE_LOOP.values(), BOX_FRICTION_LOOP[LAW])


def _hooke(deck, e):
    # HOOKE floor scenes are built without floor_deck's spectator: they then compile the loop
    # of the shipped Chung & Ooi decks (one sphere, a plane), not one of their own
    return dataclasses.replace(deck, hooke=(Hooke(deck.pdmp[0].nodlim, KN, e),))


def _rocking(law, e, steps_per_period, degrees=10.0):
    """A sphere at rest on the HOOKE floor (static approach m g cos(theta) / k_n) under gravity
    tilted by ``degrees`` along x: it rolls off without sliding (the spring's largest force,
    2 m_t g sin(theta), is 0.34 of mu m g cos(theta) at 10 deg), and its contact point, whose
    acceleration is g sin(theta) + F/m_t (1/m_t = 1/m + R^2/I), slips at
    (g sin(theta)/w) e^(-alpha t) sin(w t), alpha = c_t / (2 m_t), w^2 = k_t/m_t - alpha^2.
    Returns the largest difference over two periods, relative to g sin(theta)/w."""
    le = math.log(e)
    zeta = -le / math.sqrt(math.pi**2 + le * le)
    kt = 2.0 * (1.0 - STEEL_NU) / (2.0 - STEEL_NU) * KN
    ct = 2.0 * zeta * math.sqrt(M * kt)
    m_t = 2.0 * M / 7.0
    alpha = ct / (2.0 * m_t)
    w = math.sqrt(kt / m_t - alpha * alpha)
    period = 2.0 * math.pi / math.sqrt(kt / m_t)
    gx, gy = G * math.sin(math.radians(degrees)), G * math.cos(math.radians(degrees))
    deck = floor_deck(
        dt=period / steps_per_period,
        height=STEEL_R - M * gy / KN,
        velocity=(0.0, 0.0, 0.0),
        gravity=G,
        mu=0.3,
        spectator=False,
    )
    deck = dataclasses.replace(_hooke(deck, e), body=Body(gx, -gy, 0.0))
    res = x3dpd.run(deck, tmax=2.0 * period, friction=law)
    t = res.trace.time
    slip = res.trace.velocity[:, 0, 0] + res.trace.spin[:, 0, 2] * STEEL_R
    expected = gx / w * np.exp(-alpha * t) * np.sin(w * t)
    return float(np.abs(slip - expected).max() / (gx / w))


@pytest.mark.parametrize("law", [LAW, "mindlin"])
def test_a_sphere_rolling_off_rocks_on_the_tangential_spring(law):
    """Both spring laws are this oscillator while the contact sticks. Undamped (e 1) at 100
    steps per period: to 3e-3 (Verlet's phase error (w dt)^2/24 per radian is 2.1e-3 after
    4 pi; measured 2.1e-3). Damped (e 0.5): the dashpot acts on the half-step velocity, as the
    normal one does, which makes the damped oscillator first order in dt: to 2e-3 at 2000
    steps per period (measured 4.8e-4)."""
    undamped = _rocking(law, 1.0, 100)
    damped = _rocking(law, 0.5, 2000)
    print(f"\n{law}: largest slip error {undamped:.2e} (e 1), {damped:.2e} (e 0.5)")
    assert undamped < 3e-3
    assert damped < 2e-3


def test_gross_sliding_matches_the_rigid_body_impulse():
    """80 deg on Hertz, mu 0.3: the contact slides throughout, v_t' = v_t - mu (1 + e)
    (1 + m R^2/I) v_n to 1e-3 (as every tangential law: tests/physics/test_mindlin.py)."""
    vn, vt = 10.0 * math.cos(math.radians(80.0)), 10.0 * math.sin(math.radians(80.0))
    res = x3dpd.run(floor_deck(dt=5e-7, velocity=(vt, -vn, 0.0), mu=0.3), tmax=8e-5, friction=LAW)
    v, w = res.trace.velocity[-1, 0], res.trace.spin[-1, 0]
    e = v[1] / vn
    expected = vt - 0.3 * (1.0 + e) * (1.0 + M * STEEL_R**2 / INERTIA) * vn
    assert v[0] + w[2] * STEEL_R == pytest.approx(expected, rel=1e-3)


def hooke_sliding_impulse(e: float) -> float:
    """int |F_N| dt / (m v_n) of a HOOKE impact of restitution ``e`` (k_n a + c_n da/dt,
    unclamped): the approach a = v_n/w_d exp(-alpha t) sin(w_d t) ends at t = pi/w_d with
    da/dt = -e v_n, e = exp(-beta pi), beta = alpha/w_d; F_N = -m a'' turns negative (the
    dashpot pulls) where da/dt is smallest, w_d t_1 = pi - 2 atan(beta), da/dt = -e v_n
    exp(2 beta atan(beta)). So int |F_N| = m (v_n - 2 min da/dt + da/dt(end)) =
    m v_n (1 + e (2 exp(2 beta atan beta) - 1)); (1 + e) for e = 1 or a clamped law."""
    beta = -math.log(e) / math.pi
    return 1.0 + e * (2.0 * math.exp(2.0 * beta * math.atan(beta)) - 1.0)


@pytest.mark.parametrize("law", [LAW, "mindlin", "coulomb"])
def test_damped_gross_sliding_matches_the_rigid_body_impulse(law):
    """80 deg on HOOKE e 0.5, mu 0.3: sliding throughout, the tangential impulse is mu
    int |F_N| dt (Coulomb's limit acts on |F_N|, and the unclamped dashpot pulls at the end:
    hooke_sliding_impulse, 1.6006 m v_n against (1 + e) m v_n = 1.5), so
    v_t' = v_t - mu (1 + m R^2/I) v_n (1 + e (2 exp(2 beta atan beta) - 1)), to 1e-3 at 870
    steps per contact (the damped normal motion is first order in dt: 2.7e-3 at the report's
    54). Linear_history's dashpot slip c_t v_t is 7 mu F_N at the onset (the reset's stored
    energy stopped this run with exit 3); every law gives the same rebound."""
    e = 0.5
    vn, vt = 10.0 * math.cos(math.radians(80.0)), 10.0 * math.sin(math.radians(80.0))
    res = x3dpd.run(
        _hooke(floor_deck(dt=5e-7 / 16, velocity=(vt, -vn, 0.0), mu=0.3, spectator=False), e),
        tmax=6e-5,
        friction=law,
    )
    v, w = res.trace.velocity[-1, 0], res.trace.spin[-1, 0]
    expected = vt - 0.3 * (1.0 + M * STEEL_R**2 / INERTIA) * vn * hooke_sliding_impulse(e)
    slip = v[0] + w[2] * STEEL_R
    print(f"\n{law}: slip out {slip:.6f}, closed form {expected:.6f}")
    assert slip == pytest.approx(expected, rel=1e-3)


def _lammps_reference(chi: float, steps: int) -> float:
    """beta of Chung & Ooi's test 6 (aluminium alloy sphere spinning onto the plane, HOOKE e
    0.5) under LAMMPS's linear_history rules, integrated slowly on the relative normal motion
    and the contact point's slip (tests/contact_reference.py: sliding, the spring keeps the
    limited force minus the dashpot's, within the limit and the step's slip work: x3dpd's
    energy-consistent form of LAMMPS's reset)."""
    cfg = co.TESTS[6]
    r, e, mu, vn = cfg["radius"], cfg["e"], cfg["mu"], cfg["speed"]
    m = co.sphere_mass("aluminium alloy", r)
    return hooke_oblique_beta(
        co.hooke_stiffness("aluminium alloy", r, vn),
        e,
        co.MATERIALS["aluminium alloy"][1],
        m,
        3.5 / m,
        mu,
        vn,
        3.5 * mu * (1.0 + e) * vn / chi,
        steps,
        dashpot_rests=False,
    )


def test_sliding_keeps_the_dashpot_as_lammps_does(tmp_path):
    """Chung & Ooi test 6 at chi = 4.5 (sticks, slides at the ends): beta of the step loop at
    20000 steps per contact is the slow reference's at 320000 (converged to 1e-3) within 0.01;
    the sliding rule matters: mindlin's (the dashpot rests while sliding) gives another beta
    (-0.027 against linear_history's +0.018; LAMMPS's reset unbounded gives +0.029, the
    difference made where the force passes zero near the end: docs/physics.md)."""
    chi = co.T8_CHI[12]
    cfg = co.TESTS[6]
    slip = 3.5 * cfg["mu"] * (1.0 + cfg["e"]) * cfg["speed"] / chi
    out = co.oblique_wall(
        6,
        "aluminium alloy",
        cfg["speed"],
        0.0,
        -slip / cfg["radius"],
        tmp_path,
        20000,
        friction=LAW,
    )
    beta = -out["slip_out"] / out["slip_in"]
    ref = _lammps_reference(chi, 320000)
    print(f"\nchi {chi}: beta {beta:+.4f}, reference {ref:+.4f}")
    assert beta == pytest.approx(ref, abs=0.01)
    assert abs(beta - co.test6_point("aluminium alloy", chi, tmp_path, 20000)) > 0.03


@pytest.mark.parametrize("e", [1.0, 0.5])
def test_an_oblique_hooke_impact_never_creates_energy(e):
    """Under HOOKE without damping (e 1: k_t constant, no dashpot) and with it (e 0.5: the
    dashpot c_t = c_n sqrt(k_t/k_n)) at 10 ... 80 deg and 89, sliding (mu 0.3) and sticking
    (mu 10): the tangential and rotational energy after the impact is not above the tangential
    energy before (to 1e-6 of the impact's energy), the ledger's friction dissipation is never
    negative (1e-12 of it, round-off) and its residual stays at round-off (1e-12). Damped,
    LAMMPS's reset stored up to 1/2 (c_t v_t - mu F_N)^2 / k_t and the audit stopped the
    sliding impacts at their first step (exit 3)."""
    total = 0.5 * M * 100.0
    for mu in (0.3, 10.0):
        for degrees in [*range(10, 90, 10), 89]:
            vn = 10.0 * math.cos(math.radians(degrees))
            vt = 10.0 * math.sin(math.radians(degrees))
            deck = _hooke(floor_deck(dt=5e-7, velocity=(vt, -vn, 0.0), mu=mu, spectator=False), e)
            res = x3dpd.run(deck, tmax=6e-5, friction=LAW)
            v, w = res.trace.velocity[-1, 0], res.trace.spin[-1, 0]
            ke_out = 0.5 * M * (v[0] ** 2 + v[2] ** 2) + 0.5 * INERTIA * float(w @ w)
            assert ke_out <= 0.5 * M * vt * vt + 1e-6 * total, (mu, degrees)
            assert res.energy["dissipated_friction"].min() >= -1e-12 * total, (mu, degrees)
            assert np.abs(res.energy["residual"]).max() <= 1e-12 * total, (mu, degrees)


def test_chung_ooi_test6_in_gross_sliding_runs_to_its_end(tmp_path):
    """The test-6 deck (aluminium alloy, HOOKE e 0.5, spinning onto the plane at chi = 0.187:
    slides throughout, c_t v_t = 6.3 mu F_N at the peak force) through the CLI: exit 0 (it was
    exit 3 at 3.6 us, "energy was created": friction -1.79 J of 4.66 J), the ledger's residual
    at round-off (1e-12 of the energy) and its friction dissipation never negative (1e-12);
    in gross sliding the force is mu |F_N| against the slip, so the trace is the Coulomb law's,
    value for value."""
    deck = ROOT / "decks" / "benchmarks" / "chung_ooi" / "test6_aluminium_alloy.inp"
    proc = run_process(deck, "--friction", LAW, "--trace", "t6.trace.txt", "-q", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    energy = x3dpd.read_energy(tmp_path / "t6.energy.csv")
    e0 = energy["total_energy"][0]
    print(
        f"\nresidual {np.abs(energy['residual']).max() / e0:.1e}, friction dissipated "
        f"{energy['dissipated_friction'][-1]:.4f} J of {e0:.4f} J"
    )
    assert np.abs(energy["residual"]).max() <= 1e-12 * e0
    assert energy["dissipated_friction"].min() >= -1e-12 * e0
    x3dpd.run(x3dpd.load_deck(deck), friction="coulomb", trace=tmp_path / "c.trace.txt")
    trace, coulomb = (x3dpd.read_trace(tmp_path / name) for name in ("t6.trace.txt", "c.trace.txt"))
    assert np.array_equal(trace.data, coulomb.data)


def test_a_restart_in_the_middle_of_the_contact_is_bit_identical(tmp_path):
    """Straight through, and stopped 10 steps into the contact then restarted: the same trace
    bytes (the displacement and stiffness are in the dump)."""
    deck = _hooke(floor_deck(dt=5e-7, velocity=(4.0, -9.0, 0.0), mu=0.3, spectator=False), 0.5)
    whole, part = tmp_path / "whole.trace.txt", tmp_path / "part.trace.txt"
    x3dpd.run(deck, tmax=4e-5, friction=LAW, trace=whole)
    x3dpd.run(deck, tmax=5e-6, friction=LAW, trace=part)
    x3dpd.run(deck, tmax=4e-5, friction=LAW, trace=part, restart=True)
    assert whole.read_bytes() == part.read_bytes()
