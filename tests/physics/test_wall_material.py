"""Compliant walls (WALLMAT card, x3dpd.physics.wall_material): a head-on impact on an elastic
wall is Hertz's with the mixed modulus, its friction is the wall's, `x3dpd check` reports it,
and bad records are refused at their place.

Expected values are closed forms evaluated here (Johnson, *Contact Mechanics* §11.4; the brief's
t_c = 2.87 (m*^2/(R* E*^2 v))^(1/5) with the exact constant 2.868):
1/E* = (1-nu_p^2)/E_p + (1-nu_w^2)/E_w, delta_max = (15 m v^2 / (16 E* R^1/2))^(2/5),
F_max = 4/3 E* R^1/2 delta_max^3/2.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from click.testing import CliRunner

import x3dpd
from x3dpd.cli.check import check

# the report's Figure 28 sphere (decks/impact_wall.inp): steel, R 0.0625 in, 62.832 in/s
R, E_P, NU_P, RHO, V = 0.0625, 3.0e7, 0.33, 0.283 / 386.1, 62.832
M = RHO * 4.0 / 3.0 * math.pi * R**3
# the walls: acrylic 3.2 GPa = 4.64e5 psi, nu 0.35; aluminium 6061 68.9 GPa = 1.0e7 psi, nu 0.33
WALLS = {"acrylic": (4.64e5, 0.35), "aluminium": (1.0e7, 0.33)}

DECK = """TITLE
sphere on a compliant wall
END
PARAMETERS
   0.0 {tmax} 0.0 {dt} {dt} 0 1e9 0 5 0 1
END
PDMP
   8 0.0625 0.0007329707329707328 0.33 30000000.0 0.0 1.0 {pcof} {vx} {vy} 0.0
END
TRACE
   9
END
NODE COORDINATES
   1 0.0 -0.25 -0.25
   2 0.0 0.25 -0.25
   3 0.0 0.25 0.25
   4 0.0 -0.25 0.25
   9 0.0625 0.0 0.0
END
BOUNDARY CONDITIONS
   1 4 1 1 2 3 4 5 6
END
CONTACT
   1 1 2 3
   1 1 3 4
END
   1 9
