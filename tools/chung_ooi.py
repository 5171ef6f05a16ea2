"""The Chung & Ooi benchmark tests 1-8 as x3dpd decks: scenes, reference values, plots.

Chung, Y. C. and Ooi, J. Y., "Benchmark tests for verifying discrete element modelling codes at
particle impact level", Granular Matter 13 (2011) 643-656. Eight single impacts, each with two
materials; every scene here is a deck in SI units (UNITS m N s) written by :func:`wall_deck` or
:func:`pair_deck` and run through ``x3dpd.run``; docs/physics.md "The Chung & Ooi benchmarks"
says what each test checks, with which reference and tolerance.

Commands (python tools/chung_ooi.py ...):

* ``decks DIR``: write one deck per test and material (the first angle of each sweep) to DIR
  (the shipped set is decks/benchmarks/chung_ooi/);
* ``plots``: run every curve and write docs/img/chung_ooi_*.png;
* ``convergence``: the test-4 errors at 25, 50, 100, 200, 400 steps per contact (the table in
  docs/physics.md).

Reference data. Tests 1-3 and the gross-sliding branches of tests 5, 6 and 8: closed forms
(Hertz; the rigid-body impulse law), evaluated here. Test 4 (tangential restitution, final spin,
rebound angle of Al2O3 at 13 angles) and test 5 (final spin of steel and polyethylene) and test 8
(beta against chi, sphere on sphere): the paper's curves as digitised by the Kratos DEM
application's Chung & Ooi tests (github.com/KratosMultiphysics/Kratos,
applications/DEMApplication/tests/DEM3D_chung_ooi_tests/: test4_data/paper_data/
benchmark4_graph{1,2,3}_ref.dat, paper_data_5_to_8/benchmark5_graph2.dat, benchmark8_graph1.dat).
Test 7's reference is exact (the spins do not slip: nothing changes).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

import x3dpd

ROOT = Path(__file__).resolve().parents[1]

#: Young's modulus [Pa], Poisson's ratio, density [kg/m^3] (Chung & Ooi Table 1; the values of
#: tests 1-4 as the Kratos and Yade benchmark scripts use them).
MATERIALS = {
    "glass": (4.8e10, 0.20, 2800.0),
    "limestone": (2.0e10, 0.25, 2500.0),
    "aluminium alloy": (7.0e10, 0.33, 2700.0),
    "magnesium alloy": (4.0e10, 0.35, 1800.0),
    "aluminium oxide": (3.8e11, 0.23, 4000.0),
    "cast iron": (1.0e11, 0.25, 7000.0),
    "steel": (2.08e11, 0.30, 7850.0),
    "polyethylene": (1.0e9, 0.40, 1400.0),
    "nylon": (2.5e9, 0.40, 1000.0),
    "copper": (1.2e11, 0.35, 8900.0),
}
#: Test 2's aluminium alloy has nu 0.30 and density 2699 (test 4's: 0.33, 2700).
MATERIALS["aluminium alloy (test 2)"] = (7.0e10, 0.30, 2699.0)

#: Each test: materials, radius [m], speed [m/s], mu, restitution (None: the elastic law).
TESTS = {
    1: dict(materials=("glass", "limestone"), radius=0.010, speed=10.0, mu=0.35, e=None),
    2: dict(
        materials=("aluminium alloy (test 2)", "magnesium alloy"),
        radius=0.10,
        speed=0.2,
        mu=0.0,
        e=None,
    ),
    3: dict(
        materials=("aluminium oxide", "cast iron"),
        radius=0.0025,
        speed=3.9,
        mu=0.0,
        e=(0.2, 0.4, 0.6, 0.8, 1.0),
    ),
    4: dict(
        materials=("aluminium oxide", "aluminium alloy"), radius=0.0025, speed=3.9, mu=0.092, e=None
    ),
    5: dict(materials=("steel", "polyethylene"), radius=1.0e-5, speed=5.0, mu=0.3, e=None),
    6: dict(materials=("aluminium alloy", "nylon"), radius=0.10, speed=0.2, mu=0.4, e=0.5),
    7: dict(materials=("aluminium alloy", "copper"), radius=0.10, speed=0.2, mu=0.4, e=0.5),
    8: dict(materials=("aluminium alloy", "nylon"), radius=0.10, speed=0.2, mu=0.4, e=0.5),
}

#: Test 4, Al2O3: incident angle [deg] -> tangential restitution, final spin [rad/s] (Kratos's
#: sign: spin about the axis that makes it negative), rebound angle of the contact point [deg].
T4_ANGLES = (5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 50.0, 60.0, 70.0, 80.0, 85.0)
T4_TANGENTIAL = (
    0.9481,
    0.6870,
    0.6244,
    0.6161,
    0.6343,
    0.6837,
    0.7372,
    0.7809,
    0.8451,
    0.8929,
    0.9316,
    0.9662,
    0.9827,
)
T4_SPIN = (
    -19.27,
    -213.0,
    -377.8,
    -510.6,
    -599.4,
    -616.5,
    -582.3,
    -544.8,
    -457.0,
    -357.5,
    -246.2,
    -126.3,
    -63.15,
)
T4_REBOUND = (
    3.761,
    -1.556,
    -5.544,
    -7.538,
    -7.538,
    -3.550,
    3.429,
    11.57,
    29.35,
    47.79,
    64.58,
    78.70,
    84.52,
)
#: Test 5: v_t/(mu v_n) -> -R w'/(mu v_n) (the final spin), FEM and the paper's DEM curves
T5_X = (
    0.0578,
    0.3526,
    0.6821,
    0.9942,
    1.3410,
    1.6879,
    2.0000,
    2.3295,
    2.9884,
    3.3179,
    3.9942,
    5.0,
    6.0058,
    10.0116,
    20.0,
)
T5_SPIN = {
    "steel": (
        -0.1055,
        -0.4301,
        -0.8197,
        -1.2498,
        -1.6637,
        -2.0938,
        -2.5240,
        -2.9784,
        -3.9037,
        -4.2932,
        -4.8368,
        -5.0068,
        -5.0062,
        -5.0041,
        -4.9905,
    ),
    "polyethylene": (
        -0.0974,
        -0.4382,
        -0.9009,
        -1.3310,
        -1.7611,
        -2.2156,
        -2.6701,
        -3.1165,
        -4.0498,
        -4.4556,
        -4.9342,
        -4.9662,
        -4.9575,
        -4.9635,
        -4.9418,
    ),
}
#: Test 8 (case A, two spheres): chi = 3.5 mu (1+e) v_n / v_s -> beta = -v_s'/v_s
T8_CHI = (
    0.1872,
    0.3583,
    0.5508,
    0.7647,
    0.9786,
    1.2139,
    1.4920,
    1.7701,
    2.0909,
    2.5187,
    2.9893,
    3.6310,
    4.5080,
    5.7701,
    7.8449,
    11.9091,
    23.9733,
)
T8_BETA = (
    -0.8152,
    -0.6262,
    -0.4394,
    -0.2378,
    -0.0173,
    0.0961,
    0.1108,
    0.0898,
    0.0583,
    0.0058,
    -0.0488,
    -0.1034,
    -0.1391,
    -0.1622,
    -0.2042,
    -0.2483,
    -0.3176,
)

#: Steps per (normal) contact duration of the benchmark runs (docs/physics.md: convergence).
STEPS_PER_CONTACT = 200


# -- closed forms ---------------------------------------------------------------------------


def sphere_mass(material: str, radius: float) -> float:
    return MATERIALS[material][2] * 4.0 / 3.0 * math.pi * radius**3


def hertz_wall(material: str, radius: float, v: float, pair: bool = False) -> dict:
    """Head-on elastic Hertz impact on a rigid wall (or on an identical sphere, ``pair``, at
    closing speed ``v``): E*, m*, R*, the largest approach, peak force and contact time
    (Johnson, Contact Mechanics §11.4)."""
    e, nu, _ = MATERIALS[material]
    m = sphere_mass(material, radius)
    e_star, m_eff, r_eff = e / (1.0 - nu**2), m, radius
    if pair:
        e_star, m_eff, r_eff = e_star / 2.0, m / 2.0, radius / 2.0
    delta = (15.0 * m_eff * v**2 / (16.0 * e_star * math.sqrt(r_eff))) ** 0.4
    factor = 0.4 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)  # 1.4716
    return dict(
        e_star=e_star,
        m_eff=m_eff,
        r_eff=r_eff,
        delta=delta,
        force=4.0 / 3.0 * e_star * math.sqrt(r_eff) * delta**1.5,
        contact_time=2.0 * factor * delta / v,
    )


def hooke_stiffness(material: str, radius: float, v: float, pair: bool = False) -> float:
    """k_n [N/m] whose undamped contact lasts as long as the Hertz impact at ``v``
    (pi sqrt(m*/k_n) = t_c): the linear stand-in of tests 3, 6-8 (restitution as input)."""
    h = hertz_wall(material, radius, v, pair)
    return h["m_eff"] * (math.pi / h["contact_time"]) ** 2


def hooke_friction_impulse(e: float) -> float:
    """int |F_N| dt / int F_N dt of a head-on HOOKE impact with restitution ``e``.

    The HOOKE law is not clamped: near the end its dashpot pulls (F_N < 0), and Coulomb's limit
    mu |F_N| keeps acting, so a sliding contact receives mu times the *absolute* normal impulse.
    Over the half period of x = (v/w_d) e^{-z w_n t} sin(w_d t) the sphere's speed falls from v
    to its most negative u_1 (where the acceleration changes sign, w_d t_1 = pi +
    atan(2 a w_d / (a^2 - w_d^2)), a = z w_n) and rises back to -e v, so
    int |F| dt = m (v - u_1) + m (-e v - u_1) against the net m v (1 + e)."""
    if e >= 1.0:
        return 1.0
    le = math.log(e)
    zeta = -le / math.sqrt(math.pi**2 + le * le)
    wd = math.sqrt(1.0 - zeta * zeta)  # w_n = 1
    a = zeta
    t1 = (math.pi + math.atan(2.0 * a * wd / (a * a - wd * wd))) / wd
    u1 = math.exp(-a * t1) * (math.cos(wd * t1) - a / wd * math.sin(wd * t1))  # v = 1
    return ((1.0 - u1) + (-e - u1)) / (1.0 + e)


def sliding_beta(chi: float, e: float | None = None) -> float:
    """Gross sliding throughout the impact (rigid-body impulse law, sphere I = 2/5 m R^2):
    the contact point's slip v_s changes by -mu (1+e) v_n (1 + m R^2/I) = -chi v_s, so
    beta = -v_s'/v_s = chi - 1 (valid while the slip keeps its sign). Under the HOOKE law
    (``e`` given) the friction impulse is mu times the absolute normal impulse
    (:func:`hooke_friction_impulse`)."""
    return chi * (1.0 if e is None else hooke_friction_impulse(e)) - 1.0


# -- decks ------------------------------------------------------------------------------------


def _deck(title, *, radius, material, mu, dt, tmax, itrac, particles, triangle_x, hooke):
    e, nu, rho = MATERIALS[material]
    radius, mu, dt, tmax = float(radius), float(mu), float(dt), float(tmax)
    particles = [(float(x), tuple(map(float, v)), float(w)) for x, v, w in particles]
    hooke = None if hooke is None else tuple(map(float, hooke))
    half = 20.0 * radius
    lines = [
        "$ Chung & Ooi (2011) benchmark scene, written by tools/chung_ooi.py",
        "TITLE",
        title,
        "END",
        "UNITS",
        "   m N s",
        "END",
        "PARAMETERS",
        "$ TIME TMAX TREST DTMIN DTMAX INCR INCMAX IREST NINTPL ISTAT ITRAC",
        f"   0.0 {tmax!r} 0.0 {dt!r} {dt!r} 0 1e9 0 5 0 {itrac}",
        "END",
        "PDMP",
        "$ NODLIM RZERO PRHO PPOI E0 E1 T1 PCOF VX0 VY0 VZ0",
        f"   8 {radius!r} {rho!r} {nu!r} {e!r} 0.0 1.0 {mu!r} 0.0 0.0 0.0",
        "END",
        "TRACE",
        "   " + " ".join(str(9 + k) for k in range(len(particles))),
        "END",
        "NODE COORDINATES",
    ]
    corners = [(-half, -half), (half, -half), (half, half), (-half, half)]
    lines += [f"   {k + 1} {triangle_x!r} {y!r} {z!r}" for k, (y, z) in enumerate(corners)]
    lines += [f"   {9 + k} {x!r} 0.0 0.0" for k, (x, _, _) in enumerate(particles)]
    lines += [
        "END",
        "BOUNDARY CONDITIONS",
        "   1 4 1 1 2 3 4 5 6",
        "END",
        "CONTACT",
        "   1 1 2 3",
        "   1 1 3 4",
        "END",
        "   1 " + " ".join(str(9 + k) for k in range(len(particles))),
        "END",
        "INITIAL",
    ]
    lines += [
        f"   {9 + k} {v[0]!r} {v[1]!r} 0.0 0.0 0.0 {w!r}" for k, (_, v, w) in enumerate(particles)
    ]
    lines.append("END")
    if hooke is not None:
        lines += ["HOOKE", f"   8 {hooke[0]!r} {hooke[1]!r}", "END"]
    return "\n".join(lines) + "\n"


def wall_deck(
    material: str,
    radius: float,
    velocity,
    spin: float = 0.0,
    *,
    mu: float,
    dt: float,
    tmax: float,
    itrac: int = 1,
    hooke=None,
) -> str:
    """A sphere (node 9) touching the fixed flat wall x = 0 at t = 0 from x = R, with velocity
    (vx, vy) [m/s] (vx < 0: into the wall) and spin w_z [rad/s]; its contact point is at
    -R x, where it moves at v_y - R w_z. ``hooke``: (k_n, e) for the HOOKE law."""
    return _deck(
        f"Chung & Ooi: {material} sphere R {radius:g} m on a rigid plane",
        radius=radius,
        material=material,
        mu=mu,
        dt=dt,
        tmax=tmax,
        itrac=itrac,
        particles=[(radius, tuple(velocity), spin)],
        triangle_x=0.0,
        hooke=hooke,
    )


def pair_deck(
    material: str,
    radius: float,
    first,
    second,
    *,
    mu: float,
    dt: float,
    tmax: float,
    itrac: int = 1,
    hooke=None,
) -> str:
    """Two identical spheres touching at the origin at t = 0: node 9 at x = -R, node 10 at
    x = +R, each ((vx, vy), w_z); a far wall (x = -20 R) closes the cavity. Sphere 9's contact
    point moves at v_y + R w_z, sphere 10's at v_y - R w_z."""
    return _deck(
        f"Chung & Ooi: two {material} spheres R {radius:g} m",
        radius=radius,
        material=material,
        mu=mu,
        dt=dt,
        tmax=tmax,
        itrac=itrac,
        particles=[(-radius, tuple(first[0]), first[1]), (radius, tuple(second[0]), second[1])],
        triangle_x=-20.0 * radius,
        hooke=hooke,
    )


