"""The order the test suite runs in.

The shipped decks' runs through the API and the CLI, their studies and their golden replays
each compile the deck's step loop (docs/engine.md, "Compile time") the first time one of them
meets it. In collection order these tests sit in three far-apart files, so pytest-xdist's two
workers met the same deck's loop at about the same time: one compiled it while the other waited
on the compile lock (x3dpd.solver.compile_lock), a core idle for up to half a minute per deck.
They now run first, deck by deck: one worker compiles each loop once and its next two tests
reuse it in the same process, while the other worker starts on the rest of the suite.

The suite also compiles every step loop strictly (``X3DPD_STRICT_STEP_LOOP=1``, inherited by
the processes the tests start): a loop that does not type without SSA fails its test instead of
falling back to numba's slower full pipeline (x3dpd._jit.StepLoopCompiler).
"""

from __future__ import annotations

import os

os.environ.setdefault("X3DPD_STRICT_STEP_LOOP", "1")

#: node-id prefixes of the tests parametrized over decks/*.inp, run deck by deck in this order
BY_DECK = (
    "tests/api/test_api_run.py::test_api_writes_the_same_bytes_as_the_cli[",
    "tests/test_decks.py::test_replay_matches_golden[",
    "tests/study/test_study_decks.py::test_every_shipped_deck_can_be_studied_in_a_tiny_window[",
)


def _order(indexed):
    index, item = indexed
    for rank, prefix in enumerate(BY_DECK):
        if item.nodeid.startswith(prefix):
            return (0, item.nodeid[len(prefix) : -1], rank)
    return (1, "", index)


def pytest_collection_modifyitems(session, config, items):
    items[:] = [item for _, item in sorted(enumerate(items), key=_order)]
