#!/usr/bin/env python3
"""How far a change of the force summation order moved the goldens: old and new code side by
side on every case of tests/golden/cases.json, against what rounding alone does.

    PYTHONPATH=OLD_TREE python tools/study/golden_shift.py record old.npz
    python tools/study/golden_shift.py record new.npz
    python tools/study/golden_shift.py compare old.npz new.npz

``record`` runs each golden case through :func:`x3dpd.run` at full precision with the tree on
``PYTHONPATH`` (its traces and ledgers into one .npz) and, with ``--nudged``, the same case
with one number one ulp larger, each of tools/regen_goldens.py's nudges in turn: the first
particle's x, and the PDMP modulus E0 every contact uses at every step (as a summation order
does, it touches every contact's force at every step).
``compare`` prints one Markdown row per case:

- the worst trace difference over the rows both runs wrote, divided by the case's rounding
  bound -- 100 x its ``rounding_envelope`` at that row (tests/golden/PROVENANCE.json), what
  tests/golden_compare.py lets a replay on another CPU differ by: below 1 the two traces agree
  to round-off;
- the worst ledger difference (every energy column) relative to the ledger's scale, the largest
  |total energy| of the run (1e-12 is the bar issue 30 sets); and, when ``record --nudged`` was
  run, the same for the one-ulp nudges of the old code (the larger of the two): what rounding
  alone moves the ledger.

docs/engine.md, "The order of force sums", shows the table of the last change.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from pathlib import Path

import numpy as np

import x3dpd

ROOT = Path(__file__).resolve().parents[2]


def _regen():
    spec = importlib.util.spec_from_file_location("regen", ROOT / "tools" / "regen_goldens.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def record(out: Path, nudged: bool) -> None:
    regen = _regen()
    arrays = {}
    for case in regen.load_cases():
        if case.get("refused"):
            continue
        deck = ROOT / "decks" / case["deck"]
        opts = regen._api_options(case)
        r = x3dpd.run(deck, **opts)
        arrays[f"{case['deck']}:trace"] = r.trace.data
        arrays[f"{case['deck']}:energy"] = r.energy.data
        for what in regen.NUDGES if nudged else ():
            text, _ = regen.nudged_deck_text(deck, what)
            tmp = deck.parent / f".nudged_{deck.name}"
            try:
                tmp.write_text(text)
                arrays[f"{case['deck']}:energy_{what}"] = x3dpd.run(tmp, **opts).energy.data
            finally:
                tmp.unlink(missing_ok=True)
        print(f"{case['deck']}: {r.trace.data.shape[0]} rows", file=sys.stderr)
    np.savez(out, **arrays)


def _ledger_shift(a: np.ndarray, b: np.ndarray) -> float:
    """Worst |a - b| over the energy columns (time left out) / the run's largest |total|."""
    n = min(len(a), len(b))
    scale = np.abs(a[:, 10]).max() or 1.0
    return float(np.abs(a[:n, 1:] - b[:n, 1:]).max() / scale)


def compare(old: Path, new: Path) -> list[str]:
    prov = json.loads((ROOT / "tests" / "golden" / "PROVENANCE.json").read_text())
    envelopes = {name: entry.get("rounding_envelope") for name, entry in prov["cases"].items()}
    a, b = np.load(old), np.load(new)
    lines = [
        "| deck | rows compared | worst trace difference / rounding bound "
        "| worst ledger difference / scale | one-ulp nudge: ledger / scale |",
        "|---|---:|---:|---:|---:|",
    ]
    for key in sorted(k for k in a.files if k.endswith(":trace")):
        deck = key[: -len(":trace")]
        ta, tb = a[key], b[key]
        n = min(len(ta), len(tb))
        scale = np.maximum(np.abs(ta[:n]).max(axis=(0, 1)), 1e-300)
        per_row = (np.abs(ta[:n] - tb[:n]) / scale).max(axis=(1, 2))
        env = envelopes.get(deck)
        bound = 100.0 * np.asarray(env[:n]) if env else np.full(n, np.nan)
        # rows where rounding itself moved nothing (bound 0) compare exactly
        nonzero = bound > 0
        if np.any(per_row[~nonzero] > 0):
            trace = "differs where rounding does not"
        elif not per_row.any():
            trace = "0 (the same bits)"
        else:
            trace = f"{(per_row[nonzero] / bound[nonzero]).max():.2g}"
        ledger = _ledger_shift(a[f"{deck}:energy"], b[f"{deck}:energy"])
        nudges = [
            _ledger_shift(a[f"{deck}:energy"], a[k])
            for k in a.files
            if k.startswith(f"{deck}:energy_")
        ]
        nudge = f"{max(nudges):.2g}" if nudges else "-"
        lines.append(f"| {deck} | {n} of {len(ta)} | {trace} | {ledger:.2g} | {nudge} |")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="what", required=True)
    rec = sub.add_parser("record")
    rec.add_argument("out", type=Path)
    rec.add_argument("--nudged", action="store_true")
    cmp_ = sub.add_parser("compare")
    cmp_.add_argument("old", type=Path)
    cmp_.add_argument("new", type=Path)
    args = ap.parse_args(argv)
    if args.what == "record":
        record(args.out, args.nudged)
    else:
        print("\n".join(compare(args.old, args.new)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