def run_deck(text: str, workdir: Path, name: str, friction: str = "mindlin"):
    """Write ``text`` to workdir/name.inp and run it (x3dpd.run): the RunResult."""
    path = Path(workdir) / f"{name}.inp"
    path.write_text(text)
    return x3dpd.run(path, friction=friction)


# -- the scenes of the tests, and what is measured -----------------------------------------------


def normal_impact(test: int, material: str, workdir, steps: int = STEPS_PER_CONTACT) -> dict:
    """Tests 1 (two spheres) and 2 (sphere on wall): peak force m dv/dt, largest approach and
    contact time of the run, with the Hertz closed form."""
    cfg = TESTS[test]
    r, v, pair = cfg["radius"], cfg["speed"], test == 1
    h = hertz_wall(material, r, 2.0 * v if pair else v, pair)
    dt = h["contact_time"] / steps
    tmax = 1.2 * h["contact_time"]
    if pair:
        text = pair_deck(material, r, ((v, 0.0), 0.0), ((-v, 0.0), 0.0), mu=0.0, dt=dt, tmax=tmax)
    else:
        text = wall_deck(material, r, (-v, 0.0), mu=0.0, dt=dt, tmax=tmax)
    res = run_deck(text, workdir, f"test{test}", friction="regularized")
    t = res.trace.time
    x = res.trace.position[:, 0, 0]
    vx = res.trace.velocity[:, 0, 0]
    m = sphere_mass(material, r)
    force = m * np.abs(np.diff(vx) / np.diff(t))
    approach = 2.0 * r - (res.trace.position[:, 1, 0] - x) if pair else r - x
    k = int(np.flatnonzero((approach[:-1] > 0) & (approach[1:] <= 0))[0])
    t_end = t[k] + approach[k] / (approach[k] - approach[k + 1]) * (t[k + 1] - t[k])
    return dict(
        force=_refined_peak(force),
        delta=_refined_peak(approach),
        contact_time=t_end,
        reference=h,
        dt=dt,
    )


