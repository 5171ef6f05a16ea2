#!/usr/bin/env python3
"""Regenerate the golden traces of tests/test_decks.py, deliberately.

    python tools/regen_goldens.py            # every case of tests/golden/cases.json
    python tools/regen_goldens.py beam_64    # the cases whose deck name starts with this
    python tools/regen_goldens.py --envelopes [beam_64 ...]   # only remeasure the envelopes

Each case runs ``x3dpd decks/DECK ARGS --tmax T`` from the repository root and stores its trace
and sidecar as ``tests/golden/<deck stem>.trace.txt(.json)``; ``tests/golden/PROVENANCE.json``
records the x3dpd version, git commit, date and machine. Run it only after a change that is
*meant* to change results (a physics fix, a new deck), on a quiet machine, and say why in the
commit message; see docs/running.md.

**The rounding envelope.** A golden replays bit for bit on a machine like the one that made it;
on another one some numbers may differ in their last bit (another OpenBLAS kernel for the modal
algebra, another libm) and the particles' chaos grows that difference about 10x per simulated
millisecond. Beside each golden this tool records how fast: it runs the case through the API
at full precision as is and with one number nudged one ulp -- an initial value (the first
particle's x) and a constant every contact uses at every step (PDMP's E0), as a constant that
another CPU rounds differently would be -- and stores the largest relative difference per
output row (of each trace column's largest |value|, over every node and both nudges):
``rounding_envelope`` in PROVENANCE.json. tests/test_decks.py bounds a replay from another
machine by a multiple of it (docs/running.md, "Golden traces on another machine").
"""

from __future__ import annotations

import datetime as _dt
import json
import re
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
        "libc": libc(),
    }


def llvm_cpu() -> str:
    """The CPU numba compiles for (``znver5``, ...): with numba and glibc's math, what decides
    the rounding of a run, and so whether a chaotic golden replays bit for bit."""
    import llvmlite.binding as llvm

    return llvm.get_host_cpu_name()


def libc() -> str:
    """The C library (``glibc 2.36``): its libm rounds exp, sin, pow ... for the run."""
    return " ".join(platform.libc_ver()).strip()


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


def _api_options(case: dict) -> dict:
    """The case's CLI arguments as :func:`x3dpd.run` keywords (cases.json uses only these)."""
    args = list(case.get("args", []))
    opts: dict = {"usrfrc": [], "motion": []}
    while args:
        flag, value = args.pop(0), args.pop(0)
        if flag == "--temperature":
            opts["temperature"] = value
            continue
        opts[{"--usrfrc": "usrfrc", "--motion": "motion"}[flag]].append(value)
    if case.get("tmax") is not None:
        opts["tmax"] = float(case["tmax"])
    return opts


def changed_record(lines: list[str], card: str, match, field: int, change) -> str | None:
    """Replace field ``field`` (a number) of the first record of ``card`` that
    ``match(fields)`` accepts by ``change(value)``, in place; return what was changed
    (``"old -> new"``), or None."""
    inside = False
    for k, line in enumerate(lines):
        head = line.strip().upper()
        if head.startswith(card):
            inside = True
        elif head == "END":
            inside = False
        elif inside and line.strip() and not line.strip().startswith("$"):
            # free format: fields apart by blanks or commas, Fortran D exponents
            fields = [f for f in re.split(r"[\s,]+", line.strip()) if f]
            if match(fields):
                old = float(fields[field].upper().replace("D", "E"))
                fields[field] = repr(float(change(old)))
                lines[k] = "   " + " ".join(fields)
                return f"{old!r} -> {fields[field]}"
    return None


#: what :func:`nudged_deck_text` nudges one ulp: an initial value, and a constant every
#: contact uses at every step (as a constant computed with another CPU's rounding would be)
NUDGES = ("initial", "constant")
#: E0's field in a PDMP record (NODLIM RZERO PRHO PPOI E0 ...)
PDMP_E0 = 4


