"""The report's Section 8.3 beam study (Figures 45-48), reproduced with ``x3dpd sweep``.

    python tools/study/beam_study.py --out study --workers 2

runs ``x3dpd sweep`` on decks/beam_1.inp, beam_64.inp and beam_512.inp (all three at once on one
Dask cluster, so that their chains share the cores) at
both drives (200 mV = 4.84040e-3 lbf and 400 mV = 9.68080e-3 lbf, Table 4), a down-sweep chain
per drive over 14 frequencies 35-40 Hz (denser near the resonances), with the undamped and
added-mass baselines (closed form: the structure is a linear SDOF). Then it draws
``OUT/beam_study_200mV.png`` and ``OUT/beam_study_400mV.png`` (all five configurations at one
drive, like Figures 45-48) and writes ``OUT/study.csv`` (peak amplitude and attenuation of every
damper at each drive) and ``OUT/timing.json`` (wall time of each sweep and of the whole study).
Rerunning resumes (finished points are kept in OUT/beam_N/points/).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

from x3dpd.analysis.design_plots import attenuations, plot_configurations
from x3dpd.design.commands import sweep_command

ROOT = Path(__file__).resolve().parents[2]
DRIVES = {"200 mV": 4.84040e-3, "400 mV": 9.68080e-3}
FREQ = "35,35.5,36,36.5,36.75,37,37.25,37.5,37.75,38,38.25,38.5,39,40"
DECKS = {"1 particle": "beam_1.inp", "64 particles": "beam_64.inp",
         "512 particles": "beam_512.inp"}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="study")
    ap.add_argument("--workers", type=int, default=2,
                    help="local worker processes shared by the three sweeps (1: serial)")
    ap.add_argument("--scheduler", default=None, help="address of an existing Dask cluster")
    ap.add_argument("--tol", type=float, default=0.02)
    ap.add_argument("--freq", default=FREQ)
    ap.add_argument("--direction", default="down")
    ap.add_argument("--summarize", action="store_true",
                    help="only redraw the figures and study.csv from the points done so far")
    args = ap.parse_args()
    out = Path(args.out)
    if args.summarize:
        summarize(out)
        return
    out.mkdir(parents=True, exist_ok=True)
    timing = run_all(out, args)
    (out / "timing.json").write_text(json.dumps(timing, indent=1) + "\n")
    summarize(out)
    print(f"beam study: {timing['total']:.0f} s in all "
          + ", ".join(f"{k} {v:.0f} s" for k, v in timing.items() if k != "total"))


def run_all(out: Path, args) -> dict:
    """The three sweeps at once on one Dask cluster (``--workers`` local processes, or
    ``--scheduler``): their six chains (deck x drive) share the workers, so no core idles
    while a short sweep waits for a long one. The longest (beam_512) is submitted first.
    Returns the wall time of each sweep and of the whole study [s]."""
    import threading
    from contextlib import nullcontext

    from dask.distributed import LocalCluster

    timing: dict = {}
    errors: list = []
    start = time.perf_counter()
    cluster = (nullcontext(None) if args.scheduler or args.workers == 1 else
               LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                            dashboard_address=":0"))
    with cluster as local:
        address = args.scheduler or (local.scheduler_address if local else None)

        def one(deck: str) -> None:
            t = time.perf_counter()
            try:
                sweep_command(str(ROOT / "decks" / deck), freq=args.freq,
                              amps=[",".join(repr(d) for d in DRIVES.values())],
                              direction=args.direction, baselines=("undamped", "added-mass"),
                              out=str(out / Path(deck).stem), workers=1 if not address else None,
                              scheduler=address, tol=args.tol,
                              echo=lambda line, d=deck: print(f"[{d}] {line}", flush=True))
            except BaseException as exc:   # reported after the other sweeps end
                errors.append((deck, exc))
            timing[deck] = time.perf_counter() - t

        decks = sorted(DECKS.values(), key=lambda d: -int(d.split("_")[1].split(".")[0]))
        if address is None:
            for deck in decks:
                one(deck)
        else:
            threads = [threading.Thread(target=one, args=(d,), daemon=True) for d in decks]
            for th in threads:
                th.start()
                time.sleep(2.0)   # submission order = priority order on a FIFO scheduler
            for th in threads:
                th.join()
    if errors:
        raise errors[0][1]
    timing["total"] = time.perf_counter() - start
    return timing


def points_done(folder: Path) -> list[dict]:
    """The rows of a sweep's finished points (DIR/points/*.json), done or still running."""
    return [json.loads(p.read_text()) for p in sorted((folder / "points").glob("*.json"))]


def summarize(out: Path) -> None:
    """The two figures and study.csv from the three sweeps' CSVs."""
    from x3dpd.deck.parser import read_deck
    from x3dpd.design.spec import SweepSpec, parse_frequencies
    from x3dpd.design.sweep import baseline_curves

    lines = ["drive,configuration,peak_amplitude,peak_frequency_hz,"
             "attenuation_vs_undamped_db,attenuation_vs_added_mass_db,points,converged"]
    rows = {label: points_done(out / Path(deck).stem) for label, deck in DECKS.items()}
    deck0 = read_deck(ROOT / "decks" / "beam_64.inp")
    freqs = sorted({r["frequency_hz"] for rs in rows.values() for r in rs}
                   | set(parse_frequencies(FREQ)))
    spec = SweepSpec(deck=deck0, deck_text_hash="", frequencies=tuple(freqs),
                     drives=tuple(DRIVES.values()), node=9, dof=1,
                     baselines=("undamped", "added-mass"))
    curves = baseline_curves(spec)
    for name, drive in DRIVES.items():
        series = {label: [r for r in rs if r["config"] == "deck" and r["drive"] == drive]
                  for label, rs in rows.items()}
        base = {f"{c} (closed form)": curves[(c, drive)] for c in ("undamped", "added-mass")}
        tag = name.replace(" ", "")
        plot_configurations(out / f"beam_study_{tag}.png", series, base,
                            title=f"Section 8.2 beam, {name} drive ({drive:g} lbf), "
                                  "down-sweep")
        for label, rs in series.items():
            att = {a["baseline"]: a["attenuation_db"] for a in attenuations(
                rs, {(c, drive): curves[(c, drive)] for c in ("undamped", "added-mass")})}
            if not rs:
                continue
            peak = max(rs, key=lambda r: r["amplitude"])
            lines.append(f"{name},{label},{peak['amplitude']!r},{peak['frequency_hz']!r},"
                         f"{att.get('undamped', math.nan):.2f},"
                         f"{att.get('added-mass', math.nan):.2f},{len(rs)},"
                         f"{sum(int(r['converged']) for r in rs)}")
    (out / "study.csv").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    # steady state: the ledger's dissipation per cycle equals the drive's work pi F X sin(-phi)
    for label, rs in rows.items():
        rel = sorted(abs(r["dissipated_per_cycle"] - r["input_work_per_cycle"])
                     / abs(r["input_work_per_cycle"]) for r in rs if r["config"] == "deck")
        if rel:
            print(f"{label}: ledger dissipation vs drive work per cycle, median "
                  f"{100 * rel[len(rel) // 2]:.1f} %, largest {100 * rel[-1]:.1f} %")


if __name__ == "__main__":
    main()