def restitution(material: str, e_in: float, workdir, steps: int = STEPS_PER_CONTACT) -> float:
    """Test 3: the normal restitution v_out/v_in of a HOOKE impact with input ``e_in``."""
    cfg = TESTS[3]
    r, v = cfg["radius"], cfg["speed"]
    kn = hooke_stiffness(material, r, v)
    t_c = hertz_wall(material, r, v)["contact_time"]
    text = wall_deck(
        material, r, (-v, 0.0), mu=0.0, dt=t_c / steps, tmax=1.3 * t_c, itrac=1, hooke=(kn, e_in)
    )
    res = run_deck(text, workdir, "test3", friction="regularized")
    return float(res.trace.velocity[-1, 0, 0] / v)


def oblique_wall(
    test: int,
    material: str,
    vn: float,
    vt: float,
    spin: float,
    workdir,
    steps: int = STEPS_PER_CONTACT,
    friction: str = "mindlin",
) -> dict:
    """Tests 4-6: a sphere at normal speed ``vn``, tangential ``vt`` (centre) and spin w_z on
    the plane; returns the velocities after the impact: vn' (> 0: away), vt', w_z', and the
    contact point's tangential speeds before and after (v_t - R w_z)."""
    cfg = TESTS[test]
    r = cfg["radius"]
    h = hertz_wall(material, r, vn)
    hooke = None if cfg["e"] is None else (hooke_stiffness(material, r, vn), cfg["e"])
    t_c = h["contact_time"]
    text = wall_deck(
        material,
        r,
        (-vn, vt),
        spin,
        mu=cfg["mu"],
        dt=t_c / steps,
        tmax=1.3 * t_c,
        itrac=1,
        hooke=hooke,
    )
    res = run_deck(text, workdir, f"test{test}", friction=friction)
    vx, vy = res.trace.velocity[-1, 0, :2]
    wz = res.trace.spin[-1, 0, 2]
    return dict(
        vn=float(vx),
        vt=float(vy),
        spin=float(wz),
        slip_in=vt - r * spin,
        slip_out=float(vy - r * wz),
        radius=r,
    )