END
{extra}"""


def _closed_form(e_w: float, nu_w: float) -> tuple[float, float, float]:
    """(E*, t_c, F_max) of the head-on impact on a wall (E_w, nu_w); E_w = inf: rigid."""
    e_star = 1.0 / ((1.0 - NU_P**2) / E_P + (0.0 if math.isinf(e_w) else (1.0 - nu_w**2) / e_w))
    t_c = (
        2.0
        * (0.4 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9))
        * (15.0 / 16.0) ** 0.4
        * (M**2 / (R * e_star**2 * V)) ** 0.2
    )
    delta = (15.0 * M * V**2 / (16.0 * e_star * math.sqrt(R))) ** 0.4
    return e_star, t_c, 4.0 / 3.0 * e_star * math.sqrt(R) * delta**1.5


def _deck(tmp_path, name, *, dt, tmax, extra="", pcof=0.0, vx=-V, vy=0.0):
    path = tmp_path / f"{name}.inp"
    path.write_text(DECK.format(dt=dt, tmax=tmax, extra=extra, pcof=pcof, vx=vx, vy=vy))
    return path


def _refined_peak(y: np.ndarray) -> float:
    """Peak of samples refined by the parabola through the largest sample and its neighbours."""
    k = int(np.argmax(y))
    a, b, c = y[k - 1], y[k], y[k + 1]
    return b + (a - c) ** 2 / (8.0 * (2.0 * b - a - c))


@pytest.mark.parametrize("wall", sorted(WALLS))
def test_head_on_impact_on_a_compliant_wall_is_hertz_with_the_mixed_modulus(tmp_path, wall):
    """Peak force and contact time to 1e-3 at 2000 steps per contact (Verlet's error there is
    ~(pi/2000)^2 ~ 2.5e-6; the force is m dv/dt by central differences of the traced velocity)."""
    e_w, nu_w = WALLS[wall]
    _, t_c, f_max = _closed_form(e_w, nu_w)
    rigid_tc = _closed_form(math.inf, 0.0)[1]
    assert t_c > 1.2 * rigid_tc  # the wall matters: a rigid-wall answer fails the test
    dt = t_c / 2000
    path = _deck(
        tmp_path, wall, dt=dt, tmax=1.2 * t_c, extra=f"WALLMAT\n   1 {e_w!r} {nu_w!r} 0.0\nEND\n"
    )
    res = x3dpd.run(path, itrac=1)
    t = res.trace.time
    x = res.trace.position[:, 0, 0]
    vx = res.trace.velocity[:, 0, 0]
    force = M * np.diff(vx) / np.diff(t)  # at the half steps
    peak = _refined_peak(force)
    approach = R - x
    k = int(np.flatnonzero((approach[:-1] > 0) & (approach[1:] <= 0))[0])
    t_end = t[k] + approach[k] / (approach[k] - approach[k + 1]) * (t[k + 1] - t[k])
    assert peak == pytest.approx(f_max, rel=1e-3)
    assert t_end == pytest.approx(t_c, rel=1e-3)
    assert vx[-1] == pytest.approx(V, rel=1e-3)  # elastic: no loss


def test_check_reports_the_wall_and_the_mixed_contact_time(tmp_path):
    e_w, nu_w = WALLS["acrylic"]
    e_star, t_c, _ = _closed_form(e_w, nu_w)
    path = _deck(
        tmp_path, "check", dt=1e-9, tmax=1e-5, extra=f"WALLMAT\n   1 {e_w!r} {nu_w!r} 0.25\nEND\n"
    )
    advice = x3dpd.check(path).time_step
    assert advice.t_contact == pytest.approx(t_c, rel=1e-9)
    out = CliRunner().invoke(check, [str(path)]).output
    assert "wall material (WALLMAT): E 464000 psi, NU 0.35, MU 0.25" in out
    assert f"contact E* group 1 {e_star:.6g} psi" in out
    assert f"lasts {t_c:.3g} s" in out
    rigid = _deck(tmp_path, "rigid", dt=1e-9, tmax=1e-5)
    assert "WALLMAT" not in CliRunner().invoke(check, [str(rigid)]).output


@pytest.mark.parametrize("friction", ["coulomb", "mindlin"])
def test_the_walls_friction_coefficient_is_the_contacts(tmp_path, friction):
    """Gross sliding on the wall: v_t' = v_t - mu (1 + e)(1 + m R^2/I) v_n (e = 1, I = 2/5 m R^2)
    with the wall's MU 0.1, not the particle's PCOF 0.4. At 80 degrees the contact slides
    throughout (v_t > 3.5 mu (1+e) v_n): Coulomb's law exactly, and Hertz-Mindlin (whose wall
    mu_k is MU too) once its spring has built up, within 1e-3."""
    mu_w, speed = 0.1, V
    vn, vt = speed * math.cos(math.radians(80)), speed * math.sin(math.radians(80))
    e_w, nu_w = WALLS["aluminium"]
    _, t_c, _ = _closed_form(e_w, nu_w)
    path = _deck(
        tmp_path,
        "slide",
        dt=t_c / 2000,
        tmax=1.5 * t_c,
        pcof=0.4,
        vx=-vn,
        vy=vt,
        extra=f"WALLMAT\n   1 {e_w!r} {nu_w!r} {mu_w!r}\nEND\n",
    )
    res = x3dpd.run(path, friction=friction, itrac=100)
    vy_end = res.trace.velocity[-1, 0, 1]
    # the centre loses mu (1+e) v_n of tangential speed; the contact point (at -R x) moves at
    # v_y - R w_z, and loses (1 + m R^2/I) = 3.5 times as much
    assert vy_end == pytest.approx(vt - mu_w * 2.0 * vn, rel=1e-3)
    spin = res.trace.spin[-1, 0, 2]
    assert vy_end - R * spin == pytest.approx(vt - 3.5 * mu_w * 2.0 * vn, rel=1e-3)


@pytest.mark.parametrize(
    "record, col, phrase",
    [
        (
            "   7 1e7 0.3 0.1",
            4,
            "set 7 has no walls (the CONTACT triangles and analytic walls use set ids 1)",
        ),
        ("   1 -1e7 0.3 0.1", 6, "E (the wall's Young's modulus) must be > 0; got -1e7"),
        ("   1 1e7 0.5 0.1", 10, "NU (the wall's Poisson's ratio) must lie in (-1, 0.5); got 0.5"),
        ("   1 1e7 0.3 -0.1", 14, "MU (the wall's friction coefficient) must be >= 0; got -0.1"),
        ("   1 1e7 0.3", 4, "WALLMAT needs 4 values: SET E NU MU; got 3"),
    ],
)
def test_bad_records_are_refused_at_their_place(tmp_path, record, col, phrase):
    path = _deck(tmp_path, "bad", dt=1e-9, tmax=1e-5, extra=f"WALLMAT\n{record}\nEND\n")
    line = DECK.count("\n") + 2
    with pytest.raises(x3dpd.DeckError) as err:
        x3dpd.build(x3dpd.load_deck(path))
    assert str(err.value) == f"{path}:{line}:{col}: WALLMAT: {phrase}"
    out = CliRunner().invoke(check, [str(path)])
    assert out.exit_code == 2 and phrase in out.output and "Traceback" not in out.output


def test_a_set_given_twice_and_the_hooke_law_are_refused(tmp_path):
    path = _deck(
        tmp_path,
        "twice",
        dt=1e-9,
        tmax=1e-5,
        extra="WALLMAT\n   1 1e7 0.3 0.1\n   1 2e7 0.3 0.1\nEND\n",
    )
    line = DECK.count("\n") + 3
    with pytest.raises(
        x3dpd.DeckError,
        match=rf":{line}:4: WALLMAT: set 1 is given twice "
        rf"\(first at line {line - 1}\)",
    ):
        x3dpd.build(x3dpd.load_deck(path))
    path = _deck(
        tmp_path,
        "hooke",
        dt=1e-9,
        tmax=1e-5,
        extra="HOOKE\n   8 1e4 0.9\nEND\nWALLMAT\n   1 1e7 0.3 0.1\nEND\n",
    )
    with pytest.raises(x3dpd.DeckError, match="WALLMAT: the HOOKE law gives its wall stiffness"):
        x3dpd.build(x3dpd.load_deck(path))


def test_wallmat_round_trips_and_leaves_old_decks_keys_alone(tmp_path):
    from x3dpd.api.outputs import deck_key
    from x3dpd.deck import format_deck, parse_deck

    plain = parse_deck(DECK.format(dt=1e-9, tmax=1e-5, extra="", pcof=0.0, vx=-V, vy=0.0))
    soft = parse_deck(
        DECK.format(
            dt=1e-9,
            tmax=1e-5,
            pcof=0.0,
            vx=-V,
            vy=0.0,
            extra="wallmaterial\n 1, 4.64e5, .35, 0.25 $ acrylic\nEND\n",
        )
    )
    again = parse_deck(format_deck(soft))
    assert [(m.set_id, m.e, m.nu, m.mu) for m in again.wallmat] == [(1, 4.64e5, 0.35, 0.25)]
    assert deck_key(again) == deck_key(soft) != deck_key(plain)
    assert plain.wallmat is None
