"""The effect units' part of a step-loop variant's VARIANT block (x3dpd.solver.variants).

For the units a variant compiles (x3dpd.physics.effect_units.units_of) it writes, into the
variant's copy of ``_template_variant.py``:

* ``UNIT_BUNDLES(u)``: the units' bundles rebuilt as named tuples from the plain tuples the
  step loop is handed (x3dpd.solver.bundles.pack: the units' bundles in registry order);
* one function per slot (``SLOT_FIRST_HALF_KICK``, ``SLOT_DRIFT``, ``SLOT_FOLLOW``,
  ``SLOT_FORCE``, ``SLOT_GATHER``, ``SLOT_KICK``, ``SLOT_SECOND_HALF_KICK``, ``SLOT_PLACE``,
  ``SLOT_ENERGY``: x3dpd.physics.effect_unit.SLOTS) calling the hooks of the
  units that fill it, in registry order (those that run ``first`` there before the others;
  a hook with an ``only_with`` flag only when the variant has it),
  each with its own bundle; ``SLOT_DRIFT`` and ``SLOT_KICK`` take the step's start time
  ``t_old`` after ``t``, which the hooks of units with ``step_start`` get; a unit's
  ``variant_args`` (constants of the VARIANT block) follow.

Every function is a ``step_kernel``, inlined where the loop calls it; beside each,
``FILLED_<SLOT>`` says whether any hook fills it, and the loop calls a slot only under that
constant: a slot without hooks is never called, so numba neither types nor inlines it and
LLVM has nothing to clean up (an empty function's arguments -- the bundles -- still cost the
optimizer a pass over their copies). The hooks are imported from
their modules under generated names, as the laws are (x3dpd.solver.variants).
"""

from __future__ import annotations

from x3dpd.physics.effect_units import SLOTS, units_of

#: A slot's arguments after the unit's bundle, as the loop calls it.
_ARGS = {slot: "nodes, rigid, stepping, t" for slot in SLOTS}
_ARGS["energy"] = "nodes, en"
#: The slots that also have the step's start time, for the hooks of units with step_start.
_STEP_START = ("drift", "kick")


def units_source(variant) -> str:
    """The VARIANT block's lines of the units ``variant`` compiles: imports, ``UNIT_BUNDLES``
    and the slot functions (module docstring)."""
    units = units_of(variant)
    lines = ["from x3dpd._jit import step_kernel as _unit_kernel  # noqa: E402"]
    for k, unit in enumerate(units):
        names = [f"{unit.bundle.__name__} as _UNIT_{k}_BUNDLE"] + [
            f"{hook} as _UNIT_{k}_{slot.upper()}" for slot, hook in unit.hooks.items()]
        lines.append(f"from {unit.module} import {', '.join(names)}  # noqa: E402,E501")
    rebuilt = "".join(f"_UNIT_{k}_BUNDLE(*u[{k}]), " for k in range(len(units)))
    lines += _function("UNIT_BUNDLES", "u", [f"return ({rebuilt.rstrip(' ')})"
                                              if units else "return ()"])
    for slot in SLOTS:
        start = slot in _STEP_START
        order = sorted(range(len(units)), key=lambda k: slot not in units[k].first)
        calls = [f"_UNIT_{k}_{slot.upper()}(units[{k}], {_ARGS[slot]}"
                 f"{', t_old' if start and units[k].step_start else ''}"
                 f"{''.join(', ' + a for a in units[k].variant_args)})"
                 for k in order if _compiles(units[k], slot, variant)]
        if slot == "energy":
            body = ["shadow = 0.0"] + [f"shadow += {call}" for call in calls]
            body.append("return shadow")
        else:
            body = calls or ["return"]
        args = f"units, {_ARGS[slot]}{', t_old' if start else ''}"
        lines += ["", "", f"FILLED_{slot.upper()} = {bool(calls)}"]
        lines += _function(f"SLOT_{slot.upper()}", args, body)
    return "\n".join(lines + [""])


def _compiles(unit, slot: str, variant) -> bool:
    """Whether ``variant`` compiles ``unit``'s hook in ``slot``: it has one there, and the flag
    the unit names for it (``only_with``), if any, is on."""
    flag = unit.only_with.get(slot)
    return slot in unit.hooks and (flag is None or getattr(variant, flag))


def _function(name: str, args: str, body: list[str]) -> list[str]:
    return ["", "", "@_unit_kernel", f"def {name}({args}):"] + [f"    {b}" for b in body]