def oblique_pair(
    test: int,
    material: str,
    first,
    second,
    workdir,
    steps: int = STEPS_PER_CONTACT,
    friction: str = "mindlin",
) -> dict:
    """Tests 7-8: two spheres ((vx, vy), w_z each); the slip of sphere 9's contact point
    relative to sphere 10's before and after, and both spheres' final (vy, w_z)."""
    cfg = TESTS[test]
    r = cfg["radius"]
    closing = first[0][0] - second[0][0]
    h = hertz_wall(material, r, closing, pair=True)
    hooke = (
        None if cfg["e"] is None else (hooke_stiffness(material, r, closing, pair=True), cfg["e"])
    )
    t_c = h["contact_time"]
    text = pair_deck(
        material,
        r,
        first,
        second,
        mu=cfg["mu"],
        dt=t_c / steps,
        tmax=1.3 * t_c,
        itrac=1,
        hooke=hooke,
    )
    res = run_deck(text, workdir, f"test{test}", friction=friction)
    v = res.trace.velocity[-1, :, :2]
    w = res.trace.spin[-1, :, 2]

    def slip(v1y, w1, v2y, w2):
        return (v1y + r * w1) - (v2y - r * w2)

    return dict(
        slip_in=slip(first[0][1], first[1], second[0][1], second[1]),
        slip_out=float(slip(v[0, 1], w[0], v[1, 1], w[1])),
        vn=float(v[1, 0] - v[0, 0]),
        vt=tuple(map(float, v[:, 1])),
        spin=tuple(map(float, w)),
        radius=r,
    )


