"""``x3dpd DECK`` / ``x3dpd run DECK``: run a deck, streaming the trace and the energy ledger.

A thin layer over :func:`x3dpd.api.run` (docs/running.md): it resolves the options, shows
progress, prints the summary and draws ``--plot``.

Exit status: 0 done, 2 bad input, 3 unstable run (trace kept, its sidecar says "unstable"),
130 interrupted by Ctrl-C (the current chunk is finished, a restart dump written and the trace
flushed; resume with ``--restart``).
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass, field

import click

from x3dpd.api import FRICTION_LAWS
from x3dpd.api.config import ENERGY_TOLERANCE, PENETRATION_LIMIT, RunConfig, run_config
from x3dpd.api.outputs import check_writable, default_paths as _default_paths
from x3dpd.cli.progress import CompileTicker, Progress
from x3dpd.cli.run_summary import format_summary
from x3dpd.cli.resume import resume_command
from x3dpd.cli.temperature_option import temperature_option
from x3dpd.errors import InputError, UnstableRunError


@dataclass
class RunOptions:
    """The command line of ``x3dpd run`` as typed (what the resume line repeats); the run
    itself is its :meth:`config`, the API's :class:`~x3dpd.api.config.RunConfig`."""

    deck: str
    trace: str | None = None
    tmax: float | None = None
    dt: float | str | None = None
    usrfrc: tuple[str, ...] = ()
    usrfrc_add: bool = False
    usrfrc_python: bool = False
    motion: tuple[str, ...] = ()
    energy: str | None = None
    plot: str | None = None
    overwrite: bool = False
    restart: bool = False
    friction: str | None = None
    temperature: str | None = None
    quiet: bool = False
    penetration_limit: float = PENETRATION_LIMIT
    energy_tolerance: float = ENERGY_TOLERANCE
    threads: int = 1
    trace_nodes: str | None = None
    argv: tuple[str, ...] = field(default_factory=tuple)

    def config(self, **callbacks) -> RunConfig:
        """The run these options ask for (the deck read and every option resolved and checked
        by :func:`x3dpd.api.config.run_config`), writing its files and keeping no rows in
        memory, with ``callbacks`` (``progress``, ``on_compile``)."""
        from x3dpd.api.runner import command_line

        trace, energy, _ = default_paths(self)
        return run_config(
            self.deck,
            tmax=self.tmax,
            dt=self.dt,
            usrfrc=self.usrfrc,
            usrfrc_mode="add" if self.usrfrc_add else "replace",
            motion=self.motion,
            friction=self.friction,
            temperature=self.temperature,
            trace=trace,
            energy=energy,
            overwrite=self.overwrite,
            restart=self.restart,
            keep_trace=False,
            usrfrc_python=self.usrfrc_python,
            penetration_limit=self.penetration_limit,
            energy_tolerance=self.energy_tolerance,
            threads=self.threads,
            trace_nodes=_trace_nodes(self.trace_nodes),
            handle_signals=True,
            command=command_line(self.argv),
            **callbacks,
        )


