"""The kernel cache's manifest: which step-loop variants it holds, what each cost to compile and
who compiled it first (issue 32 item 3; docs/engine.md, "Compile time").

The cache (x3dpd.solver.variants: ``$X3DPD_CACHE_DIR``, default ``~/.cache/x3dpd``) holds a
folder per x3dpd source hash, ``kernels/<hash>/``, with each variant's generated sources and
numba's machine code for them (``__pycache__/*.nbi``, ``*.nbc``). Beside them,
``manifest.json`` records per variant (keyed by the generated files' stem)::

    {"format": 1, "source_hash": "...", "numba": "0.68.1", "variants": {STEM: {
        "label": "walls+pairs+walls_translate",   # Variant.label(): its effects
        "effects": {...},                         # every field of the Variant
        "compile_seconds": 23.4,                  # the first calls that compiled it [s]
        "compile_seconds_total": 23.4,            # every compile of it (other signatures)
        "first_user": "x3dpd decks/beam_64.inp",  # or the test that compiled it
        "compiled": "2026-11-28T09:12:03+00:00",  # first compile (UTC)
        "last_compiled": "...", "compiles": 1,    # compiled again: another argument
                                                  # signature, or a lost file
        "loads": 3, "last_loaded": "...",         # processes that loaded it from the cache
        "source_hash": "..."}}}

:func:`watch_first_calls` fills it in: x3dpd.solver.compile_lock wraps a Simulation's first
kernel calls (where numba compiles the loop or loads it) in it, under the variant's compile
lock. Whether they compiled or loaded is numba's own count (the loop dispatcher's cache misses
and hits). The manifest is rewritten whole, atomically (a temporary file renamed over it),
under an exclusive lock of its own (``manifest.lock``): two processes compiling two variants at
once each add their entry. A failure to write it never stops a run.

With ``X3DPD_COMPILE_EVENTS`` set to a file, each compile or load also appends one JSON line
there, whatever the cache: the test suite's report of what a run compiled reads it
(tests/conftest.py). :func:`loops_run_here` lists the loops this process has run, for the
tests that declare the loop they ride. Listing and clearing a cache (``x3dpd cache``):
x3dpd.solver.cache_listing.
"""

from __future__ import annotations

import atexit
import contextlib
import json
import os
import shlex
import sys
import time
from dataclasses import asdict
from datetime import datetime, timezone
from pathlib import Path

try:  # POSIX
    import fcntl
except ImportError:  # pragma: no cover - Windows: atomic renames only
    fcntl = None

import numba

from x3dpd.errors import InputError
from x3dpd.solver.variants import variant_of

#: The manifest's file name in each source-hash folder, and its format number.
MANIFEST = "manifest.json"
FORMAT = 1
#: The environment variable naming the file each compile and load is appended to.
EVENTS_ENV = "X3DPD_COMPILE_EVENTS"

#: labels of the loops this process ran (every Simulation's first calls), oldest first
_RUN_HERE: list[str] = []
#: generated module name -> (cache hits, misses) of its loop already recorded in this process
_RECORDED: dict[str, tuple[int, int]] = {}


class CacheError(InputError):
    """A kernel cache or manifest that cannot be read, listed or cleared (missing, unreadable,
    not x3dpd's): bad input, exit status 2 at the command line."""


def _now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="seconds")


def first_user() -> str:
    """Who is compiling: the test (``PYTEST_CURRENT_TEST``; and the command, when a test's own
    subprocess compiles) or this process's command line, at most 200 characters."""
    argv = list(sys.argv) or ["python"]
    head = argv[0]
    if head.endswith("__main__.py"):
        argv[:1] = ["python", "-m", Path(head).parent.name]
    elif head not in ("-c", "-m", ""):
        argv[0] = Path(head).name
    command = " ".join(shlex.quote(a) for a in argv)
    test = os.environ.get("PYTEST_CURRENT_TEST")
    if test:
        test = test.rsplit(" (", 1)[0]
        command = test if "pytest" in sys.modules else f"{test} via {command}"
    return command[:200]


def _loop_counts(module) -> tuple[int, int] | None:
    """numba's (cache hits, cache misses) of a generated module's loop, or None without one
    (NUMBA_DISABLE_JIT: the loop is a Python function)."""
    stats = getattr(getattr(module, "advance_packed", None), "stats", None)
    if stats is None:
        return None
    return sum(stats.cache_hits.values()), sum(stats.cache_misses.values())


def _has_code(module) -> bool:
    """Whether the loop of a generated module has machine code (a compile that failed counts
    a cache miss but leaves none)."""
    return bool(getattr(getattr(module, "advance_packed", None), "overloads", None))


@contextlib.contextmanager
def watch_first_calls(folder: Path, module_name: str):
    """Time the block (a Simulation's first kernel calls) and record in the manifest of
    ``folder`` whether it compiled ``module_name``'s loop or loaded it from the cache."""
    if variant_of(module_name) is not None:
        _RUN_HERE.append(variant_of(module_name)[0].label())
    module = sys.modules.get(module_name)
    before = _loop_counts(module)
    t = time.perf_counter()
    try:
        yield
    finally:
        seconds = time.perf_counter() - t
        after = _loop_counts(module)
        if before is not None and after is not None and after != before and _has_code(module):
            compiled = after[1] > before[1]
            record(
                folder,
                module_name,
                "compiled" if compiled else "loaded",
                seconds if compiled else None,
            )
            _RECORDED[module_name] = after


