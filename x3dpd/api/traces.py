"""Reading what a run wrote, for the tools above the API (re-exports; docs/trace-format.md):

* :func:`read_trace` (whole trace, :class:`~x3dpd.io.trace.TraceData`), :class:`TraceWarning`
  (a truncated or damaged trace read as far as it goes);
* :func:`trace_info` -> :class:`TraceInfo` (the sidecar), :func:`iter_blocks` (a trace read a
  block at a time, memory bounded), :func:`sha256_file` (the deck a sidecar names);
* :func:`read_energy` and :data:`ENERGY_COLUMNS` -- the energy ledger file and its columns
  (docs/physics.md, "Energy ledger"); :data:`ROLLING_COLUMN`, the one a scene with a rolling
  law adds after them;
* :func:`compare_traces` -- ``x3dpd tracediff``'s comparison of two traces.
"""

from __future__ import annotations

from x3dpd.io.energy import read_energy
from x3dpd.io.trace import TraceWarning, read_trace, sha256_file
from x3dpd.io.trace_stream import TraceInfo, iter_blocks, trace_info
from x3dpd.io.tracediff import compare_traces
from x3dpd.solver.simulation import ENERGY_COLUMNS, ROLLING_COLUMN

__all__ = [
    "ENERGY_COLUMNS",
    "ROLLING_COLUMN",
    "TraceInfo",
    "TraceWarning",
    "compare_traces",
    "iter_blocks",
    "read_energy",
    "read_trace",
    "sha256_file",
    "trace_info",
]