@click.command("run", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("deck", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--trace",
    "trace",
    metavar="PATH",
    help="Trace file [default: <deck stem>.trace.txt in the current directory].",
)
@click.option(
    "--trace-nodes",
    metavar="WHICH",
    help="Nodes to trace: structure (the TRACE card's structure nodes, without its "
    "particles: a far smaller trace for frf, spectrum or sweep) or a comma list of node "
    "ids [default: the deck's TRACE card].",
)
@click.option("--tmax", type=float, metavar="T", help="End time [s] [default: the deck's TMAX].")
@click.option(
    "--dt",
    metavar="DT",
    help="Time step [s], or auto: a step chosen by accuracy within DTMIN ... DTMAX "
    "[default: the deck's DTMAX; auto when its DTMIN < DTMAX].",
)
@click.option(
    "--usrfrc",
    multiple=True,
    metavar="SPEC",
    help="External force: a built-in law (sine:node=25,dof=1,amp=4.84e-3,hz=37.21) or "
    "a user file force.py (repeatable). Replaces the deck's USRFRC card (the "
    "summary says so); see --usrfrc-add and docs/usrfrc.md.",
)
@click.option(
    "--usrfrc-add",
    is_flag=True,
    help="Add the --usrfrc forces to the deck's USRFRC card instead of replacing it.",
)
@click.option(
    "--usrfrc-python",
    is_flag=True,
    help="Accept user force files numba cannot compile (runs them in Python, slowly).",
)
@click.option(
    "--motion",
    multiple=True,
    metavar="SPEC",
    help="Prescribed motion (node=25,dof=1,amp=0.01,hz=37.21; repeatable).",
)
@click.option(
    "--energy",
    metavar="PATH",
    help="Energy ledger CSV [default: the trace's name with .energy.csv].",
)
@click.option(
    "--plot",
    metavar="PNG",
    help="After the run, plot the first TRACE node's x displacement and the energy "
    "dissipated vs time to this PNG.",
)
@click.option(
    "--overwrite",
    is_flag=True,
    help="Replace an existing trace and energy file (the old ones are kept as .bak).",
)
@click.option(
    "--restart",
    is_flag=True,
    help="Resume from <trace>.restart.npz (as IREST = 1 in the deck); with a later "
    "--tmax, extends a finished run.",
)
@click.option(
    "--friction",
    type=click.Choice(FRICTION_LAWS),
    default=None,
    help="Tangential contact law for the whole run (docs/physics.md), over the deck's "
    "FRICTION card  [default: the card's, else regularized]",
)
@temperature_option
@click.option(
    "--energy-tolerance",
    type=click.FloatRange(min=0.0, min_open=True),
    default=ENERGY_TOLERANCE,
    show_default=True,
    metavar="FRACTION",
    help="Stop (exit 3) when the energy ledger's residual exceeds this fraction of "
    'the energy scale (docs/physics.md, "Stopping a run that goes unstable").',
)
@click.option(
    "--threads",
    metavar="N",
    envvar="X3DPD_THREADS",
    default="1",
    show_default=True,
    help='Threads of the pair contacts (docs/engine.md, "Threads"): a number up to '
    "the cores numba sees (NUMBA_NUM_THREADS), or auto for all; the results are "
    "the same bytes. Pays for beds of thousands of particles. Environment: "
    "X3DPD_THREADS.",
)
@click.option("--quiet", "-q", is_flag=True, help="Print errors only.")
def run(
    deck,
    trace,
    trace_nodes,
    tmax,
    dt,
    usrfrc,
    usrfrc_add,
    usrfrc_python,
    motion,
    energy,
    plot,
    overwrite,
    restart,
    friction,
    temperature,
    energy_tolerance,
    threads,
    quiet,
) -> None:
    """Run DECK: write its trace, energy ledger and restart dumps.

    Exit status: 0 done, 2 bad input, 3 unstable run (diagnosis printed, trace kept),
    130 interrupted (Ctrl-C: restart dump written; resume with --restart).
    """
    from x3dpd.api.runner import thread_count

    opts = RunOptions(
        deck=deck,
        trace=trace,
        tmax=tmax,
        dt=_step(dt),
        usrfrc=tuple(usrfrc),
        usrfrc_add=usrfrc_add,
        usrfrc_python=usrfrc_python,
        motion=tuple(motion),
        energy=energy,
        plot=plot,
        overwrite=overwrite,
        restart=restart,
        friction=friction,
        temperature=temperature,
        quiet=quiet,
        energy_tolerance=energy_tolerance,
        threads=thread_count(threads, "--threads"),
        trace_nodes=trace_nodes,
        argv=_command_line(),
    )
    status = run_deck(opts)
    if status:
        # SystemExit rather than ctx.exit(): x3dpd.cli.main runs click with standalone_mode=False
        sys.exit(status)


def _step(text: str | None) -> float | str | None:
    """``--dt``: a positive number of seconds or ``auto``."""
    if text is None:
        return None
    if text.strip().lower() == "auto":
        return "auto"
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"--dt: expected a time step in s or auto, got {text!r}") from None
    return value


