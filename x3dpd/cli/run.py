"""``x3dpd DECK`` / ``x3dpd run DECK``: run a deck, streaming the trace and the energy ledger.

What a run does, in order (docs/running.md):

1. read the deck, build the model, and refuse (exit 2) a deck whose particles start inside a
   wall deeper than the penetration limit (the report's printed Appendix A deck);
2. compile or load the step loop for the scene's effects (:class:`Simulation`);
3. open the trace (``<stem>.trace.txt``) and the energy file (``<stem>.energy.csv``), refusing to
   replace existing ones unless ``--overwrite`` (which keeps ``.bak`` copies);
4. step in chunks of about 0.3 s of wall time, writing every ITRAC-th step, showing progress,
   taking a restart dump (``<trace>.restart.npz``) every TREST of simulated time;
5. print a summary: effects, steps, times, speed and the energy ledger.

Exit status: 0 done, 2 bad input, 3 unstable run (trace kept, its sidecar says "unstable"),
130 interrupted by Ctrl-C (the current chunk is finished, a restart dump written and the trace
flushed; resume with ``--restart``).
"""

from __future__ import annotations

import math
import os
import shlex
import signal
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import click
import numpy as np

from x3dpd import __version__
from x3dpd.cli.progress import Progress
from x3dpd.cli.resume import (
    deck_key,
    load_dump,
    resume_command,
    sidecar_status,
    user_file_hashes,
)
from x3dpd.errors import InputError, UnstableRunError

#: Wall time one ``Simulation.advance`` call should take [s] (chunks adapt to the speed).
CHUNK_SECONDS = 0.3
#: Wall time between trace flushes (sidecar updates) outside restart dumps [s].
FLUSH_SECONDS = 30.0
#: Exit status after SIGINT (128 + 2) and SIGTERM (128 + 15).
EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143


@dataclass
class RunOptions:
    """Everything ``x3dpd run`` was asked to do (the CLI's options, resolved later)."""

    deck: str
    trace: str | None = None
    tmax: float | None = None
    dt: float | None = None
    usrfrc: tuple[str, ...] = ()
    usrfrc_python: bool = False
    motion: tuple[str, ...] = ()
    energy: str | None = None
    plot: str | None = None
    overwrite: bool = False
    restart: bool = False
    friction: str = "regularized"
    quiet: bool = False
    penetration_limit: float = 0.25
    argv: tuple[str, ...] = field(default_factory=tuple)


