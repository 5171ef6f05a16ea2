"""The CAPSULE card through the public interfaces: bad cards and cross references as
FILE:LINE:COL errors, ``x3dpd check`` (the capsule, its volume, the particles' clearances, the
warnings and the start refusal for spheres outside or in the wall), the deck writer, and a
deck with a cylinder and a capsule cavity side by side: it runs, each sphere stays in its own
cavity, and a restart continues it bit for bit."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from cli_helpers import first_record_line, run_cli, with_card
from factories import CAVITY_BIG_R, CAVITY_LENGTH, CAVITY_R, small_cylinder_deck

from x3dpd.api import safety as x3dpd_safety
from x3dpd.deck import parse_deck
from x3dpd.deck.cards import AnalyticWall, Contact, Initial, Node, Rbel, SlaveSet, Trace
from x3dpd.deck.generate import Material3
from x3dpd.deck.writer import format_deck
from x3dpd.errors import DeckError
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model
from x3dpd.model.check_shapes import shape_clearances
from x3dpd.solver.simulation import Simulation

STEEL = Material3(27.5e6, 0.0, 1.0, 0.3, 0.0, 7.32971e-4)
R, BIG_R, LENGTH = CAVITY_R, CAVITY_BIG_R, CAVITY_LENGTH


def _deck(pos, vel=None, *, dt=5e-7, shape="capsule"):
    return small_cylinder_deck(pos, vel, material=STEEL, dt=dt, shape=shape)


def _text(pos, vel=None, *, dt=5e-7):
    return format_deck(_deck(pos, vel, dt=dt))


@pytest.mark.parametrize(
    "card, message, column",
    [
        ("CAPSULE\n 1 2 3\nEND", "CAPSULE needs 4 values", None),
        ("CAPSULE\n 1 2 3 -0.2\nEND", "RADIUS must be > 0", 8),
        ("CAPSULE\n 1 2 3 0\nEND", "RADIUS must be > 0", 8),
        ("CAPSULE\n 1 2 2 0.2\nEND", "NODE_B must differ from NODE_A", 6),
    ],
)
def test_bad_capsule_records_are_deck_errors_at_the_field(card, message, column):
    text = with_card(_text([[0.15, 0.0, 0.0]]), card)
    with pytest.raises(DeckError, match=message) as err:
        parse_deck(text, "deck.inp")
    assert err.value.card == "CAPSULE"
    line = first_record_line(text, "CAPSULE")
    assert err.value.line == line
    assert str(err.value).startswith(f"deck.inp:{line}:")
    if column is not None:
        assert err.value.column == column


@pytest.mark.parametrize(
    "card, message, column",
    [
        ("CAPSULE\n 1 2 99 0.2\nEND", "axis node B 99 is not defined", 6),
        ("CAPSULE\n 1 99 3 0.2\nEND", "axis node A 99 is not defined", 4),
        ("CAPSULE\n 1 2 5 0.2\nEND", "axis node B 5 is a particle node", 6),
    ],
)
def test_bad_capsule_references_are_deck_errors_at_the_node(card, message, column):
    """The error points at the offending node id's field (1-based column)."""
    text = with_card(_text([[0.15, 0.0, 0.0], [0.15, 0.1, 0.0]]), card)
    with pytest.raises(DeckError, match=message) as err:
        build_model(parse_deck(text, "deck.inp"))
    assert err.value.card == "CAPSULE"
    line = first_record_line(text, "CAPSULE")
    assert err.value.line == line
    assert err.value.column == column
    assert str(err.value).startswith(f"deck.inp:{line}:{column}: ")


def test_a_slave_set_without_triangles_or_capsule_is_a_deck_error():
    # the capsule names set 7; the particles' set 1 then has no wall at all
    text = with_card(_text([[0.15, 0.0, 0.0]]), "CAPSULE\n 7 2 3 0.2\nEND")
    with pytest.raises(
        DeckError,
        match="slave set 1 has no master triangles and no "
        r"CYLINDER or CAPSULE or HOLES \(.*set ids 7\)",
    ) as err:
        build_model(parse_deck(text, "deck.inp"))
    assert err.value.card == "CONTACT" and err.value.line > 0 and err.value.column > 0


