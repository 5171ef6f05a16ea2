"""Tests import their shared helpers (tests/factories.py, tests/cli/cli_helpers.py,
tools/bench ...) through pytest's ``pythonpath`` (pyproject.toml), never by editing
``sys.path`` themselves: a helper moved is then one line of configuration, not a hunt."""

from __future__ import annotations

from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]
EDITS = tuple("sys.path." + verb for verb in ("insert", "append", "extend"))


def test_no_test_edits_sys_path():
    offenders = [
        str(p.relative_to(TESTS))
        for p in sorted(TESTS.rglob("*.py"))
        if any(edit in p.read_text() for edit in EDITS)
    ]
    assert offenders == []
