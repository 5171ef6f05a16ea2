"""The progress lines of ``x3dpd run`` (and of ``frf`` and ``spectrum`` reading a big trace):
one updating line on a terminal, a plain line every ~10 s when stderr is a file or a pipe,
nothing with ``--quiet``."""

from __future__ import annotations

import math
import sys
import time

#: Wall time between progress lines when stderr is not a terminal [s].
PLAIN_PROGRESS_SECONDS = 10.0
#: Wall time between progress updates on a terminal [s].
TTY_PROGRESS_SECONDS = 0.2
#: Traces from this size on get a reading line (``x3dpd frf``, ``spectrum``) [bytes]: a
#: 39 MB trace takes about 20 s to read.
READ_PROGRESS_BYTES = 4_000_000


def _fmt_duration(s: float) -> str:
    if not math.isfinite(s):
        return "?"
    s = int(round(s))
    h, rem = divmod(s, 3600)
    m, sec = divmod(rem, 60)
    return f"{h}:{m:02d}:{sec:02d}" if h else f"{m}:{sec:02d}"


def _fmt_rate(r: float) -> str:
    if r >= 1e6:
        return f"{r / 1e6:.2f}M"
    if r >= 1e3:
        return f"{r / 1e3:.1f}k"
    return f"{r:.0f}"


class Progress:
    """One updating line on a terminal, a plain line every ~10 s otherwise, nothing if quiet."""

    def __init__(self, quiet: bool, tmax: float, stream=None):
        self.stream = stream or sys.stderr
        self.quiet = quiet
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.tmax = tmax
        self.last = time.perf_counter()
        self.width = 0

    def update(self, t: float, rate: float, eta: float, residual: float, force=False) -> None:
        if self.quiet:
            return
        now = time.perf_counter()
        every = TTY_PROGRESS_SECONDS if self.tty else PLAIN_PROGRESS_SECONDS
        if not force and now - self.last < every:
            return
        self.last = now
        pct = 100.0 * t / self.tmax if self.tmax > 0 else 100.0
        speed = f"{_fmt_rate(rate)} steps/s" if rate > 0 else "(warming up)"
        line = (
            f"t = {t:.6g} / {self.tmax:.6g} s ({pct:5.1f} %)  {speed}  "
            f"ETA {_fmt_duration(eta)}  energy residual {residual:+.2e} of scale"
        )
        if self.tty:
            pad = max(0, self.width - len(line))
            self.stream.write("\r" + line + " " * pad)
            self.width = len(line)
        else:
            self.stream.write(line + "\n")
        self.stream.flush()

    def done(self) -> None:
        if self.tty and self.width and not self.quiet:
            self.stream.write("\n")
            self.stream.flush()
            self.width = 0


class CompileTicker:
    """The compile-progress line: while numba compiles a scene's step loop (which holds no
    progress of its own), count the seconds up to the expected compile time on a terminal
    (``x3dpd: compiling ... 12 s of about 25 s``); one plain line when stderr is a file."""

    def __init__(self, message: str, expected_s: float, stream=None):
        import threading

        self.stream = stream or sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.message = message
        self.expected_s = expected_s
        self.t0 = time.perf_counter()
        self._stop = threading.Event()
        self._thread = None
        if not self.tty:
            self.stream.write(f"x3dpd: {message} ...\n")
            self.stream.flush()
            return
        self.stream.write(f"x3dpd: {message}\n")
        self._thread = threading.Thread(target=self._tick, daemon=True)
        self._thread.start()

    def _line(self) -> str:
        elapsed = time.perf_counter() - self.t0
        return f"\rcompiling ... {elapsed:.0f} s of about {self.expected_s:.0f} s"

    def _tick(self) -> None:
        while not self._stop.wait(1.0):
            self.stream.write(self._line())
            self.stream.flush()

    def stop(self) -> None:
        """End the line (idempotent): the step loop is compiled, stepping begins."""
        if self._thread is None or self._stop.is_set():
            return
        self._stop.set()
        self._thread.join()
        elapsed = time.perf_counter() - self.t0
        self.stream.write(f"\rcompiled in {elapsed:.0f} s" + " " * 24 + "\n")
        self.stream.flush()


class ReadProgress:
    """``progress(path, bytes_read, size)`` of a trace being read (x3dpd.testlab.frf): for a
    file of :data:`READ_PROGRESS_BYTES` or more, ``reading PATH (39.0 MB): 45 %`` updated on a
    terminal (a plain line every ~10 s otherwise), ending ``100 % in 20.3 s``."""

    def __init__(self, stream=None):
        self.stream = stream or sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.path = None
        self.start = self.last = 0.0

    def __call__(self, path: str, done: int, total: int) -> None:
        if total < READ_PROGRESS_BYTES:
            return
        now = time.perf_counter()
        head = f"reading {path} ({total / 1e6:.1f} MB): "
        if path != self.path:
            self.path, self.start, self.last = path, now, now
            self._write(head + "0 %", end=False)
        if done >= total:
            self._write(f"{head}100 % in {now - self.start:.1f} s", end=True)
            return
        every = TTY_PROGRESS_SECONDS if self.tty else PLAIN_PROGRESS_SECONDS
        if now - self.last >= every:
            self.last = now
            self._write(f"{head}{100.0 * done / total:.0f} %", end=False)

    def _write(self, line: str, end: bool) -> None:
        if self.tty:
            self.stream.write("\r" + line + ("\n" if end else ""))
        else:
            self.stream.write(line + "\n")
        self.stream.flush()
