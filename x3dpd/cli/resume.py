"""The command line that resumes an interrupted ``x3dpd run`` from its restart dump
(docs/running.md, "Restart"). The dump itself and the check that it belongs to the run are the
API's (:mod:`x3dpd.api.outputs`)."""

from __future__ import annotations

import shlex
from typing import TYPE_CHECKING

from x3dpd.api.config import ENERGY_TOLERANCE

if TYPE_CHECKING:
    from x3dpd.cli.run import RunOptions


def resume_command(opts: RunOptions) -> str:
    """The arguments that resume this run from its restart dump."""
    args = [opts.deck, "--restart"]
    if opts.trace:
        args += ["--trace", opts.trace]
    if opts.energy:
        args += ["--energy", opts.energy]
    if opts.trace_nodes:
        args += ["--trace-nodes", opts.trace_nodes]
    for spec in opts.usrfrc:
        args += ["--usrfrc", spec]
    if opts.usrfrc_add:
        args.append("--usrfrc-add")
    for spec in opts.motion:
        args += ["--motion", spec]
    if opts.usrfrc_python:
        args.append("--usrfrc-python")
    if opts.dt is not None:
        args += ["--dt", opts.dt if isinstance(opts.dt, str) else repr(opts.dt)]
    if opts.tmax is not None:
        args += ["--tmax", repr(opts.tmax)]
    if opts.friction:
        args += ["--friction", opts.friction]
    if opts.temperature is not None:
        args += ["--temperature", opts.temperature]
    if opts.energy_tolerance != ENERGY_TOLERANCE:
        args += ["--energy-tolerance", repr(opts.energy_tolerance)]
    if opts.threads != 1:
        args += ["--threads", str(opts.threads)]
    return shlex.join(args)
