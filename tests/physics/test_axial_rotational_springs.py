"""Axial (MATID type 2) and rotational (type 3) spring-dampers, run by the solver from deck text,
against closed forms computed here from k, c, m and I.

* a mass on an axial spring inclined at an arbitrary angle oscillates along the spring's line
  at sqrt(k/m);
* a mass whirling on an axial spring (several full turns: large rotation) stays on its circle
  at the closed-form rate with the spring stretched by a constant amount;
* an axial damper rings a mass down at the damped frequency and decay of the closed form, and
  the ledger's dissipation is the energy the closed form loses;
* a rotational spring turns a node with rotary inertia at sqrt(k/I) about each axis, a
  two-node one at sqrt(k (1/I_a + 1/I_b)) with the angular momentum kept, a damped one rings
  down as the closed form;
* on a rigid body's slave node a rotational spring turns the body at sqrt(k/J);
* the energy ledger closes in every run; a resumed run continues bit for bit.

Every scene holds resting spectators (an axial and a rotational element, a free rigid body) so
that all runs share one compiled step loop (:data:`SPRINGS_LOOP`: the tests ride it).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import x3dpd

DT = 1e-4


def _deck(
    tmp_path,
    *,
    materials,
    nodes,
    elements,
    masses,
    boundaries,
    initials,
    tmax,
    rbels=(),
    itrac=10,
    trace=None,
    name="springs.inp",
):
    """A deck file of the given records (one string per record) and the spectators, no
    particles."""

    def card(title, records):
        return [title, *(f"   {r}" for r in records), "END"]

    lines = [
        "$ axial and rotational spring test scene",
        "TITLE",
        name,
        "END",
        *card("PARAMETERS", [f"0.0 {tmax!r} 0.0 {DT!r} {DT!r} 0 1e12 0 5 0 {itrac}"]),
        *card("MATID", [*materials, *SPECTATOR_MATERIALS]),
        *card("NODE COORDINATES", [*nodes, *SPECTATOR_NODES]),
        *card("ELEMENTS", [*elements, *SPECTATOR_ELEMENTS]),
        *card("MASS", [*masses, *SPECTATOR_MASSES]),
        *card("RBEL", [*rbels, *SPECTATOR_RBELS]),
        *card("BOUNDARY CONDITIONS", [*boundaries, *SPECTATOR_BOUNDARIES]),
    ]
    if initials:
        lines += card("INITIAL", initials)
    if trace:
        lines += card("TRACE", [" ".join(str(n) for n in trace)])
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


def _f(*values) -> str:
    """Numbers as deck fields (shortest round-trip form)."""
    return " ".join(repr(float(v)) for v in values)


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


#: Spectators in every scene: node 90 fixed, node 91 resting on an axial spring to it (MID 90),
#: node 92 resting on a rotational spring to ground (MID 91), a free rigid body (master 93,
#: slave 94) at rest. Nothing moves them.
SPECTATOR_MATERIALS = ["90 2 0.0 1.0 10.0 0.0 0.0 0.0", "91 3 0.0 1.0 10.0 10.0 10.0 0.0"]
SPECTATOR_NODES = [
    "90 9.0 9.0 9.0",
    "91 9.0 9.0 10.0",
    "92 8.0 8.0 8.0",
    "93 7.0 7.0 7.0",
    "94 7.5 7.0 7.0",
]
SPECTATOR_ELEMENTS = ["90 90 90 91", "91 91 92"]
SPECTATOR_MASSES = ["91 1.0", "92 0.0 1.0 1.0 1.0", "93 1.0 1.0 1.0 1.0"]
SPECTATOR_RBELS = ["93 123456 1 94"]
SPECTATOR_BOUNDARIES = ["90 90 1 1 2 3 4 5 6", "91 91 1 4 5 6", "92 92 1 1 2 3"]
#: The one step loop of these scenes with their spectators (x3dpd Variant.label)
SPRINGS_LOOP = "rigid+rigid_rotation+axial_springs+rotational_springs"
#: decks/beam_1.inp's loop
BEAM_1_LOOP = (
    "springs+rigid+walls+friction+viscoelastic+external+n_maxwell=1+walls_translate+one_wall_kind"
)
pytestmark = pytest.mark.rides(SPRINGS_LOOP)


def _ledger_closes(r, rel):
    """|residual| over the run within ``rel`` of the largest total energy."""
    e = r.energy
    scale = np.abs(e["total_energy"]).max()
    worst = np.abs(e["residual"]).max() / scale
    print(f"ledger residual {worst:.1e} of the energy")
    assert worst < rel, worst
    return worst


def _axial_scene(tmp_path, *, anchor, direction, rest, k, c, m, v0, tmax):
    """Node 1 fixed at ``anchor``; node 2 (mass m, rotations fixed) at anchor + rest *
    direction, on a type 2 element (k, c) from node 1, starting with velocity ``v0``."""
    tip = np.asarray(anchor) + rest * _unit(direction)
    path = _deck(
        tmp_path,
        materials=[f"1 2 0.0 1.0 {_f(k)} 0.0 0.0 {_f(c)}"],
        nodes=[f"1 {_f(*anchor)}", f"2 {_f(*tip)}"],
        elements=["1 1 1 2"],
        masses=[f"2 {_f(m)}"],
        boundaries=["1 1 1 1 2 3 4 5 6", "2 2 1 4 5 6"],
        initials=[f"2 {_f(*v0)}"],
        tmax=tmax,
        trace=(2, 91, 92),
    )
    return x3dpd.run(path), tip


def test_inclined_axial_spring_oscillates_along_its_line(tmp_path):
    """x(t) = x0 + e (V/w) sin(w t), w = sqrt(k/m), along the line e of the spring, which is
    inclined to every axis; no motion across it."""
    k, m, speed = 80.0, 0.5, 0.3
    e = _unit([0.31, -0.52, 0.79])
    r, tip = _axial_scene(
        tmp_path,
        anchor=(0.2, -0.1, 0.3),
        direction=e,
        rest=1.3,
        k=k,
        c=0.0,
        m=m,
        v0=speed * e,
        tmax=2.0,
    )
    w = math.sqrt(k / m)
    t = r.trace.time
    want = tip + np.outer(speed / w * np.sin(w * t), e)
    err = np.abs(r.trace.node(2)[:, :3] - want).max() / (speed / w)
    print(f"\ninclined: max |x - exact| = {err:.1e} of the amplitude")
    # velocity Verlet's phase error after w t = 25 rad at w dt = 1.3e-3 is w t (w dt)^2 / 24
    # = 1.7e-6 of the amplitude (measured 1.3e-6); 1e-5 leaves room for it and rounding. An
    # axis-aligned spring (type 1 with KX alone) would leave y and z free: an error of order 1.
    assert err < 1e-5, err
    # linear along the line: the ledger closes to round-off (measured 3e-13)
    _ledger_closes(r, 1e-10)


def test_axial_spring_whirls_through_large_rotations(tmp_path):
    """Started at rest length with a speed V across the spring, the mass whirls round the fixed
    node for more than two turns while the spring stretches and relaxes: a central force, so
    the angular momentum m (x - x_1) x v is constant, the motion stays in its plane, the radius
    swings between L0 and the r_max of the closed form, and the spring's energy is
    k (L - L0)^2 / 2 of the length L between the nodes, whatever their direction."""
    k, m, rest, speed = 100.0, 1.0, 1.0, 5.0
    u = _unit([0.6, 0.2, -0.3])
    across = _unit(np.cross(u, [0.1, 0.9, 0.4]))
    anchor = np.array([0.5, 0.0, -0.2])
    r, _ = _axial_scene(
        tmp_path,
        anchor=anchor,
        direction=u,
        rest=rest,
        k=k,
        c=0.0,
        m=m,
        v0=speed * across,
        tmax=4.0,
    )
    x = r.trace.node(2)[:, :3] - anchor
    v = r.trace.node(2)[:, 3:6]
    radius = np.linalg.norm(x, axis=1)
    # angular momentum: velocity Verlet keeps x(n) x v(n) of a central force exactly (the
    # kicks are parallel to x), so only rounding is left (measured 1.5e-14)
    h0 = m * rest * speed * np.cross(u, across)
    h = m * np.cross(x, v)
    print(
        f"\nwhirl: angular momentum drift {np.abs(h - h0).max() / np.linalg.norm(h0):.1e}, "
        f"r_max {radius.max():.6f}, min {radius.min():.6f}"
    )
    assert np.abs(h - h0).max() / np.linalg.norm(h0) < 1e-10
    # more than two full turns in the plane of (u, across)
    turned = np.unwrap(np.arctan2(x @ across, x @ u))
    assert turned[-1] > 4 * math.pi
    # r_max: the other root of m V^2 L0^2 / r^2 + k (r - L0)^2 = m V^2 (energy and angular
    # momentum at the turning points), found by bisection
    lo, hi = rest * (1 + 1e-9), 10 * rest

    def excess(q):
        return m * speed**2 * rest**2 / q**2 + k * (q - rest) ** 2 - m * speed**2

    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if excess(mid) < 0 else (lo, mid)
    r_max = 0.5 * (lo + hi)
    # sampled every 1e-3 s: near a turning point the radius is off its peak by at most
    # r'' (dt_out / 2)^2 / 2 ~ 1e-5 of it; the integrator's error is smaller
    assert radius.max() == pytest.approx(r_max, rel=1e-4)
    assert radius.min() == pytest.approx(rest, rel=1e-4)
    # the stored energy is that of the stretch along the turning line (an axis-wise spring
    # would store k |x - x0|^2 / 2, many times more after half a turn)
    np.testing.assert_allclose(
        r.energy["spring_energy"],
        0.5 * k * (radius - rest) ** 2,
        rtol=1e-9,
        atol=1e-12 * k * rest**2,
    )
    # a turning force is not linear: the residual is the integrator's O((kappa dt)^2), kappa
    # ~ 12 rad/s the radial frequency: ~2e-6 of the energy (measured 1e-7)
    _ledger_closes(r, 1e-5)


def test_axial_damper_rings_down_as_the_closed_form(tmp_path):
    """x(t) = x0 + e V exp(-zeta w t) sin(w_d t) / w_d along the inclined line, w = sqrt(k/m),
    zeta = c / (2 m w), w_d = w sqrt(1 - zeta^2); the ledger's damper dissipation is the
    energy the closed form has lost."""
    k, m, c, speed = 80.0, 0.5, 1.2, 0.3
    w = math.sqrt(k / m)
    zeta = c / (2 * m * w)
    wd = w * math.sqrt(1 - zeta**2)
    e = _unit([-0.4, 0.35, 0.85])
    r, tip = _axial_scene(
        tmp_path,
        anchor=(0.0, 0.0, 0.0),
        direction=e,
        rest=0.7,
        k=k,
        c=c,
        m=m,
        v0=speed * e,
        tmax=2.0,
    )
    t = r.trace.time
    s = speed / wd * np.exp(-zeta * w * t) * np.sin(wd * t)
    sdot = speed * np.exp(-zeta * w * t) * (np.cos(wd * t) - zeta * w / wd * np.sin(wd * t))
    err = np.abs(r.trace.node(2)[:, :3] - (tip + np.outer(s, e))).max() / (speed / w)
    print(f"\ndamped: max |x - exact| = {err:.1e} of V/w")
    # the dashpot reads the half-step velocity (X3D's central difference): a lag of dt/2 that
    # errs by O(zeta w dt) = 1.2e-4 of the amplitude; 1e-3 bounds it (measured 2.0e-4).
    # Damping across the line, or none, changes the decay by order 1.
    assert err < 1e-3, err
    lost = 0.5 * m * speed**2 - (0.5 * m * sdot**2 + 0.5 * k * s**2)
    d = r.energy["dissipated_dampers"]
    print(f"dissipation error {np.abs(d - lost).max() / (0.5 * m * speed**2):.1e} of the start")
    assert np.abs(d - lost).max() < 1e-3 * 0.5 * m * speed**2
    assert d[-1] > 0.9 * 0.5 * m * speed**2  # most of it gone after 2 s (zeta w t = 2.4)
    # linear: the ledger closes to round-off (measured 1e-13)
    _ledger_closes(r, 1e-10)


def _rotational_run(tmp_path):
    """Node 3 (inertias I3) on a rotational spring K3 to ground; nodes 4 and 5 (inertias I4,
    I5) joined by a rotational spring K45; node 6 (inertia I6) on a damped one (K6, C6) to
    ground. Translations fixed; the nodes start turning at W3, W4 and W6."""
    p = ROTATIONAL

    def fmt(v):
        return _f(*v)

    path = _deck(
        tmp_path,
        materials=[
            f"3 3 0.0 1.0 {fmt(p['K3'])} 0.0",
            f"4 3 0.0 1.0 {fmt(p['K45'])} 0.0",
            f"6 3 0.0 1.0 {fmt(p['K6'])} {_f(p['C6'])}",
        ],
        nodes=["3 0.0 0.0 0.0", "4 1.0 0.0 0.0", "5 2.0 0.5 0.0", "6 0.0 3.0 0.0"],
        elements=["3 3 3", "4 4 4 5", "6 6 6"],
        masses=[
            f"3 0.0 {fmt(p['I3'])}",
            f"4 0.0 {fmt(p['I4'])}",
            f"5 0.0 {fmt(p['I5'])}",
            f"6 0.0 {fmt(p['I6'])}",
        ],
        boundaries=["3 6 1 1 2 3"],
        initials=[f"3 0 0 0 {fmt(p['W3'])}", f"4 0 0 0 {fmt(p['W4'])}", f"6 0 0 0 {fmt(p['W6'])}"],
        tmax=3.0,
        trace=(3, 4, 5, 6, 91, 92, 93),
        name="rotational.inp",
    )
    return x3dpd.run(path)


def _rigid_body_run(tmp_path):
    """A rigid body (master 7 with inertia I7 and mass M7, slave 8 of mass M8 at R8 from it
    along x) free to turn about z only, held by a rotational spring K8 about z on its slave;
    it starts turning at W7."""
    p = ROTATIONAL
    path = _deck(
        tmp_path,
        materials=[f"8 3 0.0 1.0 0.0 0.0 {_f(p['K8'])} 0.0"],
        nodes=["7 0.0 -3.0 0.0", f"8 {_f(p['R8'])} -3.0 0.0"],
        elements=["8 8 8"],
        masses=[f"7 {_f(p['M7'], *p['I7'])}", f"8 {_f(p['M8'])}"],
        rbels=["7 123456 1 8"],
        boundaries=["7 7 1 1 2 3 4 5"],
        initials=[f"7 0 0 0 0 0 {_f(p['W7'])}"],
        tmax=3.0,
        trace=(7,),
        name="rigid.inp",
    )
    return x3dpd.run(path)


ROTATIONAL = {
    "I3": np.array([2.0, 0.5, 1.0]),
    "K3": np.array([50.0, 8.0, 30.0]),
    "W3": np.array([0.2, -0.3, 0.1]),
    "I4": np.array([1.5, 1.5, 1.5]),
    "I5": np.array([0.5, 0.5, 0.5]),
    "K45": np.array([20.0, 20.0, 20.0]),
    "W4": np.array([0.2, -0.1, 0.2]),
    "I6": np.array([1.0, 1.0, 1.0]),
    "K6": np.array([40.0, 40.0, 40.0]),
    "C6": 0.8,
    "W6": np.array([0.3, 0.0, -0.1]),
    "M7": 1.0,
    "I7": np.array([0.4, 0.4, 0.4]),
    "M8": 2.0,
    "R8": 0.5,
    "K8": 36.0,
    "W7": 0.25,
}


@pytest.fixture(scope="module")
def rotational(tmp_path_factory):
    return _rotational_run(tmp_path_factory.mktemp("rot"))


def test_rotational_spring_turns_at_sqrt_k_over_i(rotational):
    """omega_d(t) = W_d cos(sqrt(k_d / I_d) t) about each global axis, and the spring stores
    k_d theta_d^2 / 2 with theta_d = W_d sin(sqrt(k_d / I_d) t) / sqrt(k_d / I_d)."""
    p = ROTATIONAL
    t = rotational.trace.time
    rate = np.sqrt(p["K3"] / p["I3"])
    want = p["W3"] * np.cos(np.outer(t, rate))
    err = np.abs(rotational.trace.node(3)[:, 6:9] - want).max() / np.abs(p["W3"]).max()
    print(f"\nrotational: max |w - exact| = {err:.1e} of W")
    # velocity Verlet's phase error, Omega t (Omega dt)^2 / 24 at Omega dt <= 5.5e-4 for 3 s:
    # 2e-7 (measured 1e-7); 1e-5 bounds it with rounding. Stiffness about the wrong axis
    # changes the rate by order 1.
    assert err < 1e-5, err


def test_two_node_rotational_spring_keeps_the_angular_momentum(rotational):
    """Between two free nodes the relative spin w_4 - w_5 = W cos(Omega t),
    Omega^2 = k (1/I_4 + 1/I_5); the spin of the pair's total angular momentum is constant:
    w_4 = w_c + I_5/(I_4 + I_5) W cos(Omega t), w_5 = w_c - I_4/(I_4 + I_5) W cos(Omega t)."""
    p = ROTATIONAL
    t = rotational.trace.time
    i4, i5 = p["I4"], p["I5"]
    omega = np.sqrt(p["K45"] * (1 / i4 + 1 / i5))
    rel = p["W4"] * np.cos(np.outer(t, omega))
    wc = i4 * p["W4"] / (i4 + i5)
    w4 = rotational.trace.node(4)[:, 6:9]
    w5 = rotational.trace.node(5)[:, 6:9]
    scale = np.abs(p["W4"]).max()
    print(
        f"\ntwo-node: {np.abs(w4 - (wc + i5 / (i4 + i5) * rel)).max() / scale:.1e}, "
        f"{np.abs(w5 - (wc - i4 / (i4 + i5) * rel)).max() / scale:.1e} of W"
    )
    # phase error at Omega dt = 7.3e-4 over 22 rad: 5e-7 of W (measured 3.4e-7); 1e-5 bounds
    # it. Without the
    # reaction on the second node, w_5 stays 0 and the momentum is not kept.
    assert np.abs(w4 - (wc + i5 / (i4 + i5) * rel)).max() / scale < 1e-5
    assert np.abs(w5 - (wc - i4 / (i4 + i5) * rel)).max() / scale < 1e-5
    momentum = i4 * w4 + i5 * w5
    assert np.abs(momentum - i4 * p["W4"]).max() < 1e-12 * np.abs(i4 * p["W4"]).max()


def test_rotational_spring_on_a_rigid_body_turns_the_body(tmp_path):
    """On a slave node the spring's moment turns the whole body, J = I_7 + M_8 R_8^2 about z:
    omega_z(t) = W cos(sqrt(k/J) t). The spring's rotation advances with the slave's spin,
    which the slave takes from its master in the same drift."""
    p = ROTATIONAL
    r = _rigid_body_run(tmp_path)
    t = r.trace.time
    inertia = p["I7"][2] + p["M8"] * p["R8"] ** 2
    want = p["W7"] * np.cos(math.sqrt(p["K8"] / inertia) * t)
    err = np.abs(r.trace.node(7)[:, 8] - want).max() / p["W7"]
    print(f"\nrigid body: max |w - exact| = {err:.1e} of W")
    # phase error Omega t (Omega dt)^2 / 24 at Omega dt = 6.3e-4: 3e-7; 1e-5 bounds it. A
    # rotation advanced with the slave's spin of the step before (stale by one step) errs by
    # Omega dt ~ 6e-4.
    assert err < 1e-5, err
    # a rigid master's rotation is kicked with its inertia tensor, outside the ledger's Verlet
    # correction S (which sums f^2/m over the DOFs with an inverse mass), so the ledger shows
    # the integrator's (Omega dt)^2 / 4 = 1e-7 of the body's energy (measured 1.0e-7)
    _ledger_closes(r, 1e-6)


def test_rotational_damper_rings_down_as_the_closed_form(rotational):
    """omega(t) = W exp(-zeta Omega t) (cos Omega_d t - zeta Omega / Omega_d sin Omega_d t),
    Omega = sqrt(k/I), zeta = c / (2 sqrt(k I)), Omega_d = Omega sqrt(1 - zeta^2)."""
    p = ROTATIONAL
    t = rotational.trace.time
    rate = np.sqrt(p["K6"] / p["I6"])
    zeta = p["C6"] / (2 * np.sqrt(p["K6"] * p["I6"]))
    rd = rate * np.sqrt(1 - zeta**2)
    decay = np.exp(-np.outer(t, zeta * rate))
    want = p["W6"] * decay * (np.cos(np.outer(t, rd)) - zeta * rate / rd * np.sin(np.outer(t, rd)))
    err = np.abs(rotational.trace.node(6)[:, 6:9] - want).max() / np.abs(p["W6"]).max()
    print(f"\nrotational damper: max |w - exact| = {err:.1e} of W")
    # the damper reads the half-step spin: a lag of dt/2, an error O(zeta Omega dt) ~ 4e-5
    # per radian of phase; 1e-3 bounds it (measured 1.2e-4)
    assert err < 1e-3, err


def test_rotational_ledger_closes(rotational):
    """Kinetic (rotation) + spring energy + damper dissipation stay the initial kinetic
    energy: the ledger closes to round-off for these linear springs, and the dissipation is
    what the damped node has lost."""
    p = ROTATIONAL
    e = rotational.energy
    start = 0.5 * (
        np.sum(p["I3"] * p["W3"] ** 2)
        + np.sum(p["I4"] * p["W4"] ** 2)
        + np.sum(p["I6"] * p["W6"] ** 2)
    )
    assert e["kinetic_rotation"][0] == pytest.approx(start, rel=1e-14)
    assert e["spring_energy"][0] == 0.0
    _ledger_closes(rotational, 1e-10)
    # all of node 6's energy is gone by 3 s (zeta Omega t = 1.2: exp(-2.4) = 9 % left)
    six = 0.5 * np.sum(p["I6"] * p["W6"] ** 2)
    assert 0.85 * six < e["dissipated_dampers"][-1] < six
    # the spectators never move
    assert np.all(rotational.trace.node(91)[:, 3:9] == 0.0)
    assert np.all(rotational.trace.node(92)[:, 3:9] == 0.0)
    assert np.all(rotational.trace.node(93)[:, 3:9] == 0.0)


def _damped_pair_deck(tmp_path, tmax):
    """A damped axial element (node 2 on node 1) and a damped rotational one (node 6): every
    state the new springs carry between steps is non-zero."""
    e = _unit([0.2, 0.7, -0.4])
    tip = 0.8 * e
    p = ROTATIONAL
    return _deck(
        tmp_path,
        materials=["1 2 0.0 1.0 80.0 0.0 0.0 1.2", f"6 3 0.0 1.0 {_f(*p['K6'])} {_f(p['C6'])}"],
        nodes=["1 0.0 0.0 0.0", f"2 {_f(*tip)}", "6 0.0 3.0 0.0"],
        elements=["1 1 1 2", "6 6 6"],
        masses=["2 0.5", f"6 0.0 {_f(*p['I6'])}"],
        boundaries=["1 1 1 1 2 3 4 5 6", "2 2 1 4 5 6", "6 6 1 1 2 3"],
        initials=[f"2 {_f(*(0.3 * _unit([1.0, 0.2, 0.1])))}", f"6 0 0 0 {_f(*p['W6'])}"],
        tmax=tmax,
        name="damped.inp",
    )


def test_a_resumed_run_continues_bit_for_bit(tmp_path, monkeypatch):
    """The restart dump holds each rotational spring's rotation and the dampers' last forces
    and moments: a run resumed from it writes the same bytes as the run that went through."""
    from x3dpd.io.restart import load_restart

    monkeypatch.chdir(tmp_path)
    deck = _damped_pair_deck(tmp_path, tmax=0.5)
    x3dpd.run(deck, trace="whole.trace.txt")
    x3dpd.run(deck, tmax=0.25, trace="part.trace.txt")
    arrays, _ = load_restart("part.trace.txt.restart.npz")
    assert np.any(arrays["rotational_theta"] != 0.0)
    assert np.any(arrays["rotational_md_prev"] != 0.0)
    assert np.any(arrays["axial_fd_prev"] != 0.0)
    x3dpd.run(deck, trace="part.trace.txt", restart=True)
    for name in ("trace.txt", "energy.csv"):
        assert (tmp_path / f"part.{name}").read_bytes() == (tmp_path / f"whole.{name}").read_bytes()


@pytest.mark.rides(BEAM_1_LOOP)
def test_a_dump_from_before_these_springs_restores_and_runs_on():
    """Restart dumps written before types 2 and 3 have none of their state: such a state has
    empty spring rows (a scene without them) and runs on bit for bit."""
    from pathlib import Path

    from x3dpd.model.build import build_model
    from x3dpd.solver.simulation import Simulation
    from x3dpd.solver.state import State

    deck = x3dpd.load_deck(Path(__file__).resolve().parents[2] / "decks" / "beam_1.inp")
    model = build_model(deck)
    whole = Simulation(model)
    whole.advance(400)
    sim = Simulation(model)
    sim.advance(200)
    new = ("axial_fd_prev", "rotational_theta", "rotational_md_prev")
    old = State.from_arrays({k: v for k, v in sim.state.to_arrays().items() if k not in new})
    assert all(getattr(old, name).shape == (0, 3) for name in new)
    resumed = Simulation(model)
    resumed.restore(old)
    resumed.advance(200)
    np.testing.assert_array_equal(resumed.state.x, whole.state.x)
    np.testing.assert_array_equal(resumed.state.vel, whole.state.vel)
