"""Short traces of every shipped deck that runs, shared by the post-processing command tests."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import DECKS, SHORT_RUNS, run_cli


@pytest.fixture(scope="session")
def short_traces(tmp_path_factory) -> dict[str, Path]:
    """deck name -> trace path of a short run in a temporary folder (decks given by path)."""
    out = {}
    folder = tmp_path_factory.mktemp("short_traces")
    for name, tmax in SHORT_RUNS.items():
        trace = folder / name.replace(".inp", ".trace.txt")
        assert run_cli(DECKS / name, "--tmax", tmax, "--trace", trace, "--quiet") == 0
        out[name] = trace
    return out
