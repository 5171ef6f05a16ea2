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
from x3dpd.api.outputs import check_writable, default_paths as _default_paths
from x3dpd.cli.progress import CompileTicker, Progress
from x3dpd.cli.resume import resume_command
from x3dpd.cli.temperature_option import temperature_option
from x3dpd.errors import InputError, UnstableRunError


@dataclass
class RunOptions:
    """Everything ``x3dpd run`` was asked to do (the CLI's options, resolved later)."""

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
    penetration_limit: float = 0.25
    energy_tolerance: float = 0.05
    threads: int = 1
    trace_nodes: str | None = None
    argv: tuple[str, ...] = field(default_factory=tuple)


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
    default=0.05,
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
    from x3dpd.api.runner import command_line, run as api_run

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

    try:
        result = api_run(
            opts.deck,
            tmax=opts.tmax,
            dt=opts.dt,
            usrfrc=opts.usrfrc,
            usrfrc_mode="add" if opts.usrfrc_add else "replace",
            motion=opts.motion,
            friction=opts.friction,
            temperature=opts.temperature,
            trace=trace_path,
            energy=energy_path,
            overwrite=opts.overwrite,
            restart=opts.restart,
            keep_trace=False,
            progress=None if opts.quiet else on_progress,
            on_compile=on_compile,
            usrfrc_python=opts.usrfrc_python,
            penetration_limit=opts.penetration_limit,
            energy_tolerance=opts.energy_tolerance,
            threads=opts.threads,
            trace_nodes=_trace_nodes(opts.trace_nodes),
            handle_signals=True,
            command=command_line(opts.argv),
        )
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


def format_summary(deck: str, s: dict) -> str:
    """The summary ``x3dpd run`` prints (docs/running.md, "Progress and summary")."""
    from x3dpd.api.traces import ENERGY_COLUMNS

    lines = [
        f"x3dpd: {deck} -> {s['trace_file']}, {s['energy_file']} ({s['status']})",
        f"  effects        {', '.join(s['effects']) or 'none'}",
    ]
    if s.get("usrfrc_replaced"):
        lines.append(
            f"  drive          {'; '.join(s['usrfrc'])} (replaces the deck's USRFRC "
            f"{'; '.join(s['usrfrc_replaced'])}; --usrfrc-add adds instead)"
        )
    for path in s.get("code_files", ()):
        lines.append(f"  code run       {path} (a USRFRC Python file: this run executed it)")
    step = s.get("step")
    if step:
        at = (
            f"at a step chosen by accuracy ({step['min']:.4g} .. {step['max']:.4g} s, mean "
            f"{step['mean']:.4g} s since t0; bounds {step['dtmin']:.4g} .. "
            f"{step['dtmax']:.4g} s), trace every {s['itrac'] * s['dt']:.6g} s"
            if step["steps"]
            else "at a step chosen by accuracy"
        )
    else:
        at = f"at dt {s['dt']:.6g} s, trace every {s['itrac']} steps"
    lines += [
        f"  steps          {s['steps']} this run; t = {s['t_start']:.9g} .. {s['t_end']:.9g} s "
        f"{at}",
        f"  wall time      {s['wall_s']:.2f} s (setup and first-call compile/load "
        f"{s['compile_s']:.2f} s)",
    ]
    rate = s["steps_per_s"]
    if rate == rate and rate > 0:
        lines.append(f"  speed          {rate:,.0f} steps/s, {1e6 / rate:.3g} us/step")
    if s["dumps"]:
        lines.append(f"  restart dumps  {s['dumps']} written to {s['restart_file']}")
    e = s["last_energy"]
    if e is not None:
        from x3dpd.units import labels_for

        lab = labels_for(s.get("units"))
        lines.append(
            f"  energy ledger at t = {e['time']:.9g} {lab['time']} (energies in {lab['energy']})"
        )
        names = ENERGY_COLUMNS[1:11] + (
            ("dissipated_rolling",) if "dissipated_rolling" in e else ()
        )
        for name in names:
            lines.append(f"    {name:<24} {e[name]: .6e}")
        total = (
            e["dissipated_viscoelastic"]
            + e["dissipated_friction"]
            + e["dissipated_dampers"]
            + e.get("dissipated_rolling", 0.0)
        )
        lines.append(f"    {'dissipated (total)':<24} {total: .6e}")
        lines.append(
            f"    {'residual':<24} {e['residual']: .6e} ({s['residual']:+.2e} of the "
            f"energy scale {s['energy_scale']:.6g})"
        )
    return "\n".join(lines)


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