def record_unwatched() -> None:
    """Record the loops of this process that numba compiled or loaded outside
    :func:`watch_first_calls` (a kernel called before its Simulation's first calls), their
    compile time unknown. Called at exit."""
    for name, module in list(sys.modules.items()):
        if variant_of(name) is None:
            continue
        counts = _loop_counts(module)
        known = _RECORDED.get(name, (0, 0))
        if counts is None or counts == known or not _has_code(module):
            continue
        record(
            Path(module.__file__).parent,
            name,
            "compiled" if counts[1] > known[1] else "loaded",
            None,
        )
        _RECORDED[name] = counts


def _at_exit() -> None:
    with contextlib.suppress(Exception):
        record_unwatched()


atexit.register(_at_exit)


def loops_run_here() -> list[str]:
    """Labels (Variant.label) of the step loops this process's Simulations ran, oldest first,
    one per Simulation: what a test rode (tests/conftest.py, ``pytest.mark.rides``)."""
    return list(_RUN_HERE)


def record(folder: Path, module_name: str, event: str, seconds: float | None) -> None:
    """Book one compile (``event="compiled"``, in ``seconds``) or load (``"loaded"``) of the
    loop ``module_name`` in the manifest of ``folder`` and, with ``X3DPD_COMPILE_EVENTS``
    set, in that file. Errors writing either are ignored (they only feed reports)."""
    known = variant_of(module_name)
    if known is None:
        return
    variant, stem = known
    folder = Path(folder)
    user, now = first_user(), _now()
    seconds = None if seconds is None else round(float(seconds), 2)

    def update(data: dict) -> None:
        entry = data["variants"].get(stem)
        if entry is None:
            entry = data["variants"][stem] = {
                "label": variant.label(),
                "effects": asdict(variant),
                "compile_seconds": None,
                "compile_seconds_total": 0.0,
                "first_user": user,
                "compiled": None,
                "last_compiled": None,
                "compiles": 0,
                "loads": 0,
                "last_loaded": None,
                "source_hash": folder.name,
            }
        if event == "compiled":
            entry["compiles"] += 1
            entry["last_compiled"] = now
            if entry["compiled"] is None:
                entry["compiled"] = now
                entry["first_user"] = user
            if seconds is not None:
                if entry["compile_seconds"] is None:
                    entry["compile_seconds"] = seconds
                entry["compile_seconds_total"] = round(
                    (entry.get("compile_seconds_total") or 0.0) + seconds, 2
                )
        else:
            entry["loads"] += 1
            entry["last_loaded"] = now

    with contextlib.suppress(OSError):
        update_manifest(folder, update)
    events = os.environ.get(EVENTS_ENV)
    if events:
        line = {
            "event": event,
            "name": stem,
            "label": variant.label(),
            "seconds": seconds,
            "cache": str(folder),
            "user": user,
            "pid": os.getpid(),
            "time": now,
        }
        with contextlib.suppress(OSError):
            fd = os.open(events, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
            try:
                os.write(fd, (json.dumps(line) + "\n").encode())
            finally:
                os.close(fd)


def _empty_manifest(folder: Path) -> dict:
    return {
        "format": FORMAT,
        "source_hash": folder.name,
        "numba": numba.__version__,
        "variants": {},
    }


def read_manifest(folder: Path) -> dict:
    """The manifest of a source-hash folder (an empty one where there is none yet); a
    :class:`CacheError` when it cannot be read or is not a manifest."""
    path = Path(folder) / MANIFEST
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        return _empty_manifest(Path(folder))
    except (OSError, ValueError) as exc:
        raise CacheError(f"cannot read the kernel cache's manifest {path}: {exc}") from None
    if not (
        isinstance(data, dict)
        and data.get("format") == FORMAT
        and isinstance(data.get("variants"), dict)
    ):
        raise CacheError(f"{path} is not a manifest of this x3dpd (format {FORMAT})")
    return data


@contextlib.contextmanager
def _manifest_lock(folder: Path):
    if fcntl is None:
        yield
        return
    fd = os.open(folder / "manifest.lock", os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


def update_manifest(folder: Path, change) -> dict:
    """Apply ``change(data)`` to the manifest of ``folder`` under its lock and write it back
    atomically; a damaged manifest is started anew. Returns the data written."""
    folder = Path(folder)
    with _manifest_lock(folder):
        try:
            data = read_manifest(folder)
        except CacheError:
            data = _empty_manifest(folder)
        change(data)
        tmp = folder / f"{MANIFEST}.tmp{os.getpid()}"
        tmp.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
        os.replace(tmp, folder / MANIFEST)
    return data


def read_events(path: Path) -> list[dict]:
    """The lines ``X3DPD_COMPILE_EVENTS`` collected (damaged lines skipped)."""
    out = []
    try:
        text = Path(path).read_text()
    except OSError:
        return out
    for line in text.splitlines():
        with contextlib.suppress(ValueError):
            event = json.loads(line)
            if isinstance(event, dict) and event.get("event") in ("compiled", "loaded"):
                out.append(event)
    return out


__all__ = [
    "CacheError",
    "EVENTS_ENV",
    "MANIFEST",
    "first_user",
    "loops_run_here",
    "read_events",
    "read_manifest",
    "record",
    "record_unwatched",
    "update_manifest",
    "watch_first_calls",
]