def _trace_nodes(text: str | None) -> str | tuple[int, ...] | None:
    """``--trace-nodes``: ``structure`` or a comma list of node ids."""
    if text is None or text.strip().lower() == "structure":
        return text and "structure"
    try:
        return tuple(int(part) for part in text.split(","))
    except ValueError:
        raise InputError(f"--trace-nodes {text!r}: expected structure or node ids (9,12)") from None


def _command_line() -> tuple[str, ...]:
    """The arguments of the ``x3dpd`` command that runs (for the sidecar), () when x3dpd runs
    inside another program (tests call ``x3dpd.cli.main(argv)``)."""
    prog = os.path.basename(sys.argv[0]) if sys.argv else ""
    return tuple(sys.argv[1:]) if prog in ("x3dpd", "__main__.py") else ()


def default_paths(opts: RunOptions) -> tuple[str, str, str]:
    """(trace, energy, restart dump) paths of a run."""
    return _default_paths(opts.deck, opts.trace, opts.energy)


def run_deck(opts: RunOptions) -> int:
    """Run a deck as ``x3dpd run`` does; returns the exit status (0 or 130/143).

    Raises the typed errors (exit 2 / 3) for ``x3dpd.cli.main`` to report.
    """
    from x3dpd.api.runner import run as api_run

    trace_path, energy_path, _ = default_paths(opts)
    if opts.plot:
        if not opts.plot.lower().endswith(".png"):
            raise InputError(
                f"--plot {opts.plot}: the plot is a PNG file; give a name ending in .png"
            )
        check_writable(opts.plot, "--plot")
    progress = Progress(opts.quiet, float("nan"))

    ticker = []  # the compile-progress line while the step loop compiles

    def stop_ticker():
        while ticker:
            ticker.pop().stop()

    def on_progress(t, rate, eta, residual, t_end):
        stop_ticker()
        progress.tmax = t_end
        progress.update(t, rate, eta, residual, force=t >= t_end)

    def on_compile(message) -> None:
        if not opts.quiet:
            ticker.append(CompileTicker(message, getattr(message, "expected_s", 30.0)))

    config = opts.config(progress=None if opts.quiet else on_progress, on_compile=on_compile)
    try:
        result = api_run(config)
    except UnstableRunError as exc:
        stop_ticker()
        progress.done()
        partial = getattr(exc, "result", None)
        if partial is not None:
            partial.summary["t_end"] = getattr(exc, "time", None) or partial.summary["t_end"]
            if not opts.quiet:
                click.echo(format_summary(opts.deck, partial.summary))
            _maybe_plot(opts, trace_path, energy_path, partial.model)
        raise
    except KeyboardInterrupt:
        stop_ticker()
        progress.done()
        raise
    finally:
        stop_ticker()
    progress.done()
    s = result.summary
    if not opts.quiet:
        click.echo(format_summary(opts.deck, s))
    if s["status"] == "interrupted":  # the one line --quiet keeps: it says how to go on
        click.echo(
            f"x3dpd: interrupted at t = {s['t_end']:.9g} s; restart dump "
            f"{s['restart_file']} written. Resume with: x3dpd {resume_command(opts)}",
            err=True,
        )
    _maybe_plot(opts, trace_path, energy_path, result.model)
    return int(s.get("exit_status", 0))


def _maybe_plot(opts, trace_path, energy_path, model) -> None:
    if not opts.plot or model is None:
        return
    from x3dpd.api.figures import plot_run
    from x3dpd.api.traces import read_energy

    ids = model.node_ids[model.trace_nodes].tolist()
    try:
        energy = read_energy(energy_path) if energy_path and os.path.isfile(energy_path) else None
        plot_run(opts.plot, trace_path, ids, energy, title=model.title)
    except (OSError, ValueError, InputError) as exc:
        click.echo(f"x3dpd: warning: could not write the plot {opts.plot}: {exc}", err=True)
        return
    if not opts.quiet:
        click.echo(f"  plot           {opts.plot}")
