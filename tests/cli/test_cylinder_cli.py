"""The CYLINDER card through the public interfaces: bad cards and cross references as
FILE:LINE:COL errors, ``x3dpd check`` and the start refusal for spheres outside or in the wall,
the solver's stops naming the cylinder, and a restart of decks/cylinder_64.inp continuing bit
for bit."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from cli_helpers import DECKS, first_record_line, run_cli, with_card
from factories import CAVITY_BIG_R, CAVITY_LENGTH, CAVITY_R, small_cylinder_deck

from x3dpd.deck import parse_deck
from x3dpd.deck.generate import Material3
from x3dpd.deck.writer import format_deck
from x3dpd.errors import DeckError, UnstableRunError
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model
from x3dpd.solver.simulation import Simulation

DECK = DECKS / "cylinder_64.inp"
# with friction: the kernel variant of the analytic-cylinder impact tests (test_cylinder_cavity)
STEEL = Material3(27.5e6, 0.0, 1.0, 0.3, 0.3, 7.32971e-4)
R, BIG_R, LENGTH = CAVITY_R, CAVITY_BIG_R, CAVITY_LENGTH


def _text(pos, vel=None, *, dt=5e-7):
    return format_deck(small_cylinder_deck(pos, vel, material=STEEL, dt=dt))


@pytest.mark.parametrize(
    "card, message, column",
    [
        ("CYLINDER\n 1 2 3\nEND", "CYLINDER needs 4 values", None),
        ("CYLINDER\n 1 2 3 -0.2\nEND", "RADIUS must be > 0", 8),
        ("CYLINDER\n 1 2 2 0.2\nEND", "NODE_B must differ from NODE_A", 6),
    ],
)
def test_bad_cylinder_records_are_deck_errors_at_the_field(card, message, column):
    text = with_card(_text([[0.15, 0.0, 0.0]]), card)
    with pytest.raises(DeckError, match=message) as err:
        parse_deck(text, "deck.inp")
    assert err.value.card == "CYLINDER"
    assert err.value.line == first_record_line(text, "CYLINDER")
    if column is not None:
        assert err.value.column == column


@pytest.mark.parametrize(
    "card, message",
    [
        ("CYLINDER\n 1 2 99 0.2\nEND", "axis node B 99 is not defined"),
        ("CYLINDER\n 1 2 5 0.2\nEND", "axis node B 5 is a particle node"),
        ("CYLINDER\n 7 2 3 0.2\nEND", "slave set 1 has no master triangles and no CYLINDER"),
    ],
)
def test_bad_cylinder_references_are_deck_errors(card, message):
    text = with_card(_text([[0.15, 0.0, 0.0], [0.15, 0.1, 0.0]]), card)
    with pytest.raises(DeckError, match=message) as err:
        build_model(parse_deck(text, "deck.inp"))
    assert err.value.card in ("CYLINDER", "CONTACT")


def test_axis_nodes_must_move_as_one_rigid_cavity():
    text = _text([[0.15, 0.0, 0.0]])
    # node 3 leaves the rigid body (RBEL lists 2 and 3; keep only 2) and is free
    text = text.replace("   1 123456 2 2 3\n", "   1 123456 1 2\n")
    with pytest.raises(DeckError, match="must move as one rigid cavity") as err:
        build_model(parse_deck(text, "deck.inp"))
    assert err.value.card == "CYLINDER"


def test_check_flags_spheres_outside_and_in_the_wall(tmp_path, monkeypatch):
    # one sphere 0.01 deep in the curved wall (0.32 R, beyond the 0.25 R refusal limit), one
    # with its centre beyond the cap at x = LENGTH, one clean
    pos = [[0.15, BIG_R - R + 0.01, 0.0], [LENGTH + 0.01, 0.0, 0.0], [0.15, 0.0, 0.0]]
    text = _text([[0.15, 0.0, 0.0]] * 3)
    for k, p in enumerate(pos):
        old = f"   {4 + k} 0.15 0.0 0.0\n"
        text = text.replace(old, f"   {4 + k} {p[0]!r} {p[1]!r} {p[2]!r}\n", 1)
    report = check_model(build_model(parse_deck(text, "deck.inp")))
    codes = {w.code: w for w in report.warnings}
    assert (
        "particle node 5: centre outside the cylinder on axis nodes 2, 3"
        in codes["particles-outside"].details[0]
    )
    assert codes["wall-penetration"].details[0].startswith("particle node 4: 0.01 (0.32 R)")
    path = tmp_path / "bad.inp"
    path.write_text(text)
    monkeypatch.chdir(tmp_path)  # a run writes its outputs to the working directory
    assert run_cli("check", path) == 1
    assert run_cli(path, "--quiet") == 2  # refused: the run would blow up
    assert not (tmp_path / "bad.trace.txt").exists()


def test_a_penetration_names_the_cylinder_part():
    # a sphere at 100 in/s towards the curved wall, 0.01 in a step (a step 500 x too coarse):
    # its tenth step puts it 0.009 in (29 % of R) into the wall, its centre still inside. (From
    # the axis at 2e-5 s it rebounded across the cylinder and out through the far side, where
    # the stop now says it left the cylinder: test_a_sphere_that_tunnels_out_is_caught.)
    y0 = (BIG_R - R) + 0.009 - 10 * 0.01
    text = _text([[0.15, y0, 0.0]], [[0.0, 100.0, 0.0]], dt=1e-4)
    sim = Simulation(build_model(parse_deck(text, "deck.inp")))
    with pytest.raises(
        UnstableRunError, match="penetrated the curved wall of the cylinder on axis nodes 2, 3"
    ):
        sim.advance(2000)


def test_a_sphere_that_tunnels_out_is_caught():
    # one step of 0.4 in carries a sphere from the axis through the wall (R = 0.2); the wall
    # then pushes it from the wrong side until the (relaxed) penetration limit stops the run,
    # and the stop names the cause: the sphere left its cylinder. At the same step whether the
    # run goes step by step or in one call (containment is looked at where the run stops, and
    # at fixed step counts: x3dpd.solver.run_checks.AUDIT_STEPS)
    text = _text([[0.15, 0.0, 0.0]], [[0.0, 0.0, -2000.0]], dt=2e-4)
    steps = []
    for calls in (1, 10):
        sim = Simulation(
            build_model(parse_deck(text, "deck.inp")), penetration_limit=1e9, energy_tolerance=1e300
        )
        with pytest.raises(UnstableRunError, match="particle node 4 left its cylinder") as err:
            for _ in range(calls):
                sim.advance(10 // calls)
        steps.append(err.value.step)
    assert steps[0] == steps[1] < 10


def test_restart_continues_cylinder_64_bit_for_bit(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    shutil.copy(DECK, "c.inp")
    assert run_cli("c.inp", "--tmax", 0.004, "--trace", "whole.trace.txt", "--quiet") == 0
    assert run_cli("c.inp", "--tmax", 0.002, "--trace", "part.trace.txt", "--quiet") == 0
    assert (
        run_cli("c.inp", "--tmax", 0.004, "--trace", "part.trace.txt", "--restart", "--quiet") == 0
    )
    whole = (tmp_path / "whole.trace.txt").read_bytes()
    assert (tmp_path / "part.trace.txt").read_bytes() == whole
    rows = np.loadtxt(tmp_path / "whole.trace.txt", delimiter=";")
    assert rows[-1, 0] == pytest.approx(0.004, rel=1e-12)


def test_a_dump_from_before_cylinders_restores_without_their_rows():
    """Restart dumps written before the CYLINDER card have no cylinder state: such a state
    has empty cylinder rows (a scene without cylinders) and runs on bit for bit."""
    from x3dpd.solver.state import State

    text = (DECKS / "beam_1.inp").read_text()
    model = build_model(parse_deck(text, "beam_1.inp"))
    whole = Simulation(model)
    whole.advance(400)
    sim = Simulation(model)
    sim.advance(200)
    arrays = {k: v for k, v in sim.state.to_arrays().items() if k not in ("cs", "cs_on")}
    old = State.from_arrays(arrays)
    assert old.cs.shape == (0, sim.state.ws.shape[1]) and old.cs_on.shape == (0,)
    resumed = Simulation(model)
    resumed.restore(old)
    resumed.advance(200)
    np.testing.assert_array_equal(resumed.state.x, whole.state.x)
