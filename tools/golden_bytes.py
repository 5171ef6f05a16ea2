#!/usr/bin/env python3
"""Whether a change left every golden case's output byte for byte the same: two revisions'
CLI outputs side by side (a refactor's "same bytes" claim, docs/architecture.md).

    PYTHONPATH=OLD_TREE python tools/golden_bytes.py record old/   # run from OLD_TREE
    python tools/golden_bytes.py record new/
    python tools/golden_bytes.py compare old/ new/

``record`` runs each case of tests/golden/cases.json as tools/regen_goldens.py does (``x3dpd
decks/DECK ARGS --trace DIR/STEM/STEM.trace.txt --tmax T``, from the current directory, which
must be the tree on ``PYTHONPATH``) and keeps what it writes: the trace, the energy file, the
restart dump and the sidecar. ``compare`` checks every trace and energy file byte for byte and
every array of every restart dump (the dump's own metadata, which names its paths, and the
sidecars, which name the command and the date, are not compared) and prints one line per case;
exit status 0 when all agree, 1 when one does not.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import regen_goldens  # noqa: E402

#: the restart dump's member that names paths and times, not results
_META = "__x3dpd_restart__.json"


def record(out: Path) -> int:
    cases = json.loads(Path("tests/golden/cases.json").read_text())["cases"]
    for case in cases:
        stem = Path(case["deck"]).stem
        folder = out / stem
        folder.mkdir(parents=True, exist_ok=True)
        argv = regen_goldens.case_argv(case, folder / f"{stem}.trace.txt")
        done = subprocess.run(
            [sys.executable, "-m", "x3dpd", *argv], capture_output=True, text=True
        )
        print(f"{stem}: exit {done.returncode}", flush=True)
    return 0


def _differences(a: Path, b: Path) -> list[str]:
    out = []
    names = sorted(p.name for p in a.iterdir())
    if names != sorted(p.name for p in b.iterdir()):
        out.append(f"files {names} against {sorted(p.name for p in b.iterdir())}")
    for name in names:
        fa, fb = a / name, b / name
        if not fb.exists() or name.endswith(".json"):
            continue
        if name.endswith(".npz"):
            za, zb = zipfile.ZipFile(fa), zipfile.ZipFile(fb)
            members = set(za.namelist()) - {_META}
            if members != set(zb.namelist()) - {_META}:
                out.append(f"{name}: other arrays")
            out += [
                f"{name}: {m}"
                for m in sorted(members & set(zb.namelist()))
                if za.read(m) != zb.read(m)
            ]
        elif fa.read_bytes() != fb.read_bytes():
            out.append(name)
    return out


def compare(old: Path, new: Path) -> int:
    bad = 0
    for folder in sorted(p for p in old.iterdir() if p.is_dir()):
        other = new / folder.name
        diff = _differences(folder, other) if other.is_dir() else ["missing"]
        print(f"{folder.name}: {'same bytes' if not diff else 'DIFFERS: ' + ', '.join(diff)}")
        bad += bool(diff)
    return 1 if bad else 0


def main(argv: list[str]) -> int:
    if len(argv) == 3 and argv[1] == "record":
        return record(Path(argv[2]).resolve())
    if len(argv) == 4 and argv[1] == "compare":
        return compare(Path(argv[2]), Path(argv[3]))
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    sys.exit(main(sys.argv))