def test_axis_nodes_must_move_as_one_rigid_cavity():
    text = _text([[0.15, 0.0, 0.0]])
    # node 3 leaves the rigid body (RBEL lists 2 and 3; keep only 2) and is free
    assert "   1 123456 2 2 3\n" in text
    text = text.replace("   1 123456 2 2 3\n", "   1 123456 1 2\n")
    with pytest.raises(DeckError, match="axis nodes 2 and 3 must move as one rigid cavity") as err:
        build_model(parse_deck(text, "deck.inp"))
    assert err.value.card == "CAPSULE"
    line = text.index("   1 2 3 0.2\n")
    assert err.value.line == text[:line].count("\n") + 1 and err.value.column > 0


# --- x3dpd check ----------------------------------------------------------------------------

#: One sphere 0.01 deep in the cylindrical wall (0.32 R, beyond the 0.25 R refusal limit), one
#: with its centre 0.21 from B (outside the rounded end), one beyond B but inside the
#: hemisphere (outside a flat-capped cylinder: must not be flagged), one clean on the axis.
CHECK_POS = [
    [0.15, BIG_R - R + 0.01, 0.0],
    [LENGTH + 0.21, 0.0, 0.0],
    [LENGTH + 0.1, 0.05, 0.0],
    [0.15, 0.0, 0.0],
]


def _check_text():
    text = _text([[0.15, 0.0, 0.0]] * len(CHECK_POS))
    for k, p in enumerate(CHECK_POS):
        old = f"   {4 + k} 0.15 0.0 0.0\n"
        assert old in text
        text = text.replace(old, f"   {4 + k} {p[0]!r} {p[1]!r} {p[2]!r}\n", 1)
    return text


def _distances():
    """Each CHECK_POS centre's distance to the axis segment (0,0,0)-(LENGTH,0,0), by hand."""
    return np.array([BIG_R - R + 0.01, 0.21, math.hypot(0.1, 0.05), 0.0])


def test_check_reports_the_capsule_its_volume_and_the_clearances():
    """The summary names the capsule with its radius and cap distance, the cavity's volume
    is pi R^2 L + 4/3 pi R^3 (a few operations: 1e-12), each particle's clearance is
    R - dist - r (dist by construction; 1e-12) and the smallest is printed."""
    model = build_model(parse_deck(_check_text(), "deck.inp"))
    report = check_model(model)
    (cav,) = report.cavities
    assert cav.volume == pytest.approx(
        math.pi * BIG_R**2 * LENGTH + 4.0 / 3.0 * math.pi * BIG_R**3, rel=1e-12
    )
    want = BIG_R - _distances() - R
    (wall,) = cav.analytic_walls
    assert wall == (
        f"the capsule on axis nodes 2, 3 (radius 0.2, 0.3 between the cap "
        f"centres); smallest particle clearance {want.min():.6g}"
    )
    found = sorted(shape_clearances(model), key=lambda f: f.node_id)
    assert [f.node_id for f in found] == [4, 5, 6, 7]
    np.testing.assert_allclose([f.gap for f in found], want, atol=1e-12)
    assert [f.inside for f in found] == [True, False, True, True]
    assert "capsule_contact" in report.effects


