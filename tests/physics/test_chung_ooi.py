"""The Chung & Ooi (2011) benchmark tests 1-8, run as decks through x3dpd.run.

Scenes, materials, speeds and reference data: tools/chung_ooi.py (its docstring gives the
provenance of every reference); what each test checks and why its tolerance:
docs/physics.md "The Chung & Ooi benchmarks". The default suite runs the fewest points that pin
each curve (both ends of a regime); ``pytest -m validate`` runs the full curves and the
time-step convergence. Every run uses STEPS_PER_CONTACT = 200 steps per normal contact.
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]

from contact_reference import hertz_mindlin_impact, hooke_oblique_beta  # noqa: E402

_spec = importlib.util.spec_from_file_location("chung_ooi", ROOT / "tools" / "chung_ooi.py")
co = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(co)

#: Test 4 against the paper's digitised curves: Kratos's measure sum|d| / sum|ref|. Kratos passes
#: at 1.6 / 2.2 / 2.5 % (its CI bound is 10 %); the digitised points scatter by about 1 % of
#: each axis' span (test 4's two materials are printed as one curve). 5 % is twice the worst
#: Kratos figure; we measure 1.2 / 1.7 / 2.0 % on the 13 angles.
T4_TOLERANCE = 0.05


@pytest.mark.parametrize(
    "test, material",
    [(1, "glass"), (1, "limestone"), (2, "aluminium alloy (test 2)"), (2, "magnesium alloy")],
)
def test_1_and_2_normal_impacts_are_hertz(tmp_path, test, material):
    """Peak force and contact time of an elastic head-on impact (test 1: two spheres at 10 m/s
    each; test 2: a sphere at 0.2 m/s on a rigid plane) vs Hertz's closed forms, to 1e-3
    (the paper's theory; Verlet's error at 200 steps is ~(pi/200)^2 / 10, measured 3e-5)."""
    out = co.normal_impact(test, material, tmp_path)
    ref = out["reference"]
    assert out["force"] == pytest.approx(ref["force"], rel=1e-3)
    assert out["contact_time"] == pytest.approx(ref["contact_time"], rel=1e-3)
    assert out["delta"] == pytest.approx(ref["delta"], rel=1e-3)


@pytest.mark.parametrize("e_in", [0.2, 0.6])
def test_3_restitution_out_equals_in(tmp_path, e_in):
    """The linear law with restitution input (HOOKE) rebounds at e times the impact speed
    (measured error -1.1e-3 at e = 0.2, 8e-4 at 0.6: the dashpot's jump to c_n v at the onset,
    first order in dt; 2e-3 bounds it at 200 steps)."""
    e_out = co.restitution("aluminium oxide", e_in, tmp_path)
    assert e_out == pytest.approx(e_in, abs=2e-3)


def _test4(material, angles, tmp_path, steps=co.STEPS_PER_CONTACT):
    got = np.array([co.test4_point(material, a, tmp_path, steps) for a in angles])
    idx = [co.T4_ANGLES.index(a) for a in angles]
    refs = [np.array(r)[idx] for r in (co.T4_TANGENTIAL, co.T4_SPIN, co.T4_REBOUND)]
    return [co.mean_relative_error(got[:, k], refs[k]) for k in range(3)]


def test_4_oblique_impact_three_regimes(tmp_path):
    """Al2O3 at 10 deg (the contact point's velocity reverses: negative rebound angle), 25 deg
    (the least tangential restitution) and 60 deg (gross sliding) vs the paper's curves."""
    errors = _test4("aluminium oxide", (10.0, 25.0, 60.0), tmp_path)
    assert max(errors) < T4_TOLERANCE, errors


@pytest.mark.parametrize("material", ["steel", "polyethylene"])
def test_5_gross_sliding_spin(tmp_path, material):
    """At v_t/(mu v_n) = 10 the sphere slides throughout: R w'/(mu v_n) = -(5/2)(1 + e) = -5
    (e = 1, rigid-body impulse law; the paper's plateau), to 1e-3."""
    assert co.test5_point(material, 10.0, tmp_path) == pytest.approx(-5.0, rel=1e-3)


@pytest.mark.parametrize("test", [6, 8])
def test_6_and_8_gross_sliding_recoil(tmp_path, test):
    """A spinning sphere on the plane (6) and on a sphere at rest (8), chi = 0.187: the slip
    falls by chi v_s (times the HOOKE law's absolute-impulse factor 1.067 at e = 0.5), so
    beta = chi - 1 (the paper's first point, -0.815), to 1e-3 (measured 3e-5)."""
    point = co.test6_point if test == 6 else co.test8_point
    beta = point("aluminium alloy", co.T8_CHI[0], tmp_path)
    assert beta == pytest.approx(co.sliding_beta(co.T8_CHI[0], 0.5), abs=1e-3)
    assert beta == pytest.approx(co.T8_BETA[0], abs=0.02)  # the digitised paper point


def _test5_reference(material: str, x: float, steps: int = 20000) -> float:
    """Test 5's -R w'/(mu v_n) by a slow, obviously correct integration of Hertz-Mindlin on a
    rigid plane (x3dpd.physics.mindlin's rules: force history, rescaled on unloading, Coulomb's
    limit) on the rigid-body equations of the sphere, symplectic Euler at ``steps`` steps per
    Hertz contact (it moves by 3e-4 from 5000; tests/contact_reference.py)."""
    cfg = co.TESTS[5]
    r, mu, vn = cfg["radius"], cfg["mu"], cfg["speed"]
    young, nu, _ = co.MATERIALS[material]
    h = co.hertz_wall(material, r, vn)["contact_time"] / steps
    *_, w = hertz_mindlin_impact(co.sphere_mass(material, r), r, young, nu, mu, vn, x * mu * vn, h)
    return -abs(r * w) / (mu * vn)


@pytest.mark.parametrize("material", ["steel", "polyethylene"])
def test_5_sticking_branch(tmp_path, material):
    """Below the plateau (v_t/(mu v_n) = 0.35 and 0.99: the contact sticks, then slides) the
    final spin is the reference integration's of the same rules to 3 % (measured 1.5-2.0 % at
    200 steps per contact: the stick-slip switches make the step loop first order, as in
    tests/physics/test_mindlin.py). The paper's digitised curve is not the reference here
    (docs/physics.md: it breaks the bound |R w'| <= (10/7) v_t at its first points)."""
    for x in (co.T5_X[1], co.T5_X[3]):
        ref = _test5_reference(material, x)
        got = co.test5_point(material, x, tmp_path)
        print(f"\ntest 5 {material} x {x}: {got:.5f}, reference {ref:.5f}")
        assert got == pytest.approx(ref, rel=0.03)


def _sticking_reference(test: int, material: str, chi: float, steps: int) -> float:
    """beta of tests 6 (``test`` 6: sphere on the plane) and 8 (on an identical sphere) by a
    slow, obviously correct integration of the same contact rules
    (tests/contact_reference.py, ``hooke_oblique_beta``): the HOOKE normal force, the tangential
    spring with its dashpot c_t = c_n sqrt(k_t/k_n) (x3dpd.physics.hooke.tangential_damping),
    Coulomb's limit, on the relative normal motion (mass m* = m, or m/2) and the relative slip
    (1/m_t = 3.5/m, or 7/m), at ``steps`` steps per contact."""
    cfg = co.TESTS[test]
    r, e, mu, vn = cfg["radius"], cfg["e"], cfg["mu"], cfg["speed"]
    m = co.sphere_mass(material, r)
    pair = test == 8
    m_n, inv_mt = (m / 2.0, 7.0 / m) if pair else (m, 3.5 / m)
    return hooke_oblique_beta(
        co.hooke_stiffness(material, r, vn, pair),
        e,
        co.MATERIALS[material][1],
        m_n,
        inv_mt,
        mu,
        vn,
        3.5 * mu * (1.0 + e) * vn / chi,
        steps,
    )


#: The sticking branch of tests 6 and 8 converges slowly in the step: as the unclamped HOOKE
#: force turns from push to pull near the end of the contact, Coulomb's limit mu |F_N| passes
#: through zero and releases the spring, and a step that does not land near that instant
#: keeps part of it: at large chi (a small slip, a small spring force) the step must resolve
#: mu |dF_N/dt| dt << |F_s|. At 200 steps per contact beta(chi = 24) is +0.003 (x3dpd and the
#: reference alike), converged -0.127; at 20000 steps both are within 0.006 of the converged value.
STICKING_STEPS = 20000


@pytest.mark.parametrize("test", [6, 8])
def test_6_and_8_sticking_branch(tmp_path, test):
    """At chi = 7.8 and 24 (the contact sticks but at its ends) beta is the converged value of
    the same rules (:func:`_sticking_reference` at 320000 steps per contact; it moves by 1e-3
    from 80000) to 0.01 at STICKING_STEPS per contact -- the tangential dashpot reverses the
    slip (beta < 0); without it beta is +0.16 at chi = 24. The paper's -0.32 is not reached:
    docs/physics.md says why."""
    point = co.test6_point if test == 6 else co.test8_point
    for chi in (co.T8_CHI[-3], co.T8_CHI[-1]):
        ref = _sticking_reference(test, "aluminium alloy", chi, 320000)
        beta = point("aluminium alloy", chi, tmp_path, STICKING_STEPS)
        print(f"\ntest {test} chi {chi}: beta {beta:+.4f}, reference {ref:+.4f}")
        assert beta == pytest.approx(ref, abs=0.01)
        assert beta < -0.05


def test_7_spins_that_do_not_slip_stay(tmp_path):
    """Two spheres closing at 0.2 m/s each, spinning at w and -w: their contact points move
    together, so nothing tangential happens: w' = w, v_t' = 0 (exact)."""
    out = co.test7_point("copper", 5.0, tmp_path)
    assert out["spin"] == pytest.approx((5.0, -5.0), rel=1e-12)
    assert max(abs(v) for v in out["vt"]) < 1e-12


# -- the full curves (pytest -m validate) -----------------------------------------------------


@pytest.mark.validate
def test_4_full_curves(tmp_path):
    errors = _test4("aluminium oxide", co.T4_ANGLES, tmp_path)
    print("\ntest 4 Al2O3 mean relative errors (e_t, spin, rebound):", errors)
    assert max(errors) < T4_TOLERANCE


@pytest.mark.validate
def test_4_converges_as_the_step_shrinks(tmp_path):
    """The test-4 results at 50, 100, 200, 400 steps per contact: successive changes shrink
    (second order: about fourfold per halving) and the errors against the paper settle."""
    angles = (10.0, 25.0, 60.0)
    runs = {
        n: np.array([co.test4_point("aluminium oxide", a, tmp_path, n) for a in angles])
        for n in (50, 100, 200, 400)
    }
    changes = [
        float(np.max(np.abs(runs[2 * n] - runs[n]) / np.maximum(np.abs(runs[400]), 1)))
        for n in (50, 100, 200)
    ]
    print("\nlargest change per halving:", changes)
    assert changes[1] < 0.5 * changes[0] and changes[2] < 0.5 * changes[1]
    assert changes[2] < 1e-3


@pytest.mark.validate
@pytest.mark.parametrize("material", ["aluminium oxide", "cast iron"])
def test_3_full(tmp_path, material):
    """The HOOKE restitution at 200 steps per contact. Its dashpot is not clamped, so at the
    end the contact pulls with -c_n e v; the step on which the overlap closes takes up to one
    step more or less of that pull: |e - e_in| <= (c_n/m) dt e_in = 2 zeta (pi/steps) e_in
    (k_n is fitted so that w_n t_c = pi, dt = t_c/steps; zeta from e_in), 3.5e-3 at e = 0.4,
    plus 1e-4 for Verlet's second-order error. Measured: 2.35e-3 at e = 0.4 (0.4000 at 400
    steps, 0.40059 at 800: the jitter of where the contact ends, not a drift)."""
    steps = co.STEPS_PER_CONTACT
    for e_in in co.TESTS[3]["e"]:
        le = math.log(e_in)
        zeta = -le / math.sqrt(math.pi**2 + le * le)
        bound = 2.0 * zeta * math.pi / steps * e_in + 1e-4
        assert co.restitution(material, e_in, tmp_path, steps) == pytest.approx(e_in, abs=bound)


@pytest.mark.validate
@pytest.mark.parametrize(
    "test, material", [(6, "aluminium alloy"), (6, "nylon"), (8, "aluminium alloy"), (8, "nylon")]
)
def test_6_and_8_sliding_branch(tmp_path, test, material):
    """The gross-sliding branch chi < 0.6 (the slip never reverses) against the closed form;
    the Mindlin spring's build-up at the onset costs up to 1 % of chi."""
    point = co.test6_point if test == 6 else co.test8_point
    for chi in co.T8_CHI[:3]:
        assert point(material, chi, tmp_path) == pytest.approx(
            co.sliding_beta(chi, 0.5), abs=0.01 * chi
        )


@pytest.mark.validate
@pytest.mark.parametrize("material", ["steel", "polyethylene"])
def test_5_plateau(tmp_path, material):
    for x in (10.0, 20.0):
        assert co.test5_point(material, x, tmp_path) == pytest.approx(-5.0, rel=1e-3)


def test_shipped_decks_are_the_generators(tmp_path):
    """decks/benchmarks/chung_ooi/ is what `python tools/chung_ooi.py decks DIR` writes, and
    every deck passes `x3dpd check` without errors."""
    shipped = ROOT / "decks" / "benchmarks" / "chung_ooi"
    written = co.write_decks(tmp_path)
    assert sorted(p.name for p in written) == sorted(p.name for p in shipped.glob("*.inp"))
    for p in written:
        assert p.read_text() == (shipped / p.name).read_text(), p.name
        assert not co.x3dpd.check(shipped / p.name).errors, p.name
