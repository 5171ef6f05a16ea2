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

The suite's own kernel cache (``.pytest_cache/x3dpd-kernels`` unless ``X3DPD_CACHE_DIR`` is
set), the report of the step loops a run compiled, the ratchet on them (tests/meta/variants.txt)
and ``@pytest.mark.rides`` come from tests/variant_report.py, whose hooks are imported here.
"""

from __future__ import annotations

import os

from variant_report import (  # noqa: F401  (pytest hooks of this conftest)
    pytest_configure,
    pytest_runtest_call,
    pytest_runtest_setup,
    pytest_sessionfinish,
    pytest_terminal_summary,
)

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