@click.command("run", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("deck", type=click.Path(exists=True, dir_okay=False))
@click.option("--trace", "trace", metavar="PATH",
              help="Trace file [default: <deck stem>.trace.txt in the current directory].")
@click.option("--tmax", type=float, metavar="T", help="End time [s] [default: the deck's TMAX].")
@click.option("--dt", type=float, metavar="DT", help="Time step [s] [default: the deck's DTMAX].")
@click.option("--usrfrc", multiple=True, metavar="SPEC",
              help="External force: a built-in law (sine:node=25,dof=1,amp=4.84e-3,hz=37.21) or "
                   "a user file force.py (repeatable; adds to the deck's USRFRC card). "
                   "See docs/usrfrc.md.")
@click.option("--usrfrc-python", is_flag=True,
              help="Accept user force files numba cannot compile (runs them in Python, slowly).")
@click.option("--motion", multiple=True, metavar="SPEC",
              help="Prescribed motion (node=25,dof=1,amp=0.01,hz=37.21; repeatable).")
@click.option("--energy", metavar="PATH",
              help="Energy ledger CSV [default: the trace's name with .energy.csv].")
@click.option("--plot", metavar="PNG",
              help="After the run, plot the first TRACE node's x displacement and the energy "
                   "dissipated vs time to this PNG.")
@click.option("--overwrite", is_flag=True,
              help="Replace an existing trace and energy file (the old ones are kept as .bak).")
@click.option("--restart", is_flag=True,
              help="Resume from <trace>.restart.npz (as IREST = 1 in the deck).")
@click.option("--friction", type=click.Choice(["regularized", "coulomb"]), default="regularized",
              show_default=True, help="Tangential contact law.")
@click.option("--quiet", "-q", is_flag=True, help="Print errors only.")
def run(deck, trace, tmax, dt, usrfrc, usrfrc_python, motion, energy, plot, overwrite, restart,
        friction, quiet) -> None:
    """Run DECK: write its trace, energy ledger and restart dumps.

    Exit status: 0 done, 2 bad input, 3 unstable run (diagnosis printed, trace kept),
    130 interrupted (Ctrl-C: restart dump written; resume with --restart).
    """
    opts = RunOptions(deck=deck, trace=trace, tmax=tmax, dt=dt, usrfrc=tuple(usrfrc),
                      usrfrc_python=usrfrc_python, motion=tuple(motion), energy=energy,
                      plot=plot, overwrite=overwrite, restart=restart, friction=friction,
                      quiet=quiet, argv=_command_line())
    status = run_deck(opts)
    if status:
        # SystemExit rather than ctx.exit(): x3dpd.cli.main runs click with standalone_mode=False
        sys.exit(status)


def _command_line() -> tuple[str, ...]:
    """The arguments of the ``x3dpd`` command that runs (for the sidecar), () when x3dpd runs
    inside another program (tests call ``x3dpd.cli.main(argv)``)."""
    prog = os.path.basename(sys.argv[0]) if sys.argv else ""
    return tuple(sys.argv[1:]) if prog in ("x3dpd", "__main__.py") else ()


# ----------------------------------------------------------------------------------------------
# paths


def default_paths(opts: RunOptions) -> tuple[str, str, str]:
    """(trace, energy, restart dump) paths of a run."""
    stem = Path(opts.deck).stem
    trace = opts.trace or f"{stem}.trace.txt"
    if opts.energy:
        energy = opts.energy
    elif trace.endswith(".trace.txt"):
        energy = trace[: -len(".trace.txt")] + ".energy.csv"
    else:
        energy = trace + ".energy.csv"
    return trace, energy, trace + ".restart.npz"


# ----------------------------------------------------------------------------------------------
# the refusal of decks whose particles start inside walls


def initial_penetration_error(model, limit: float, deck_path: str) -> InputError | None:
    """An :class:`InputError` naming the deepest particle that starts inside a wall deeper than
    ``limit`` x its radius (or behind a wall), None when there is none."""
    from x3dpd.model.check import particle_wall_penetrations, particles_outside

    if model.n_particles == 0 or model.tri_nodes.shape[0] == 0:
        return None
    r = model.radius
    found = []  # (depth / R, depth, node id, triangle, behind distance)
    for o in particles_outside(model):
        if o.triangle >= 0:  # centre behind a wall: the sphere is inside it by R + distance
            d = float(r[o.particle] + o.distance)
            found.append((d / r[o.particle], d, o.node_id, o.triangle, o.distance))
    behind = {f[2] for f in found}
    for p in particle_wall_penetrations(model, min_depth_fraction=limit):
        if p.node_id not in behind:
            found.append((p.depth / r[p.particle], p.depth, p.node_id, p.triangle, None))
    if not found:
        return None
    found.sort(key=lambda f: (-f[0], f[2]))
    rel, depth, nid, tri, behind_by = found[0]
    nodes = " ".join(str(int(model.node_ids[i])) for i in model.tri_nodes[tri])
    where = (f"; its centre is {behind_by:.6g} behind the wall, on the outside of the cavity"
             if behind_by is not None else "")
    n = len({f[2] for f in found})
    others = (f" ({n} of the {model.n_particles} particles start inside a wall or behind it)"
              if n > 1 else "")
    return InputError(
        f"{deck_path}: particle node {nid} starts {depth:.6g} ({rel:.3g} R) deep in wall "
        f"triangle {tri + 1} (nodes {nodes}){where}, beyond the penetration limit "
        f"{limit:g} R{others}. The run would blow up at its first step: see "
        f"`x3dpd check {deck_path}`; decks/appendix_a_cube.inp is the repaired geometry of "
        f"the report's Appendix A deck.")


# ----------------------------------------------------------------------------------------------
# signals


class _Interrupts:
    """SIGINT/SIGTERM during the stepping loop: the first one asks the loop to stop after the
    current chunk (restart dump, flushed trace); a second one stops at once."""

    def __init__(self):
        self.signum = 0
        self._old = {}

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._old[sig] = signal.signal(sig, self._handle)
        return self

    def _handle(self, signum, frame):
        if self.signum:
            raise KeyboardInterrupt
        self.signum = signum

    def __exit__(self, *exc):
        for sig, old in self._old.items():
            signal.signal(sig, old)
        return False

    @property
    def exit_status(self) -> int:
        return EXIT_TERMINATED if self.signum == signal.SIGTERM else EXIT_INTERRUPTED


# ----------------------------------------------------------------------------------------------
# the run


@dataclass
class _Stats:
    steps: int = 0              # steps done by this invocation
    timed_steps: int = 0        # steps whose wall time excludes compilation
    timed_seconds: float = 0.0
    wall_start: float = field(default_factory=time.perf_counter)
    setup_seconds: float = 0.0  # reading, building, compiling or loading before stepping
    scale: float = 0.0          # energy scale (largest ledger term seen)
    last_energy: np.ndarray | None = None
    dumps: int = 0
    t_start: float = 0.0        # simulated time this invocation started from


def run_deck(opts: RunOptions) -> int:
    """Run a deck as ``x3dpd run`` does; returns the exit status (0 or 130/143).

    Raises the typed errors (exit 2 / 3) for ``x3dpd.cli.main`` to report.
    """
    from x3dpd.deck import read_deck
    from x3dpd.model.build import build_model

    stats = _Stats()
    deck = read_deck(opts.deck)
    model = build_model(deck, usrfrc=opts.usrfrc, motion=opts.motion)
    trace_path, energy_path, dump_path = default_paths(opts)
    resume = opts.restart or model.irest == 1
    if opts.tmax is not None and not math.isfinite(opts.tmax):
        raise InputError(f"--tmax must be a finite number of seconds, got {opts.tmax}")
    tmax = float(opts.tmax if opts.tmax is not None else model.tmax)
    if not resume:
        err = initial_penetration_error(model, opts.penetration_limit, opts.deck)
        if err is not None:
            raise err

    from x3dpd.solver.simulation import ENERGY_COLUMNS, Simulation

    sim = Simulation(model, usrfrc=opts.usrfrc, motion=opts.motion, dt=opts.dt,
                     friction=opts.friction, penetration_limit=opts.penetration_limit,
                     allow_python_usrfrc=opts.usrfrc_python)
    dt, itrac, t0 = sim.dt, sim.itrac, model.t0
    n_end = int(round((tmax - t0) / dt))
    if n_end < 0:
        raise InputError(f"TMAX {tmax:g} s is before the start time {t0:g} s")
    trest_steps = int(round(model.trest / dt)) if model.trest > 0 else 0

    from x3dpd.io.trace import sha256_file

    options = {"usrfrc": list(opts.usrfrc), "motion": list(opts.motion),
               "friction": opts.friction, "tmax": tmax, "usrfrc_python": opts.usrfrc_python,
               "usrfrc_files": user_file_hashes(list(model.usrfrc) + list(opts.usrfrc))}
    deck_sha = sha256_file(opts.deck)
    key = deck_key(deck)
    sidecar = {
        "deck_path": opts.deck, "deck_sha256": deck_sha, "dt": dt, "itrac": itrac,
        "effects": sorted(sim.effects), "title": model.title, "t0": t0, "tmax": tmax,
        "usrfrc": list(model.usrfrc) + list(opts.usrfrc), "motion": list(opts.motion),
        "friction": opts.friction, "energy_file": energy_path, "restart_file": dump_path,
        "command": "x3dpd " + shlex.join(opts.argv) if opts.argv else None,
    }

    meta = None
    if resume:
        meta = load_dump(dump_path, opts, sim, key, options, model)
        sidecar["resumed_at"] = meta["time"]
        if meta["step"] >= n_end:
            raise InputError(f"{dump_path}: the restart dump is at t = {meta['time']:.9g} s, "
                             f"not before TMAX {tmax:.9g} s: nothing to run (give a larger "
                             "--tmax)")

    writer, ewriter = _open_outputs(opts, trace_path, energy_path, sim, sidecar, meta,
                                    ENERGY_COLUMNS)
    if not resume:
        try:  # a stale dump of an earlier run must not be resumed against this trace
            os.unlink(dump_path)
        except FileNotFoundError:
            pass

    def dump(reason: str) -> None:
        writer.flush()
        ewriter.flush()
        from x3dpd.io.restart import save_restart

        save_restart(dump_path, sim.state.to_arrays(), {
            "reason": reason, "x3dpd_version": __version__,
            "deck_path": opts.deck, "deck_abspath": os.path.abspath(opts.deck),
            "deck_sha256": deck_sha, "deck_key": key, "dt": dt, "itrac": itrac, "t0": t0,
            "step": int(sim.state.step), "time": sim.time,
            "trace": {"path": trace_path, "bytes": writer.tell(),
                      "blocks": writer.blocks_written},
            "energy": {"path": energy_path, "bytes": ewriter.tell(),
                       "rows": ewriter.rows_written},
            "options": options, "energy_scale": stats.scale,
            "effects": sorted(sim.effects),
        })
        stats.dumps += 1

    progress = Progress(opts.quiet, tmax)
    status = "complete"
    exit_status = 0
    if meta is not None:
        stats.scale = float(meta.get("energy_scale", 0.0))
    try:
        with writer, ewriter:
            if not resume:
                snap = sim.snapshot()
                writer.write_block(snap.times, snap.data)
                ewriter.write_rows(snap.energy)
                _note_energy(stats, snap.energy, sim)
            stats.setup_seconds = time.perf_counter() - stats.wall_start
            stats.t_start = sim.time
            with _Interrupts() as intr:
                _step_loop(sim, writer, ewriter, n_end, trest_steps, stats, progress, dump,
                           intr)
                if intr.signum:
                    dump("interrupted")
                    status = "interrupted"
                    exit_status = intr.exit_status
                    writer.close("interrupted")
    except UnstableRunError:
        progress.done()
        if not opts.quiet:
            _summary(opts, sim, stats, trace_path, energy_path, "unstable")
        _maybe_plot(opts, trace_path, energy_path, model)
        raise
    except KeyboardInterrupt:
        progress.done()
        raise
    progress.done()
    if not opts.quiet:
        _summary(opts, sim, stats, trace_path, energy_path, status)
    if status == "interrupted":  # the one line --quiet keeps: it says how to go on
        click.echo(f"x3dpd: interrupted at t = {sim.time:.9g} s; restart dump {dump_path} "
                   f"written. Resume with: x3dpd {resume_command(opts)}", err=True)
    _maybe_plot(opts, trace_path, energy_path, model)
    return exit_status


def _open_outputs(opts, trace_path, energy_path, sim, sidecar, meta, columns):
    """The trace and energy writers, new or resumed at the dump's offsets."""
    from x3dpd.io.energy import EnergyWriter, copy_backup
    from x3dpd.io.trace import TraceWriter

    ids = sim.model.node_ids[sim.trace_nodes]
    if meta is None:
        if os.path.lexists(energy_path) and not opts.overwrite:
            raise InputError(f"energy file {energy_path} already exists; pass --overwrite to "
                             f"replace it (the old one is kept as {energy_path}.bak) or choose "
                             "another --energy path")
        writer = TraceWriter(trace_path, ids, sidecar, overwrite=opts.overwrite)
        try:
            ewriter = EnergyWriter(energy_path, columns, overwrite=opts.overwrite)
        except BaseException:
            writer.close("interrupted")
            raise
        return writer, ewriter
    tr, en = meta["trace"], meta["energy"]
    complete = sidecar_status(trace_path) == "complete"
    writer = TraceWriter(trace_path, ids, sidecar, overwrite=opts.overwrite,
                         append_at=(int(tr["bytes"]), int(tr["blocks"])))
    try:
        if complete and opts.overwrite and os.path.isfile(energy_path):
            copy_backup(energy_path)
        ewriter = EnergyWriter(energy_path, columns,
                               append_at=(int(en["bytes"]), int(en["rows"])))
    except BaseException:
        writer.close("interrupted")
        raise
    return writer, ewriter


def _note_energy(stats: _Stats, energy: np.ndarray, sim) -> None:
    if energy.shape[0]:
        stats.scale = max(stats.scale, float(np.abs(energy[:, 1:11]).max()),
                          abs(float(sim.state.e_ref)))
        stats.last_energy = energy[-1].copy()


def _step_loop(sim, writer, ewriter, n_end, trest_steps, stats, progress, dump, intr) -> None:
    chunk = max(1, min(sim.itrac, 1000))
    rate = 0.0
    last_flush = time.perf_counter()
    first = True
    while sim.state.step < n_end and not intr.signum:
        step = sim.state.step
        target = min(n_end, step + chunk)
        if trest_steps:
            next_dump = (step // trest_steps + 1) * trest_steps
            target = min(target, next_dump)
        compile_before = sim.compile_seconds
        t = time.perf_counter()
        try:
            block = sim.advance(target - step)
        except UnstableRunError as exc:
            # write the rows computed before the failure, so the kept trace ends where the
            # run went wrong
            partial = getattr(exc, "block", None)
            if partial is not None and partial.times.shape[0]:
                writer.write_block(partial.times, partial.data)
                ewriter.write_rows(partial.energy)
            raise
        wall = time.perf_counter() - t
        done = sim.state.step - step
        writer.write_block(block.times, block.data)
        ewriter.write_rows(block.energy)
        _note_energy(stats, block.energy, sim)
        stats.steps += done
        compiled = sim.compile_seconds > compile_before
        if not (first and compiled):
            stats.timed_steps += done
            stats.timed_seconds += wall
            inst = done / wall if wall > 0 else float("inf")
            rate = inst if rate == 0.0 else 0.5 * rate + 0.5 * inst
            if done == target - step and math.isfinite(rate):
                chunk = int(min(max(rate * CHUNK_SECONDS, chunk / 4, 1), chunk * 4, 1e9))
        elif done == target - step:
            chunk = min(chunk * 4, max(1, n_end))
        first = False
        if trest_steps and sim.state.step % trest_steps == 0 and sim.state.step < n_end:
            dump("trest")
            last_flush = time.perf_counter()
        elif time.perf_counter() - last_flush > FLUSH_SECONDS:
            writer.flush()
            ewriter.flush()
            last_flush = time.perf_counter()
        res = _relative_residual(stats)
        left = n_end - sim.state.step
        eta = left / rate if rate > 0 else float("nan")
        progress.update(sim.time, rate, eta, res, force=sim.state.step >= n_end)


def _relative_residual(stats: _Stats) -> float:
    if stats.last_energy is None or stats.scale <= 0:
        return 0.0
    return float(stats.last_energy[11]) / stats.scale


def _summary(opts, sim, stats, trace_path, energy_path, status) -> None:
    from x3dpd.solver.simulation import ENERGY_COLUMNS

    wall = time.perf_counter() - stats.wall_start
    compile_s = float(sim.compile_seconds) + float(getattr(sim, "_load_seconds", 0.0))
    rate = stats.timed_steps / stats.timed_seconds if stats.timed_seconds > 0 else float("nan")
    lines = [f"x3dpd: {opts.deck} -> {trace_path}, {energy_path} ({status})",
             f"  effects        {', '.join(sorted(sim.effects)) or 'none'}",
             f"  steps          {stats.steps} this run; t = {stats.t_start:.9g} .. "
             f"{sim.time:.9g} s at dt {sim.dt:.6g} s, trace every {sim.itrac} steps",
             f"  wall time      {wall:.2f} s (setup and first-call compile/load "
             f"{compile_s:.2f} s)",
             ]
    if math.isfinite(rate) and rate > 0:
        lines.append(f"  speed          {rate:,.0f} steps/s, {1e6 / rate:.3g} us/step")
    if stats.dumps:
        lines.append(f"  restart dumps  {stats.dumps} written to {trace_path}.restart.npz")
    e = stats.last_energy
    if e is not None:
        lines.append(f"  energy ledger at t = {e[0]:.9g} s (deck units, lbf in for inch decks)")
        for name, v in zip(ENERGY_COLUMNS[1:11], e[1:11]):
            lines.append(f"    {name:<24} {v: .6e}")
        lines.append(f"    {'dissipated (total)':<24} {e[6] + e[7] + e[8]: .6e}")
        lines.append(f"    {'residual':<24} {e[11]: .6e} ({_relative_residual(stats):+.2e} of the "
                     f"energy scale {stats.scale:.6g})")
    click.echo("\n".join(lines))


def _maybe_plot(opts, trace_path, energy_path, model) -> None:
    if not opts.plot:
        return
    from x3dpd.analysis.plots import plot_run

    from x3dpd.io.energy import read_energy

    ids = model.node_ids[model.trace_nodes].tolist()
    try:
        energy = read_energy(energy_path) if energy_path and os.path.isfile(energy_path) else None
        plot_run(opts.plot, trace_path, ids, energy, title=model.title)
    except (OSError, ValueError, InputError) as exc:
        click.echo(f"x3dpd: warning: could not write the plot {opts.plot}: {exc}", err=True)
        return
    if not opts.quiet:
        click.echo(f"  plot           {opts.plot}")
