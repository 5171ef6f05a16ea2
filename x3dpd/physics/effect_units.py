"""The registry of effect units: what a unit provides (x3dpd.physics.effect_unit), and the units.

An effect unit is one effect of a scene -- a structure kind, a force source -- that owns its
arrays (one bundle), their builder from the model, its energy terms and its kernel hooks in the
fixed slots of the step loop. Everything else is shared and reads the registry:

* the solver builds every unit's constants (``setup``) and state arrays for every scene, so
  that a restart dump holds the same arrays whatever the scene calls for
  (x3dpd.solver.state), and hands the step loop the bundles of the units the scene calls for
  (x3dpd.solver.bundles);
* the step-loop factory (x3dpd.solver.variants, x3dpd.solver.unit_slots) compiles a unit when
  the scene's variant has its ``flag`` (set from the model's effects, any of ``effects``), and
  writes each slot of the loop as the calls of its units' hooks, in registry order; a slot
  no unit of the scene fills compiles to nothing;
* a unit with a card of its own gets it read and written (x3dpd.deck), its records checked and
  built into ``model.unit_data`` (x3dpd.model.build_units) and its findings in ``x3dpd check``;
* the diagnosis of a stop reads the units' ``stiffness`` (x3dpd.solver.diagnosis), a run's
  start their ``start`` hooks, the walls' test for turning bodies their ``turns``.

Adding a unit
-------------
Write the law in ``x3dpd/physics/<name>.py`` with its kernels, its bundle (a NamedTuple) and
``UNIT = EffectUnit(...)`` and add the module to :data:`UNITS` below; its flag becomes a field
of x3dpd.solver.variants.Variant by itself (docs/engine.md, "Adding an effect";
``x3dpd.physics.rotational_spring`` is a complete example).
"""

from __future__ import annotations

import dataclasses

from x3dpd.physics import (axial_spring, external_force, gravity, modal, motion, rigid_link,
                           rotational_spring, spring_damper)
from x3dpd.physics.effect_unit import SLOTS, EffectUnit, StateArray, UnitCard

__all__ = ["UNITS", "BY_UNIT_NAME", "BY_UNIT_CARD", "EffectUnit", "StateArray", "UnitCard",
           "SLOTS", "units_of"]


def _register(*modules) -> tuple[EffectUnit, ...]:
    """The units of ``modules`` (each defines ``UNIT``), checked, in the given order."""
    out = []
    for m in modules:
        unit = dataclasses.replace(m.UNIT, module=m.__name__)
        where = f"{m.__name__}: effect unit {unit.name!r}"
        for slot, hook in unit.hooks.items():
            if slot not in SLOTS:
                raise ValueError(f"{where}: no slot {slot!r}; the slots are {list(SLOTS)}")
            if not callable(getattr(m, hook, None)):
                raise ValueError(f"{where}: its {slot} hook {hook!r} is not in the module")
        if not set(unit.only_with) <= set(unit.hooks):
            missing = sorted(set(unit.only_with) - set(unit.hooks))
            raise ValueError(f"{where}: it compiles hooks only with a flag in {missing} "
                             "without a hook there")
        if not set(unit.first) <= set(unit.hooks):
            missing = sorted(set(unit.first) - set(unit.hooks))
            raise ValueError(f"{where}: it runs first in {missing} without a hook there")
        for name in unit.kernels:
            if not callable(getattr(m, name, None)):
                raise ValueError(f"{where}: its kernel {name!r} is not in the module")
        fields = set(unit.bundle._fields)
        named = {s.field for s in unit.state} | {f for f, _ in unit.scratch}
        if not named <= fields:
            raise ValueError(f"{where}: {sorted(named - fields)} are not fields of its bundle")
        if any(s.rows not in fields for s in unit.state):
            raise ValueError(f"{where}: a state array's rows are not a field of its bundle")
        if (unit.card is None) != (unit.build is None):
            raise ValueError(f"{where}: a card of its own needs its build, and a build its card")
        if unit.card is not None and not set(unit.card.node_fields) <= set(unit.card.fields):
            raise ValueError(f"{where}: its card's node fields are not among its fields")
        if unit.runtime != (unit.flag == ""):
            raise ValueError(f"{where}: a unit has a flag or is compiled into every loop "
                             "(runtime), not both or neither")
        out.append(unit)
    for key in ("name", "flag"):
        values = [getattr(u, key) for u in out if not (key == "flag" and u.runtime)]
        if len(set(values)) != len(values):
            raise ValueError(f"two effect units share a {key}: {values}")
    names = [s.name for u in out for s in u.state]
    if len(set(names)) != len(names):
        raise ValueError(f"two effect units' state arrays share a name: {names}")
    return tuple(out)


#: The effect units, in the order the slots call them (x3dpd.physics.effect_unit, "The slots").
#: The rigid bodies come after the modes (a modal master's slaves follow it), the prescribed
#: motions after both; gravity is last: the masses it weighs are the nodes' after the modes
#: took theirs.
UNITS: tuple[EffectUnit, ...] = _register(spring_damper, axial_spring, rotational_spring, modal,
                                         rigid_link, motion, external_force, gravity)
#: Effect unit by name.
BY_UNIT_NAME = {u.name: u for u in UNITS}
#: Effect unit by the name of its own card (those that have one).
BY_UNIT_CARD = {u.card.name: u for u in UNITS if u.card is not None}


def units_of(variant) -> tuple[EffectUnit, ...]:
    """The units a step-loop variant compiles (x3dpd.solver.variants.Variant: those whose flag
    is set, and the runtime units), in registry order."""
    return tuple(u for u in UNITS if u.runtime or getattr(variant, u.flag))