def test4_point(material: str, angle: float, workdir, steps: int = STEPS_PER_CONTACT) -> tuple:
    """Test 4 at ``angle`` [deg] from the normal, 3.9 m/s: (tangential restitution
    vt'/vt, final spin in Kratos's sign (-w_z) [rad/s], rebound angle of the contact point
    atan(slip'/vn') [deg])."""
    v = TESTS[4]["speed"]
    vn, vt = v * math.cos(math.radians(angle)), v * math.sin(math.radians(angle))
    out = oblique_wall(4, material, vn, vt, 0.0, workdir, steps)
    return (out["vt"] / vt, -out["spin"], math.degrees(math.atan(out["slip_out"] / out["vn"])))


def test5_point(material: str, x: float, workdir, steps: int = STEPS_PER_CONTACT) -> float:
    """Test 5 at v_t/(mu v_n) = ``x`` (5 m/s normal): the final spin -R w'/(mu v_n)."""
    cfg = TESTS[5]
    vn = cfg["speed"]
    out = oblique_wall(5, material, vn, x * cfg["mu"] * vn, 0.0, workdir, steps)
    return -out["radius"] * out["spin"] / (cfg["mu"] * vn)


def chi_of(test: int, slip: float) -> float:
    cfg = TESTS[test]
    return 3.5 * cfg["mu"] * (1.0 + cfg["e"]) * cfg["speed"] / slip