def test_check_flags_spheres_outside_and_in_the_wall(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a run writes its outputs to the working directory
    text = _check_text()
    report = check_model(build_model(parse_deck(text, "deck.inp")))
    codes = {w.code: w for w in report.warnings}
    where = "the capsule on axis nodes 2, 3 (radius 0.2, 0.3 between the cap centres)"
    assert codes["particles-outside"].details == (f"particle node 5: centre outside {where}",)
    assert codes["wall-penetration"].details == (f"particle node 4: 0.01 (0.32 R) into {where}",)
    path = tmp_path / "bad.inp"
    path.write_text(text)
    capsys.readouterr()
    assert run_cli("check", path) == 1
    out = capsys.readouterr().out
    assert f"particle node 5: centre outside {where}" in out
    assert "interior volume 0.0712094" in out  # pi 0.04 0.3 + 4/3 pi 0.008
    assert run_cli(path, "--quiet") == 2  # refused: the run would blow up
    assert not list(tmp_path.glob("bad.*trace*"))  # nothing ran, nothing written


def test_the_run_refuses_only_a_sphere_in_the_wall(tmp_path, monkeypatch):
    """Without the sphere outside, the one 0.32 R deep in the wall alone refuses the start;
    a sphere beyond a cap centre but inside the rounded end is not refused."""
    monkeypatch.chdir(tmp_path)  # a run writes its outputs to the working directory
    text = _text([[0.15, 0.0, 0.0]])
    assert "   4 0.15 0.0 0.0\n" in text
    text = text.replace("   4 0.15 0.0 0.0\n", f"   4 0.15 {BIG_R - R + 0.01!r} 0.0\n")
    (tmp_path / "deep.inp").write_text(text)
    assert run_cli(tmp_path / "deep.inp", "--tmax", 1e-5, "--quiet") == 2
    assert not list(tmp_path.glob("deep.*trace*"))
    # a sphere beyond B but inside the rounded end is fine (a cylinder would refuse it): the
    # start's refusal and `x3dpd check` judge it by the same clearance, and check is clean
    # (the run itself is the side-by-side test's; not compiling another loop here keeps the
    # suite short)
    (tmp_path / "ok.inp").write_text(_text([[LENGTH + 0.1, 0.05, 0.0]]))
    assert run_cli("check", tmp_path / "ok.inp") == 0
    model = build_model(parse_deck((tmp_path / "ok.inp").read_text(), "ok.inp"))
    assert x3dpd_safety.initial_penetration_error(model, 0.25, "ok.inp") is None  # the default


def test_deck_writer_round_trips_a_capsule_card():
    deck = _deck([[0.15, 0.0, 0.0]])
    text = format_deck(deck)
    assert "\nCAPSULE\n$ SET NODE_A NODE_B RADIUS\n   1 2 3 0.2\nEND\n" in text
    again = parse_deck(text, "deck.inp")
    (wall,) = again.analytic_walls
    assert (wall.shape, wall.set_id, wall.nodes, wall.params) == ("capsule", 1, (2, 3), (0.2,))
    assert format_deck(again) == text


# --- a cylinder and a capsule side by side ---------------------------------------------------

#: The capsule's axis, 1 in above the cylinder's (0,0,0)-(LENGTH,0,0) along y.
CAP_A = np.array([0.0, 1.0, 0.0])
CAP_B = np.array([LENGTH, 1.0, 0.0])
TWO_POS = np.array([[0.15, 0.05, 0.0], [0.1, 1.0, 0.05], [0.25, 0.95, -0.05]])
TWO_VEL = np.array([[25.0, 30.0, -10.0], [45.0, 10.0, 5.0], [-40.0, 0.0, 20.0]])


def _two_cavities(tmax=1.0):
    """Nodes 1 master, 2-3 the cylinder's axis, 4-5 the capsule's, all rigid with 1; sphere 6
    in the cylinder (slave set 1), 7 and 8 in the capsule (set 2)."""
    base = _deck(TWO_POS[:1], TWO_VEL[:1], shape="cylinder")
    nodes = list(base.nodes[:3]) + [Node(4, *CAP_A), Node(5, *CAP_B)]
    nodes += [Node(6 + k, *map(float, p)) for k, p in enumerate(TWO_POS)]
    (rbel,) = base.rbels
    return dataclasses.replace(
        base,
        nodes=tuple(nodes),
        pdmp=(dataclasses.replace(base.pdmp[0], nodlim=5),),
        rbels=(Rbel(rbel.master, rbel.dofs, (2, 3, 4, 5)),),
        contacts=(Contact((), (SlaveSet(1, (6,)), SlaveSet(2, (7, 8)))),),
        analytic_walls=(
            AnalyticWall("cylinder", 1, (2, 3), (BIG_R,)),
            AnalyticWall("capsule", 2, (4, 5), (BIG_R,)),
        ),
        initials=tuple(Initial(6 + k, tuple(map(float, v))) for k, v in enumerate(TWO_VEL)),
        trace=Trace((1, 6, 7, 8)),
        parameters=dataclasses.replace(base.parameters, tmax=tmax),
    )


def test_a_cylinder_and_a_capsule_cavity_run_side_by_side():
    """Both walls act, each on its own set: the cylinder's sphere stays between its flat caps
    (0 <= x - r, x + r <= L) and within its radius; the capsule's spheres stay within R - r of
    their segment and one of them goes beyond the flat ends' planes into a rounded end (where
    the cylinder's cap would have stopped it). Containment to the deepest Hertz overlap
    possible: a_max of a head-on impact at the largest speed any sphere can reach (equal
    masses, elastic contacts: at most the total kinetic energy, sqrt(sum v^2)); Hertz:
    1/2 m v^2 = 2/5 K a^(5/2), K = 4/3 E* sqrt(r), E* = E / (1 - nu^2)."""
    deck = _two_cavities()
    text = format_deck(deck)
    assert "\nCYLINDER\n" in text and "\nCAPSULE\n" in text
    model = build_model(parse_deck(text, "two.inp"))
    assert {"cylinder_contact", "capsule_contact"} <= model.effects
    sim = Simulation(model)
    block = sim.advance(40_000)  # 0.02 s: several impacts each
    x = block.data[:, 1:, :3]
    e_star = STEEL.e0 / (1.0 - STEEL.nu**2)
    v_max = math.sqrt((TWO_VEL**2).sum())
    mass = 4.0 / 3.0 * math.pi * R**3 * STEEL.density
    a_max = (5.0 * mass * v_max**2 / (4.0 * 4.0 / 3.0 * e_star * math.sqrt(R))) ** 0.4
    cyl = x[:, 0]
    rho = np.hypot(cyl[:, 1], cyl[:, 2])
    assert rho.max() + R - BIG_R <= a_max
    assert -cyl[:, 0].min() + R <= a_max and cyl[:, 0].max() + R - LENGTH <= a_max
    assert rho.max() + R - BIG_R > -0.1 * R  # it did reach its curved wall
    for k in (1, 2):
        p = x[:, k]
        t = np.clip((p[:, 0] - CAP_A[0]) / LENGTH, 0.0, 1.0)
        dist = np.linalg.norm(p - CAP_A - t[:, None] * (CAP_B - CAP_A), axis=1)
        assert dist.max() + R - BIG_R <= a_max, k
    capsule_x = x[:, 1:, 0]
    assert capsule_x.max() + R > LENGTH + 0.05 or capsule_x.min() - R < -0.05
    # and the cylinder's sphere never went where only the capsule reaches
    assert np.all(np.abs(x[:, 0, 1]) < 0.5) and np.all(np.abs(x[:, 1:, 1] - 1.0) < 0.5)


def test_restart_continues_the_two_cavity_deck_bit_for_bit(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "c.inp").write_text(format_deck(_two_cavities()))
    assert run_cli("c.inp", "--tmax", 0.004, "--trace", "whole.trace.txt", "--quiet") == 0
    assert run_cli("c.inp", "--tmax", 0.002, "--trace", "part.trace.txt", "--quiet") == 0
    assert (
        run_cli("c.inp", "--tmax", 0.004, "--trace", "part.trace.txt", "--restart", "--quiet") == 0
    )
    whole = (tmp_path / "whole.trace.txt").read_bytes()
    assert (tmp_path / "part.trace.txt").read_bytes() == whole
    rows = np.loadtxt(tmp_path / "whole.trace.txt", delimiter=";")
    assert rows[-1, 0] == pytest.approx(0.004, rel=1e-12)
