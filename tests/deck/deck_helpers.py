"""Shared helpers of the deck tests: paths and comparing decks without positions."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from x3dpd.deck.cards import NOWHERE, Pos

ROOT = Path(__file__).resolve().parents[2]
DECKS = ROOT / "decks"
FIXTURES = ROOT / "tests" / "fixtures" / "decks"

_POSITION_FIELDS = {"pos": NOWHERE, "positions": (), "slave_positions": (), "path": "<deck>"}


def strip_positions(obj: Any) -> Any:
    """``obj`` with every Pos, per-id position list and the deck path reset (for equality)."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        changes = {}
        for f in dataclasses.fields(obj):
            value = getattr(obj, f.name)
            changes[f.name] = (
                _POSITION_FIELDS[f.name] if f.name in _POSITION_FIELDS else strip_positions(value)
            )
        return dataclasses.replace(obj, **changes)
    if isinstance(obj, tuple):
        return tuple(strip_positions(x) for x in obj)
    return obj


def where(path: Path, needle: str, occurrence: int = 0) -> Pos:
    """Position (1-based line, column) of the ``occurrence``-th ``needle`` in a file's text."""
    seen = 0
    for number, line in enumerate(Path(path).read_text().splitlines(), start=1):
        col = line.find(needle)
        while col >= 0:
            if seen == occurrence:
                return Pos(number, col + 1)
            seen += 1
            col = line.find(needle, col + 1)
    raise AssertionError(f"{needle!r} not found in {path}")
