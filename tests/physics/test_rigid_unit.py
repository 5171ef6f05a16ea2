"""The rigid bodies (RBEL) as an effect unit (x3dpd.physics.rigid_link, ``UNIT``).

What the move onto the seam must keep, checked through the registry and the generated slots:
a body turns before the units that drive bodies set their turn and its slaves follow before the
units' own coordinates do (``first``); a modal master's slaves follow it after the modes and
the prescribed motions placed it; the slaves' forces are gathered in a slot of their own; the
step loop's template holds no rigid-body code of its own. The lumped masses are closed forms of
beam_1's deck: the master carries the body's mass, its slaves none, and velocity Verlet leaves
them alone; every body's rotation starts at I, and a restart dump keeps the arrays in the
order dumps have always had (``rot`` fourth). The bodies' physics (a constant moment turns a
body by theta = alpha t^2 / 2, Euler's equations) is tests/solver/test_rigid_and_motion.py's.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from x3dpd.deck import read_deck
from x3dpd.model.build import build_model
from x3dpd.physics import effect_units, rigid_link
from x3dpd.solver.state import build_setup, initial_state
from x3dpd.solver.unit_slots import units_source
from x3dpd.solver.variants import Variant

ROOT = Path(__file__).resolve().parents[2]
TEMPLATE = ROOT / "x3dpd" / "solver" / "_advance_template.py"


def _calls(source: str, slot: str) -> list[str]:
    """The modules whose hooks ``SLOT_<slot>`` calls, in order (x3dpd.solver.unit_slots)."""
    modules = dict(
        re.findall(r"from x3dpd\.physics\.(\w+) import \w+ as _UNIT_(\d+)_BUNDLE", source)
    )
    by_index = {k: m for m, k in modules.items()}
    body = source.split(f"def SLOT_{slot.upper()}(", 1)[1].split("\n\n", 1)[0]
    return [by_index[k] for k in re.findall(rf"_UNIT_(\d+)_{slot.upper()}\(", body)]


def test_the_bodies_turn_and_carry_first_and_place_their_slaves_after_the_modes_and_motions():
    source = units_source(Variant(modal=True, rigid=True, rigid_rotation=True, motion=True))
    assert _calls(source, "drift") == ["rigid_link", "modal", "motion"]
    assert _calls(source, "follow") == ["rigid_link"]
    assert _calls(source, "place") == ["motion", "modal", "rigid_link"]
    assert _calls(source, "gather") == ["rigid_link"]
    assert _calls(source, "kick") == ["motion", "modal"]
    for slot in ("first_half_kick", "second_half_kick"):
        assert _calls(source, slot) == ["rigid_link"]
    # the bodies' hooks take the variant's HAS_RIGID_ROTATION: without a free rotation the
    # kicks and the turn compile to nothing
    assert "stepping, t, HAS_RIGID_ROTATION)" in source


def test_bodies_that_cannot_turn_compile_no_kick_or_turn_and_the_loop_skips_empty_slots():
    """beam_64's body is free in translation only: its slaves follow and gather, but the
    rotation's kicks and turn (``only_with`` rigid_rotation) are not compiled, and the loop
    does not even call the slots that are left empty (``FILLED_<SLOT> = False``)."""
    source = units_source(Variant(rigid=True, walls=True))
    assert _calls(source, "follow") == ["rigid_link"]
    assert _calls(source, "gather") == ["rigid_link"]
    assert _calls(source, "place") == ["rigid_link"]
    for slot in ("first_half_kick", "drift", "second_half_kick"):
        assert _calls(source, slot) == []
        assert f"FILLED_{slot.upper()} = False" in source
    assert "FILLED_GATHER = True" in source and "FILLED_FOLLOW = True" in source


def test_a_scene_without_bodies_compiles_none_of_their_hooks():
    source = units_source(Variant(walls=True, pairs=True))
    assert "rigid_link" not in source
    for slot in ("first_half_kick", "gather", "second_half_kick"):
        assert _calls(source, slot) == []


def test_the_step_loop_is_a_sequence_of_slots_without_rigid_body_code():
    template = TEMPLATE.read_text()
    assert "rigid_link" not in template and "HAS_RIGID" not in template
    for slot in ("FIRST_HALF_KICK", "GATHER", "SECOND_HALF_KICK", "DRIFT", "FOLLOW", "PLACE"):
        assert f"SLOT_{slot}(" in template


def test_beam_1s_body_lumps_its_mass_on_the_master_and_starts_unturned():
    model = build_model(read_deck(ROOT / "decks" / "beam_1.inp"))
    setup = build_setup(model, 1e-6)
    bodies = setup.units["rigid_links"]
    assert bodies["master"].tolist() == [int(m) for m in model.rigid_master]
    m = int(bodies["master"][0])
    slaves = bodies["slaves"][bodies["ptr"][0] : bodies["ptr"][1]]
    # the RBEL body's mass (the deck's, built with the model) on its master, none on the slaves
    assert setup.kin_mass[m] == model.rigid_mass[0]
    assert np.all(setup.kin_mass[slaves] == 0.0)
    assert np.all(setup.inv_m[slaves] == 0.0)
    # beam_1's master is free in x only (BOUNDARY CONDITIONS): 1/M there, 0 where fixed
    free = ~np.asarray(model.fixed, dtype=bool).reshape(-1, 6)[m]
    assert free.tolist() == [True, False, False, False, False, False]
    assert setup.inv_m[m, 0] == 1.0 / model.rigid_mass[0]
    assert np.all(setup.inv_m[m, 1:] == 0.0)
    # its rotations are fixed: no free rotation, no inverse inertia
    assert not bodies["free_rot"].any() and np.all(bodies["inv_ib"] == 0.0)
    state = initial_state(model, setup)
    assert np.array_equal(state.rot, np.eye(3)[None])
    assert list(state.to_arrays())[:4] == ["x", "vel", "force", "rot"]


def test_the_unit_is_registered_between_the_modes_and_the_prescribed_motions():
    names = [u.name for u in effect_units.UNITS]
    assert names.index("modal") < names.index("rigid_links") < names.index("motion")
    assert effect_units.BY_UNIT_NAME["rigid_links"] is not rigid_link.UNIT  # module set
    assert effect_units.BY_UNIT_NAME["rigid_links"].module == "x3dpd.physics.rigid_link"
