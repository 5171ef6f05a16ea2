"""The effect units' registry (x3dpd.physics.effect_units) and the seam a unit with a card of
its own goes through: the deck reader and writer, the model builder and ``x3dpd check`` take a
new unit's card from its registration alone (docs/engine.md, "Adding an effect").

The card seam is shown on a unit written here (a point load: NODE FX FY FZ) and registered in a
child process, so the package's registry stays the shipped one; nothing is compiled."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from x3dpd.physics import effect_units, spring_damper
from x3dpd.physics.effect_unit import SLOTS, EffectUnit
from x3dpd.solver.kernel_cache import EVENTS_ENV
from x3dpd.solver.unit_slots import units_source
from x3dpd.solver.variants import Variant

ROOT = Path(__file__).resolve().parents[2]
BEAM_1 = ROOT / "decks" / "beam_1.inp"

POINT_LOAD = """
from typing import NamedTuple
import numpy as np
from x3dpd._jit import step_kernel
from x3dpd.physics.effect_unit import L_WEXT, EffectUnit, UnitCard

class PointLoads(NamedTuple):
    nodes: np.ndarray
    f: np.ndarray

@step_kernel
def force_hook(u, nodes, rigid, stepping, t):
    for s in range(u.nodes.shape[0]):
        for d in range(3):
            nodes.force[u.nodes[s], d] += u.f[s, d]
            # its work over the step: a constant force on the half-step velocity
            stepping.ledger[L_WEXT] += u.f[s, d] * nodes.vel[u.nodes[s], d] * stepping.dt

def _setup(model, dt, nodes):  # every scene's, with or without the card
    d = model.unit_data.get("point_load", {"nodes": [], "f": []})
    return {"nodes": np.asarray(d["nodes"], np.int64), "f": np.reshape(d["f"], (-1, 3))}

def _build(rows, fail):
    for k, r in enumerate(rows):
        if r["FX"] < 0:
            raise fail(k, "FX must not be negative")
    return {"nodes": [r["NODE"] for r in rows], "f": [[r["FX"], r["FY"], r["FZ"]] for r in rows]}

def _check(model):
    n = len(model.unit_data.get("point_load", {}).get("nodes", ()))
    return [("point-load", "point loads", [f"{n} loads"])] if n else []

UNIT = EffectUnit(
    name="point_load", flag="point_loads", effects=("point_load",), cards=("POINTLOAD",),
    bundle=PointLoads, setup=_setup, hooks={"force": "force_hook"},
    card=UnitCard("POINTLOAD", ("NODE", "FX", "FY", "FZ"), ("NODE",)), build=_build,
    check=_check)
"""

CHILD = """
import json, sys
import point_load
from x3dpd.physics import effect_units as eu
eu.UNITS = eu.UNITS + eu._register(point_load)
from x3dpd.deck.parser import read_deck, parse_deck
from x3dpd.deck.writer import format_deck
from x3dpd.errors import DeckError
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model

out = {}
for path in sys.argv[1:]:
    try:
        deck = read_deck(path)
        written = format_deck(deck)
        again = parse_deck(written)
        model = build_model(deck)
        found = [w.details for w in check_model(model).warnings if w.code == "point-load"]
        out[path] = {
            "records": [list(r.values) for r in deck.unit_records or ()],
            "again": [list(r.values) for r in again.unit_records or ()],
            "node_ids": [int(i) for i in model.node_ids],
            "data": model.unit_data.get("point_load"),
            "effect": "point_load" in model.effects,
            "check": [list(d) for d in found],
        }
    except DeckError as e:
        out[path] = {"error": str(e)}
