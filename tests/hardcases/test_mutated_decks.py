"""Mutated decks: whatever a deck says, `x3dpd check` and `x3dpd run` end with exit 0-3 and a
message, never a traceback.

Mutations of the shipped impact_wall.inp: one number replaced (by an extreme, negative, zero,
non-finite or malformed value), a line deleted, a line duplicated, or a line cut short. The runs
use a fixed short window (`--dt 1e-9 --tmax 2e-8`, 20 steps) so that a mutated DTMAX cannot ask
for 1e300 steps. The default suite mutates only numbers that keep the scene's kernel variant
(coordinates, radius, density, moduli, velocities, PARAMETERS but the start time, which can ask
for any number of steps); the `validate` suite mutates any token (and so may compile other
variants, a minute each the first time, and may run long).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from x3dpd.cli import main

DECK = (Path(__file__).resolve().parents[2] / "decks" / "impact_wall.inp").read_text()
LINES = DECK.splitlines()
DATA = [
    k
    for k, line in enumerate(LINES)
    if line.strip()
    and not line.startswith("$")
    and not line.strip().isalpha()
    and line.strip() not in ("END",)
]
#: (line, token) positions whose change keeps the variant: PDMP RZERO..E0 and VX0..VZ0, node
#: coordinates, PARAMETERS' TMAX..ITRAC.


def _card(name):
    """Data line numbers of card ``name`` (up to its END)."""
    start = LINES.index(name)
    end = LINES.index("END", start)
    return [k for k in DATA if start < k < end]


_PDMP, _PARAM, _NODES = _card("PDMP")[0], _card("PARAMETERS")[0], _card("NODE COORDINATES")
SAFE = (
    [(_PDMP, t) for t in (1, 2, 3, 4, 8, 9, 10)]
    + [(_PARAM, t) for t in range(1, 11)]
    + [(k, t) for k in _NODES for t in (1, 2, 3)]
)

VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(
        [
            "0",
            "-0.0",
            "-1",
            "1e300",
            "-1e300",
            "1e-300",
            "1e-322",
            "nan",
            "inf",
            "-inf",
            "1e400",
            "0x10",
            "1,5",
            "abc",
            "",
            "1.2.3",
            "9999999999999999999",
        ]
    ),
    st.integers(min_value=-(10**20), max_value=10**20).map(str),
)


def replace_token(lines, k, t, value):
    tokens = lines[k].split()
    if t >= len(tokens):
        return lines
    tokens[t] = value
    return lines[:k] + ["   " + " ".join(tokens)] + lines[k + 1 :]


def exit_code(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    out = capsys.readouterr()
    assert "Traceback" not in out.err
    return exc.value.code or 0


def check_and_run(tmp_path, lines, capsys):
    deck = tmp_path / "mutant.inp"
    deck.write_text("\n".join(lines) + "\n")
    assert exit_code(["check", str(deck)], capsys) in (0, 1, 2)
    trace = tmp_path / "mutant.trace.txt"
    code = exit_code(
        [
            "run",
            str(deck),
            "--dt",
            "1e-9",
            "--tmax",
            "2e-8",
            "--quiet",
            "--overwrite",
            "--trace",
            str(trace),
        ],
        capsys,
    )
    assert code in (0, 2, 3)


_SETTINGS = dict(
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


@settings(max_examples=40, **_SETTINGS)
@given(where=st.sampled_from(SAFE), value=VALUES)
def test_a_mutated_number_gives_exit_0_to_3(tmp_path, capsys, where, value):
    check_and_run(tmp_path, replace_token(LINES, *where, value), capsys)


@settings(max_examples=25, **_SETTINGS)
@given(k=st.sampled_from(DATA), how=st.sampled_from(["delete", "duplicate", "cut"]))
def test_a_deleted_duplicated_or_cut_line_gives_exit_0_to_3(tmp_path, capsys, k, how):
    lines = list(LINES)
    if how == "delete":
        del lines[k]
    elif how == "duplicate":
        lines.insert(k, lines[k])
    else:
        lines[k] = re.sub(r"\s+\S+\s*$", "", lines[k])
    check_and_run(tmp_path, lines, capsys)


@pytest.mark.validate
@settings(max_examples=150, **_SETTINGS)
@given(k=st.sampled_from(DATA), t=st.integers(0, 12), value=VALUES)
def test_any_mutated_token_gives_exit_0_to_3(tmp_path, capsys, k, t, value):
    # not the start time: TIME = -1e6 is a valid deck asking for 1e15 steps of the fixed window
    if (k, t) != (_PARAM, 0):
        check_and_run(tmp_path, replace_token(LINES, k, t, value), capsys)
