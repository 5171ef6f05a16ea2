"""Hard cases: scenes at the edge of what the solver resolves (docs/hardcases.md)."""

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))  # tests/: shared helpers