print(json.dumps(out))
"""


def _decks(tmp_path: Path, records: dict[str, str]) -> list[Path]:
    base = BEAM_1.read_text()
    paths = []
    for name, card in records.items():
        p = tmp_path / f"{name}.inp"
        p.write_text(base + (f"\nPOINTLOAD\n{card}\nEND\n" if card else ""))
        paths.append(p)
    return paths


def test_a_unit_with_a_card_of_its_own_needs_no_deck_or_model_code(tmp_path):
    (tmp_path / "point_load.py").write_text(POINT_LOAD)
    (tmp_path / "child.py").write_text(CHILD)
    decks = _decks(
        tmp_path,
        {
            "good": " 9 2.5 0 -1.25\n 10 0.5 1 0",
            "none": "",
            "negative": " 9 2.5 0 0\n 10 -1 0 0",
            "undefined": " 999 2.5 0 0",
            "short": " 9 2.5 0",
        },
    )
    env_path = f"{tmp_path}:{ROOT}"
    run = subprocess.run(
        [sys.executable, str(tmp_path / "child.py"), *map(str, decks)],
        capture_output=True,
        text=True,
        env={**__import__("os").environ, "PYTHONPATH": env_path},
        timeout=300,
    )
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    good, none, negative, undefined, short = (got[str(p)] for p in decks)

    assert good["records"] == [[9, 2.5, 0.0, -1.25], [10, 0.5, 1.0, 0.0]]
    assert good["again"] == good["records"]  # the writer writes what the reader reads
    index = {nid: k for k, nid in enumerate(good["node_ids"])}
    assert good["data"] == {"nodes": [index[9], index[10]], "f": [[2.5, 0, -1.25], [0.5, 1, 0]]}
    assert good["effect"] and good["check"] == [["2 loads"]]
    assert none["data"] is None and not none["effect"] and none["check"] == []
    assert none["records"] == none["again"] == []

    line = len(BEAM_1.read_text().splitlines()) + 4  # a blank line, POINTLOAD, 2 records
    assert negative["error"] == f"{decks[2]}:{line}:2: POINTLOAD: FX must not be negative"
    assert undefined["error"].startswith(f"{decks[3]}:{line - 1}:2: POINTLOAD: NODE (field 1)")
    assert "999" in undefined["error"]
    assert short["error"].startswith(f"{decks[4]}:{line - 1}:")
    assert "needs 4 values: NODE FX FY FZ; got 3" in short["error"]


RUN_CHILD = """
import json, sys
import numpy as np
import point_load
from x3dpd.physics import effect_units as eu
eu.UNITS = eu.UNITS + eu._register(point_load)
import x3dpd
from x3dpd.solver.variants import Variant
loaded, plain, tmax = sys.argv[1], sys.argv[2], float(sys.argv[3])
a = x3dpd.run(loaded, tmax=tmax)
b = x3dpd.run(plain, tmax=tmax, usrfrc=["constant:node=9,dof=1,amp=2.5e-3"], usrfrc_mode="add")
c = x3dpd.run(plain, tmax=tmax)
print(json.dumps({
    "flag": "point_loads" in Variant.__dataclass_fields__,
    "a": a.trace.data.tolist(), "b": b.trace.data.tolist(), "c": c.trace.data.tolist(),
    "residual": [a.summary["relative_residual"], b.summary["relative_residual"]],
}))
"""


def test_a_new_force_source_runs_in_the_step_loop_from_its_registration(tmp_path):
    """The point load, registered in a child process (its module and the registry: the two
    places a new unit with a card of its own takes), compiled into a step loop of its own --
    its Variant flag comes from the registration -- moves beam_1's node 9 as the same constant
    force given as a USRFRC law does: the same terms summed in another order (the unit's force
    before the deck's drive, the law after it), so the traces agree to rounding (1e-9 of the
    motion; a 4 % smaller law misses by 1.6 %)."""
    (tmp_path / "point_load.py").write_text(POINT_LOAD)
    (tmp_path / "child.py").write_text(RUN_CHILD)
    loaded, plain = _decks(tmp_path, {"loaded": " 9 2.5e-3 0 0", "plain": ""})
    run = subprocess.run(
        [sys.executable, str(tmp_path / "child.py"), str(loaded), str(plain), "0.02"],
        capture_output=True,
        text=True,
        env={
            **os.environ,
            "PYTHONPATH": f"{tmp_path}:{ROOT}",
            # its own kernel cache and compile log: the suite's variant list (tests/meta/
            # variants.txt) names loops of the shipped registry, and the two loops compiled
            # here (about 14 s) include a unit that exists only in this child
            "X3DPD_CACHE_DIR": str(tmp_path / "cache"),
            EVENTS_ENV: str(tmp_path / "events.jsonl"),
        },
        timeout=600,
    )
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["flag"]
    a, b = np.asarray(got["a"]), np.asarray(got["b"])
    assert a.shape == b.shape and a.shape[0] > 10
    scale = np.max(np.abs(b), axis=0) + 1e-300
    assert np.max(np.abs(a - b) / scale) < 1e-9
    # the loads do move the beam (against the deck's drive alone), and the point load books
    # its work: the energy ledger closes as well as with the USRFRC laws
    c = np.asarray(got["c"])
    assert np.max(np.abs(a - c) / scale) > 1e-3
    residual_a, residual_b = got["residual"]
    assert abs(residual_a) <= 2.0 * abs(residual_b) + 1e-12


def _module(**names) -> types.ModuleType:
    m = types.ModuleType("x3dpd.physics.fake_unit")
    m.__dict__.update(names)
    return m


def test_the_registry_refuses_a_hook_outside_the_slots_or_the_module():
    unit = spring_damper.UNIT
    bad_slot = EffectUnit(**{**unit.__dict__, "hooks": {"after": "force_hook"}})
    with pytest.raises(ValueError, match="no slot 'after'"):
        effect_units._register(_module(UNIT=bad_slot, force_hook=spring_damper.force_hook))
    with pytest.raises(ValueError, match="its force hook 'force_hook' is not in the module"):
        effect_units._register(_module(UNIT=unit, energy_hook=spring_damper.energy_hook))
    with pytest.raises(ValueError, match="share a name"):
        effect_units._register(spring_damper, spring_damper)
    first_without_hook = EffectUnit(**{**unit.__dict__, "first": ("kick",)})
    with pytest.raises(ValueError, match=r"runs first in \['kick'\] without a hook there"):
        effect_units._register(
            _module(
                UNIT=first_without_hook,
                force_hook=spring_damper.force_hook,
                energy_hook=spring_damper.energy_hook,
            )
        )


def test_a_variant_compiles_the_hooks_of_its_units_only():
    none = units_source(Variant())
    springs = units_source(Variant(springs=True))
    assert "import" in none and "spring_damper" not in none
    for slot in SLOTS:  # every slot is defined, empty without units
        assert f"def SLOT_{slot.upper()}(" in none
    assert "from x3dpd.physics.spring_damper import SpringDampers as _UNIT_0_BUNDLE" in springs
    assert "_UNIT_0_FORCE(units[0], nodes, rigid, stepping, t)" in springs
    assert "shadow += _UNIT_0_ENERGY(units[0], nodes, en)" in springs


def _slot_body(source: str, slot: str) -> list[str]:
    """The statements of the generated function ``SLOT_<slot>``."""
    body = source.split(f"def SLOT_{slot.upper()}(", 1)[1].split("\n\n", 1)[0]
    return [line.strip() for line in body.splitlines()[1:]]


def test_a_unit_runs_first_where_it_says_and_gets_the_step_start_where_it_asks():
    """The prescribed motions (registered after the modes) impose their DOFs after the modes'
    drift, and take their actuators' work and place their DOFs before the modes' kick and
    place; their drift and kick hooks get the step's start time, the modes' do not."""
    names = [u.name for u in effect_units.UNITS]
    modal_k, motion_k = (names.index(n) for n in ("modal", "motion"))
    assert modal_k < motion_k
    source = units_source(Variant(modal=True, motion=True))
    k_modal, k_motion = 0, 1  # the two units the variant compiles, in registry order
    assert _slot_body(source, "drift") == [
        f"_UNIT_{k_modal}_DRIFT(units[{k_modal}], nodes, rigid, stepping, t)",
        f"_UNIT_{k_motion}_DRIFT(units[{k_motion}], nodes, rigid, stepping, t, t_old)",
    ]
    assert _slot_body(source, "kick") == [
        f"_UNIT_{k_motion}_KICK(units[{k_motion}], nodes, rigid, stepping, t, t_old)",
        f"_UNIT_{k_modal}_KICK(units[{k_modal}], nodes, rigid, stepping, t)",
    ]
    assert _slot_body(source, "place") == [
        f"_UNIT_{k_motion}_PLACE(units[{k_motion}], nodes, rigid, stepping, t)",
        f"_UNIT_{k_modal}_PLACE(units[{k_modal}], nodes, rigid, stepping, t)",
    ]
    assert "def SLOT_DRIFT(units, nodes, rigid, stepping, t, t_old):" in source
    assert "def SLOT_PLACE(units, nodes, rigid, stepping, t):" in source


def test_the_external_forces_come_last_in_the_force_slot_with_the_variants_constants():
    """The external forces (USRFRC laws, user files, Python forces) follow the springs' forces,
    as they did before they were a unit, and take the variant's user-force constants."""
    source = units_source(Variant(springs=True, external=True, user_force=True))
    assert _slot_body(source, "force") == [
        "_UNIT_0_FORCE(units[0], nodes, rigid, stepping, t)",
        "_UNIT_1_FORCE(units[1], nodes, rigid, stepping, t, HAS_USER_FORCE, HAS_PYTHON_FORCE, "
        "USER_FORCE)",
    ]
    header = Variant(external=True).header()
    assert "HAS_USER_FORCE = False" in header and "USER_FORCE = None" in header
