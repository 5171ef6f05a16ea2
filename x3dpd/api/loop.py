"""The stepping loop of :func:`x3dpd.api.run`: chunks of steps sized to a wall time, rows to the
trace, energy file and recorder, restart dumps every TREST, progress, early stop, and SIGINT /
SIGTERM asking for a clean stop after the current chunk."""

from __future__ import annotations

import math
import signal
import threading
import time
from dataclasses import dataclass, field

import numpy as np

from x3dpd.api.results import Chunk, Recorder
from x3dpd.errors import InputError, UnstableRunError

#: Wall time one ``Simulation.advance`` call should take [s] (chunks adapt to the speed).
CHUNK_SECONDS = 0.3
#: Wall time between trace flushes (sidecar updates) outside restart dumps [s].
FLUSH_SECONDS = 30.0
#: With a ``stop`` callback, it is asked after every this many trace rows (the default of
#: ``run(stop_every=)``): a fixed step count, so that where a run stops -- and the state a
#: chained sweep point starts from -- does not depend on how fast the machine ran.
STOP_CHECK_ROWS = 20
#: Exit status after SIGINT (128 + 2) and SIGTERM (128 + 15).
EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143


class Interrupts:
    """SIGINT/SIGTERM during the stepping loop: the first one asks the loop to stop after the
    current chunk (restart dump, flushed trace); a second one stops at once."""

    def __init__(self, enabled: bool):
        self.enabled = enabled
        self.signum = 0
        self._old = {}

    def __enter__(self):
        if self.enabled and threading.current_thread() is threading.main_thread():
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


@dataclass
class Stats:
    steps: int = 0  # steps done by this call
    timed_steps: int = 0  # steps whose wall time excludes compilation
    timed_seconds: float = 0.0
    wall_start: float = field(default_factory=time.perf_counter)
    setup_seconds: float = 0.0
    last_energy: np.ndarray | None = None
    dumps: int = 0
    t_start: float = 0.0


class Sink:
    """Where rows go: the trace and energy writers (when writing files) and the recorder."""

    def __init__(self, writer, ewriter, recorder: Recorder):
        self.writer, self.ewriter, self.recorder = writer, ewriter, recorder
        self.on_close = None  # called before the trace is closed (sidecar additions)

    def write(self, times, data, energy) -> None:
        if self.writer is not None:
            self.writer.write_block(times, data)
            self.ewriter.write_rows(energy)
        self.recorder.add(times, data, energy)

    def flush(self) -> None:
        if self.writer is not None:
            self.writer.flush()
            self.ewriter.flush()

    def close(self, status: str) -> None:
        if self.writer is not None:
            if self.on_close is not None:
                self.on_close()
            self.writer.close(status)

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if self.writer is not None:
            try:
                if self.on_close is not None:
                    self.on_close()
                self.writer.__exit__(exc_type, exc, tb)
            finally:
                self.ewriter.__exit__(exc_type, exc, tb)
        return False


def note_energy(stats: Stats, energy: np.ndarray) -> None:
    if energy.shape[0]:
        stats.last_energy = energy[-1].copy()


def step_loop(
    sim,
    sink,
    n_end,
    trest_steps,
    stats,
    progress,
    dump,
    intr,
    stop,
    ids,
    stop_every: int = STOP_CHECK_ROWS,
) -> bool:
    """Advance to step ``n_end``; return True when ``stop`` ended the run early (asked after
    every ``stop_every`` trace rows)."""
    # steps per sim.advance call: adapted to the measured speed (CHUNK_SECONDS), except with a
    # stop callback, where a fixed count keeps the stopping step deterministic
    fixed_chunk = stop is not None
    chunk = sim.itrac * max(1, int(stop_every)) if fixed_chunk else max(1, min(sim.itrac, 1000))
    rate = 0.0
    last_flush = time.perf_counter()
    first = True
    while sim.clock < n_end and not intr.signum:
        step = sim.clock
        target = min(n_end, step + chunk)
        if not fixed_chunk:
            # an adapted chunk ends where the run's checks read the whole state (a multiple of
            # sim.audit_steps): what they find, and say, is then the same however fast the
            # machine ran
            audit = sim.audit_steps
            target = min(n_end, -(-target // audit) * audit)
        if trest_steps:
            next_dump = (step // trest_steps + 1) * trest_steps
            target = min(target, next_dump)
        compile_before = sim.compile_seconds
        t = time.perf_counter()
        try:
            block = sim.advance(target - step)
        except UnstableRunError as exc:
            # write the rows computed before the failure, up to the step the diagnosis names
            partial = getattr(exc, "block", None)
            if partial is not None and partial.times.shape[0]:
                keep = rows_up_to(partial.times, exc, sim)
                sink.write(partial.times[:keep], partial.data[:keep], partial.energy[:keep])
                note_energy(stats, partial.energy[:keep])
            stats.steps += sim.clock - step
            raise
        wall = time.perf_counter() - t
        done = sim.clock - step
        sink.write(block.times, block.data, block.energy)
        note_energy(stats, block.energy)
        stats.steps += done
        compiled = sim.compile_seconds > compile_before
        if not (first and compiled):
            stats.timed_steps += done
            stats.timed_seconds += wall
            inst = done / wall if wall > 0 else float("inf")
            rate = inst if rate == 0.0 else 0.5 * rate + 0.5 * inst
            if done == target - step and math.isfinite(rate) and not fixed_chunk:
                chunk = int(min(max(rate * CHUNK_SECONDS, chunk / 4, 1), chunk * 4, 1e9))
        elif done == target - step and not fixed_chunk:
            chunk = min(chunk * 4, max(1, n_end))
        first = False
        if trest_steps and sim.clock % trest_steps == 0 and sim.clock < n_end:
            dump("trest")
            last_flush = time.perf_counter()
        elif time.perf_counter() - last_flush > FLUSH_SECONDS:
            sink.flush()
            last_flush = time.perf_counter()
        if progress is not None:
            left = n_end - sim.clock
            eta = left / rate if rate > 0 else float("nan")
            progress(
                sim.time, rate, eta, relative_residual(stats, sim), sim.model.t0 + n_end * sim.dt
            )
        if stop is not None and block.times.shape[0]:
            if stop(Chunk(block.times, ids, block.data, block.energy)):
                return True
    return False


#: Most steps a run may ask for (2^53: beyond it step * dt no longer counts every step).
MAX_STEPS = 2**53


def step_count(steps: float, what: str) -> int:
    """round(steps), or an InputError when it is not a countable number of steps."""
    if not math.isfinite(steps) or abs(steps) > MAX_STEPS:
        raise InputError(
            f"{what} is {steps:.4g} time steps: not a number of steps a run can "
            f"count (at most 2^53)"
        )
    return int(round(steps))


def rows_up_to(times: np.ndarray, exc: UnstableRunError, sim) -> int:
    """How many of a failed chunk's rows lie at or before the time the diagnosis names."""
    t_bad = getattr(exc, "time", None)
    if t_bad is None or not math.isfinite(t_bad):
        return times.shape[0]
    return int(np.searchsorted(times, t_bad + 0.5 * sim.dt, side="right"))


def relative_residual(stats: Stats, sim) -> float:
    scale = sim.state.scale
    if stats.last_energy is None or scale <= 0:
        return 0.0
    return float(stats.last_energy[11]) / scale
