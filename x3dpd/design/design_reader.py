"""Reading a design file's values (x3dpd.design.design_file): where each key stands in the
text, and values checked with an InputError ``FILE:LINE: key: message`` at the key's line."""

from __future__ import annotations

import math
import re
from pathlib import Path

from x3dpd.errors import InputError

_NUMBER = (int, float)


def key_lines(text: str) -> dict[tuple, int]:
    """{key path: line} of every ``key = ...`` and table header in a TOML text (array-of-tables
    entries indexed: ("configuration", 0, "count")). Enough for messages, not a TOML parser."""
    out: dict[tuple, int] = {}
    table: tuple = ()
    arrays: dict[tuple, int] = {}
    for n, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        head = re.match(r"^\[\[\s*([\w.-]+)\s*\]\]$", line)
        if head:
            name = tuple(head.group(1).split("."))
            arrays[name] = arrays.get(name, -1) + 1
            table = name + (arrays[name],)
            out.setdefault(name, n)
            out[table] = n
            continue
        head = re.match(r"^\[\s*([\w.-]+)\s*\]$", line)
        if head:
            table = tuple(head.group(1).split("."))
            out[table] = n
            continue
        key = re.match(r"^([\w-]+)\s*=", line)
        if key:
            out.setdefault(table + (key.group(1),), n)
    return out


class Reader:
    """Checks values and raises ``FILE:LINE: message`` at their key."""

    def __init__(self, path: Path, text: str):
        self.path, self.lines = path, key_lines(text)

    def fail(self, keys: tuple, message: str):
        line = 0
        for k in range(len(keys), 0, -1):  # the key, else its table
            line = self.lines.get(tuple(keys[:k]), 0)
            if line:
                break
        where = f"{self.path}:{line}" if line else f"{self.path}"
        raise InputError(f"{where}: {'.'.join(map(str, keys))}: {message}")

    def known(self, table: dict, allowed, keys: tuple) -> None:
        for k in table:
            if k not in allowed:
                self.fail(keys + (k,), f"unknown key {k!r}; expected one of {', '.join(allowed)}")

    def number(self, value, keys, positive=True, integer=False, minimum=None):
        kind = int if integer else _NUMBER
        if isinstance(value, bool) or not isinstance(value, kind) or not math.isfinite(value):
            self.fail(keys, f"expected {'an integer' if integer else 'a number'}, got {value!r}")
        if positive and not value > 0:
            self.fail(keys, f"expected a value > 0, got {value!r}")
        if minimum is not None and value < minimum:
            self.fail(keys, f"expected a value >= {minimum}, got {value!r}")
        return value

    def config_value(self, key: str, value, keys):
        """A configuration key's value checked (materials checked against the library)."""
        if key == "material":
            if not isinstance(value, str):
                self.fail(keys, f"expected a material name, got {value!r}")
            _check_material(value, lambda msg: self.fail(keys, msg))
            return value
        if key == "packing":
            from x3dpd.api.decks import PACKINGS

            if value not in PACKINGS:
                self.fail(keys, f"expected one of {', '.join(PACKINGS)}, got {value!r}")
            return value
        if key == "cavity_size":
            if not isinstance(value, list) or len(value) != 3:
                self.fail(keys, f"expected [x, y, z] interior dimensions, got {value!r}")
            return tuple(float(self.number(v, keys)) for v in value)
        if key == "thickness":  # one plate per value (x3dpd.design.config_mip)
            values = value if isinstance(value, list) else [value]
            if not values:
                self.fail(keys, "expected a plate thickness, or a list of one per plate")
            return tuple(float(self.number(v, keys)) for v in values)
        if key == "lumped":
            if not isinstance(value, bool):
                self.fail(keys, "expected true or false")
            return value
        if key == "start":
            from x3dpd.api.decks import STARTS

            if value not in STARTS:
                self.fail(keys, f"expected one of {', '.join(STARTS)}, got {value!r}")
            return value
        if key == "holes":
            return self.number(value, keys, integer=True)
        if key in ("shim", "end_plate"):
            return float(self.number(value, keys, positive=False))
        if key in ("count", "seed"):
            return self.number(value, keys, positive=False, integer=True, minimum=0)
        if key == "cavities":
            return self.number(value, keys, integer=True)
        if key == "temperature":  # read with the deck's units when the deck is made
            if isinstance(value, bool) or not isinstance(value, (int, float, str)):
                self.fail(keys, f"expected a temperature (850F, 455C, or a number), got {value!r}")
            return value
        if key == "stiffness_scale":
            value = self.number(value, keys)
            if value > 1:
                self.fail(keys, f"expected a scale in (0, 1] (softer contacts), got {value!r}")
            return float(value)
        if key in ("gap", "gap_fraction", "jitter", "clearance"):
            value = self.number(value, keys, positive=False, minimum=0)
            if key == "jitter" and value > 1:
                self.fail(keys, f"expected a fraction 0-1, got {value!r}")
            return value
        if key == "fill_ratio":
            value = self.number(value, keys)
            if value >= 0.7405:
                self.fail(
                    keys,
                    f"fill ratio {value!r}: no packing of spheres exceeds pi/sqrt(18) = 0.7405",
                )
            return value
        return self.number(value, keys)


def _check_material(name: str, fail) -> None:
    """``fail(message)`` unless ``name`` is in the material library (x3dpd.materials)."""
    from x3dpd.materials import material

    try:
        material(name)
    except InputError as exc:
        fail(str(exc))