def test6_point(material: str, chi: float, workdir, steps: int = STEPS_PER_CONTACT) -> float:
    """Test 6: a spinning sphere (centre at rest tangentially) at 0.2 m/s on the plane, the
    slip chosen for chi = 3.5 mu (1+e) v_n / v_s; returns beta = -v_s'/v_s."""
    cfg = TESTS[6]
    slip = 3.5 * cfg["mu"] * (1.0 + cfg["e"]) * cfg["speed"] / chi
    out = oblique_wall(6, material, cfg["speed"], 0.0, -slip / cfg["radius"], workdir, steps)
    return -out["slip_out"] / out["slip_in"]


def test7_point(material: str, spin: float, workdir, steps: int = STEPS_PER_CONTACT) -> dict:
    """Test 7: two spheres closing at 2 x 0.2 m/s with spins w and -w about z (their contact
    points move together: no slip); returns the final spins and tangential velocities."""
    v = TESTS[7]["speed"]
    return oblique_pair(7, material, ((v, 0.0), spin), ((-v, 0.0), -spin), workdir, steps)


def test8_point(material: str, chi: float, workdir, steps: int = STEPS_PER_CONTACT) -> float:
    """Test 8: a spinning sphere at 0.2 m/s onto an identical one at rest, the slip chosen for
    chi; returns beta = -v_s'/v_s of the relative slip."""
    cfg = TESTS[8]
    slip = 3.5 * cfg["mu"] * (1.0 + cfg["e"]) * cfg["speed"] / chi
    out = oblique_pair(
        8, material, ((cfg["speed"], 0.0), slip / cfg["radius"]), ((0.0, 0.0), 0.0), workdir, steps
    )
    return -out["slip_out"] / out["slip_in"]


