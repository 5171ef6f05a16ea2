"""Files x3dpd writes and reads: trace files (:mod:`.trace`), restart dumps (:mod:`.restart`)
and trace comparison (:mod:`.tracediff`). Formats: ``docs/trace-format.md``."""

from x3dpd.io.restart import RESTART_FORMAT, load_restart, save_restart, write_atomically
from x3dpd.io.trace import (
    COLUMNS,
    DATA_COLUMNS,
    DEFAULT_UNITS,
    TRACE_FORMAT,
    TraceData,
    TraceWarning,
    TraceWriter,
    read_trace,
    sha256_file,
    sidecar_path,
)
from x3dpd.io.tracediff import Difference, DiffReport, compare_traces

__all__ = [
    "COLUMNS",
    "DATA_COLUMNS",
    "DEFAULT_UNITS",
    "RESTART_FORMAT",
    "TRACE_FORMAT",
    "DiffReport",
    "Difference",
    "TraceData",
    "TraceWarning",
    "TraceWriter",
    "compare_traces",
    "load_restart",
    "read_trace",
    "save_restart",
    "sha256_file",
    "sidecar_path",
    "write_atomically",
]
