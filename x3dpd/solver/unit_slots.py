"""The effect units' part of a step-loop variant's VARIANT block (x3dpd.solver.variants).

For the units a variant compiles (x3dpd.physics.effect_units.units_of) it writes, into the
variant's copy of ``_template_variant.py``:

* ``UNIT_BUNDLES(u)``: the units' bundles rebuilt as named tuples from the plain tuples the
  step loop is handed (x3dpd.solver.bundles.pack: the units' bundles in registry order);
* one function per slot (``SLOT_DRIFT``, ``SLOT_FOLLOW``, ``SLOT_FORCE``, ``SLOT_KICK``,
  ``SLOT_PLACE``, ``SLOT_ENERGY``: x3dpd.physics.effect_unit.SLOTS) calling the hooks of the
  units that fill it, in registry order, each with its own bundle.

Every function is a ``step_kernel``, inlined where the loop calls it; a slot without hooks is
an empty function, which leaves no trace in the machine code. The hooks are imported from
their modules under generated names, as the laws are (x3dpd.solver.variants).
"""

from __future__ import annotations

from x3dpd.physics.effect_units import SLOTS, units_of

#: A slot's arguments after the unit's bundle, as the loop calls it.
_ARGS = {slot: "nodes, rigid, stepping, t" for slot in SLOTS}
_ARGS["energy"] = "nodes, en"


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
        calls = [(k, f"_UNIT_{k}_{slot.upper()}(units[{k}], {_ARGS[slot]})")
                 for k, unit in enumerate(units) if slot in unit.hooks]
        if slot == "energy":
            body = ["shadow = 0.0"] + [f"shadow += {call}" for _, call in calls]
            body.append("return shadow")
        else:
            body = [call for _, call in calls] or ["return"]
        lines += _function(f"SLOT_{slot.upper()}", f"units, {_ARGS[slot]}", body)
    return "\n".join(lines + [""])


def _function(name: str, args: str, body: list[str]) -> list[str]:
    return ["", "", "@_unit_kernel", f"def {name}({args}):"] + [f"    {b}" for b in body]