def mean_relative_error(values, reference) -> float:
    """Kratos's measure: sum |x - x_ref| / sum |x_ref|."""
    values, reference = np.asarray(values, float), np.asarray(reference, float)
    return float(np.sum(np.abs(values - reference)) / np.sum(np.abs(reference)))


def _refined_peak(y) -> float:
    """Peak of samples refined by the parabola through the largest sample and its neighbours."""
    y = np.asarray(y)
    k = int(np.argmax(y))
    a, b, c = y[k - 1], y[k], y[k + 1]
    return float(b + (a - c) ** 2 / (8.0 * (2.0 * b - a - c)))


# -- commands ---------------------------------------------------------------------------------


def write_decks(outdir: Path) -> list[Path]:
    """One deck per test and material at the first point of its sweep (docstring)."""
    outdir.mkdir(parents=True, exist_ok=True)
    written = []
    for test, cfg in TESTS.items():
        for material in cfg["materials"]:
            r, v = cfg["radius"], cfg["speed"]
            pair = test in (1, 7, 8)
            t_c = hertz_wall(material, r, 2.0 * v if test in (1, 7) else v, pair)["contact_time"]
            dt, tmax = t_c / STEPS_PER_CONTACT, 1.3 * t_c
            kw = dict(mu=cfg["mu"], dt=dt, tmax=tmax, itrac=1)
            if test in (1, 7):
                w = 0.0 if test == 1 else v / r * math.tan(math.radians(5.0))
                hooke = (
                    None
                    if cfg["e"] is None
                    else (hooke_stiffness(material, r, 2.0 * v, True), cfg["e"])
                )
                text = pair_deck(material, r, ((v, 0.0), w), ((-v, 0.0), -w), hooke=hooke, **kw)
            elif test == 8:
                slip = 3.5 * cfg["mu"] * (1.0 + cfg["e"]) * v / T8_CHI[0]
                text = pair_deck(
                    material,
                    r,
                    ((v, 0.0), slip / r),
                    ((0.0, 0.0), 0.0),
                    hooke=(hooke_stiffness(material, r, v, True), cfg["e"]),
                    **kw,
                )
            else:
                hooke = (
                    None
                    if cfg["e"] is None
                    else (hooke_stiffness(material, r, v), cfg["e"] if test != 3 else 0.5)
                )
                angle = math.radians(T4_ANGLES[0]) if test == 4 else 0.0
                vt = (
                    v * math.sin(angle)
                    if test == 4
                    else T5_X[0] * cfg["mu"] * v
                    if test == 5
                    else 0.0
                )
                vn = v * math.cos(angle)
                spin = -3.5 * cfg["mu"] * 1.5 * v / 0.3 / r if test == 6 else 0.0
                text = wall_deck(material, r, (-vn, vt), spin, hooke=hooke, **kw)
            name = f"test{test}_{material.split(' (')[0].replace(' ', '_')}.inp"
            (outdir / name).write_text(text)
            written.append(outdir / name)
    return written


def main(argv: list[str]) -> int:
    if len(argv) >= 2 and argv[0] == "decks":
        for p in write_decks(Path(argv[1])):
            print(p)
        return 0
    if argv and argv[0] in ("plots", "convergence"):
        from chung_ooi_plots import convergence_table, make_plots  # tools/chung_ooi_plots.py

        return make_plots(ROOT / "docs" / "img") if argv[0] == "plots" else convergence_table()
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    raise SystemExit(main(sys.argv[1:]))
