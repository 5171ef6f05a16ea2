#!/usr/bin/env python3
"""Regenerate the golden traces of tests/test_decks.py, deliberately.

    python tools/regen_goldens.py            # every case of tests/golden/cases.json
    python tools/regen_goldens.py beam_64    # the cases whose deck name starts with this

Each case runs ``x3dpd decks/DECK ARGS --tmax T`` from the repository root and stores its trace
and sidecar as ``tests/golden/<deck stem>.trace.txt(.json)``; ``tests/golden/PROVENANCE.json``
records the x3dpd version, git commit, date and machine. Run it only after a change that is
*meant* to change results (a physics fix, a new deck), on a quiet machine, and say why in the
commit message; see docs/running.md.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GOLDEN = ROOT / "tests" / "golden"
sys.path.insert(0, str(ROOT))


def load_cases() -> list[dict]:
    return json.loads((GOLDEN / "cases.json").read_text())["cases"]


def golden_path(deck: str) -> Path:
    return GOLDEN / (Path(deck).stem + ".trace.txt")


def case_argv(case: dict, trace: str | os.PathLike) -> list[str]:
    argv = [f"decks/{case['deck']}", *case.get("args", []), "--trace", os.fspath(trace), "--quiet"]
    if case.get("tmax") is not None:
        argv += ["--tmax", repr(float(case["tmax"]))]
    return argv


def machine() -> dict:
    cpu = platform.processor()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    import numba
    import numpy

    return {
        "platform": platform.platform(),
        "machine": platform.machine(),
        "cpu": cpu,
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "numba": numba.__version__,
        "llvm_cpu": llvm_cpu(),
    }


def llvm_cpu() -> str:
    """The CPU numba compiles for (``znver5``, ...): with numba and glibc's math, what decides
    the rounding of a run, and so whether a chaotic golden replays bit for bit."""
    import llvmlite.binding as llvm

    return llvm.get_host_cpu_name()


def git_commit() -> str:
    try:
        rev = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--", "x3dpd", "decks"],
            cwd=ROOT,
            capture_output=True,
            text=True,
        ).stdout.strip()
        return rev + (" (with uncommitted changes)" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main(argv: list[str]) -> int:
    from x3dpd import __version__
    from x3dpd.api.outputs import deck_key
    from x3dpd.deck import read_deck

    wanted = argv[1:]
    cases = [
        c
        for c in load_cases()
        if not c.get("refused") and (not wanted or any(c["deck"].startswith(w) for w in wanted))
    ]
    if not cases:
        print("no case matches", wanted, file=sys.stderr)
        return 2
    prov_path = GOLDEN / "PROVENANCE.json"
    prov = json.loads(prov_path.read_text()) if prov_path.is_file() else {}
    prov.setdefault("cases", {})
    for case in cases:
        with tempfile.TemporaryDirectory() as tmp:
            trace = Path(tmp) / golden_path(case["deck"]).name
            cmd = [sys.executable, "-m", "x3dpd", *case_argv(case, trace)]
            print("$", " ".join(cmd[2:]), flush=True)
            res = subprocess.run(cmd, cwd=ROOT)
            if res.returncode != 0:
                print(f"{case['deck']}: x3dpd exited {res.returncode}", file=sys.stderr)
                return 1
            dest = golden_path(case["deck"])
            dest.write_bytes(trace.read_bytes())
            side = json.loads(Path(str(trace) + ".json").read_text())
            side["deck_path"] = f"decks/{case['deck']}"
            for key in ("energy_file", "restart_file", "command"):
                side.pop(key, None)
            Path(str(dest) + ".json").write_text(
                "{\n"
                + ",\n".join(f"  {json.dumps(k)}: {json.dumps(v)}" for k, v in side.items())
                + "\n}\n"
            )
            prov["cases"][case["deck"]] = {
                "command": "x3dpd " + " ".join(case_argv(case, dest.relative_to(ROOT))),
                "x3dpd_version": __version__,
                "git_commit": git_commit(),
                "date": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M:%S UTC"),
                "machine": machine(),
                "blocks": side["blocks"],
                "deck_sha256": side["deck_sha256"],
                "deck_key": deck_key(read_deck(ROOT / "decks" / case["deck"])),
            }
            print(f"wrote {dest.relative_to(ROOT)} ({side['blocks']} output times)")
    prov_path.write_text(json.dumps(prov, indent=1, sort_keys=True) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