def nudged_deck_text(deck: Path, what: str) -> tuple[str, str]:
    """The deck's text with one number one ulp larger, and what was nudged: ``"initial"``, the
    first particle's x coordinate (NODE COORDINATES; a PLATES deck's spheres are built from
    its first plate's thickness, nudged instead); ``"constant"``, the first PDMP record's
    instantaneous modulus E0 (a HOOKE deck's first KN)."""
    import numpy as np

    from x3dpd.deck import read_deck
    from x3dpd.model.build import build_model

    lines = deck.read_text().split("\n")
    up = lambda v: np.nextafter(v, np.inf)  # noqa: E731
    plates = any(line.strip().upper().startswith("PLAT") for line in lines)
    if what == "initial" and plates:
        for k, line in enumerate(lines):
            m = re.search(r"thickness=([^\s]+)", line)
            if m and not line.strip().startswith("$"):
                old = float(m.group(1))
                lines[k] = line.replace(m.group(0), f"thickness={float(up(old))!r}", 1)
                return "\n".join(lines), f"plate 1 thickness {old!r} -> {float(up(old))!r}"
    if what == "constant" and any(line.strip().upper().startswith("HOOK") for line in lines):
        done = changed_record(lines, "HOOK", lambda f: True, 1, up)
        return "\n".join(lines), f"HOOKE KN {done}"
    if what == "initial":
        model = build_model(read_deck(deck))
        node = str(int(model.node_ids[model.particle_start]))
        done = changed_record(lines, "NODE COORD", lambda f: f[0] == node, 1, up)
        label = f"node {node} x"
    else:
        done = changed_record(lines, "PDMP", lambda f: True, PDMP_E0, up)
        label = "PDMP E0"
    if done is None:
        raise ValueError(f"{deck}: nothing to nudge for {label}")
    return "\n".join(lines), f"{label} {done}"


def rounding_envelope(case: dict) -> tuple[list[float], list[str]]:
    """Per output row, the largest difference between the case run as is and with one number
    nudged one ulp (each of :data:`NUDGES`, :func:`nudged_deck_text`), relative to each trace
    column's largest |value| over the run, over every node, column and nudge: full precision,
    through :func:`x3dpd.run` (module docstring). Returns (the envelope, what was nudged)."""
    import numpy as np

    import x3dpd

    deck = ROOT / "decks" / case["deck"]
    opts = _api_options(case)
    plain = x3dpd.run(deck, **opts).trace.data
    scale = np.maximum(np.abs(plain).max(axis=(0, 1)), 1e-300)
    envelope = np.zeros(plain.shape[0])
    nudges = []
    for what in NUDGES:
        text, nudge = nudged_deck_text(deck, what)
        # beside the deck: mode files and user force files resolve as for the deck itself
        fd, tmp = tempfile.mkstemp(suffix=".inp", prefix=".nudged_", dir=deck.parent)
        try:
            with os.fdopen(fd, "w") as f:
                f.write(text)
            nudged = x3dpd.run(tmp, **opts).trace.data
        finally:
            os.unlink(tmp)
        envelope = np.maximum(envelope, (np.abs(nudged - plain) / scale).max(axis=(1, 2)))
        nudges.append(nudge)
    return [float(f"{v:.3g}") for v in envelope], nudges


def _measure_envelope(case: dict, entry: dict) -> None:
    envelope, nudges = rounding_envelope(case)
    entry["rounding_envelope"] = envelope
    entry["rounding_nudges"] = nudges
    entry.pop("rounding_nudge", None)
    print(
        f"  rounding envelope ({'; '.join(nudges)}): {envelope[0]:.2g} .. {envelope[-1]:.2g}",
        flush=True,
    )


def main(argv: list[str]) -> int:
    from x3dpd import __version__
    from x3dpd.api.outputs import deck_key
    from x3dpd.deck import read_deck

    envelopes_only = "--envelopes" in argv
    wanted = [a for a in argv[1:] if a != "--envelopes"]
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
        if envelopes_only:
            print(f"{case['deck']}:", flush=True)
            _measure_envelope(case, prov["cases"][case["deck"]])
            continue
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
            _measure_envelope(case, prov["cases"][case["deck"]])
    prov_path.write_text(json.dumps(prov, indent=1, sort_keys=True) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
