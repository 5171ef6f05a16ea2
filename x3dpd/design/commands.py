"""What ``x3dpd sweep`` and ``x3dpd ringdown`` do, callable from Python too.

Each function reads the deck or trace, runs the library, writes DIR's files and reports progress
through ``echo`` (a callable taking one line).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from pathlib import Path

from x3dpd.analysis.design_plots import attenuations, plot_responses, plot_sweep
from x3dpd.deck.parser import read_deck
from x3dpd.design.spec import (SweepSpec, default_drive_point, parse_drives, parse_frequencies,
                               parse_responses)
from x3dpd.design.steady_state import Criterion
from x3dpd.design.sweep import baseline_curves, deck_hash, run_sweep


def sweep_command(deck_path: str, *, freq: str, amps: Sequence[str], node: int | None = None,
                  dof: int | None = None, direction: str | None = None,
                  baselines: Sequence[str] = (), out: str, workers: int | None = None,
                  scheduler: str | None = None, dt: float | None = None, tol: float = 0.01,
                  window: int = 5, max_cycles: int = 400, samples_per_cycle: int = 200,
                  extrapolate: bool = True, predict: bool = True, overwrite: bool = False,
                  responses: Sequence[str] = (),
                  echo: Callable[[str], None] = print) -> list[dict]:
    """Run a sweep into ``out`` (sweep.csv, sweep.png, points/; with ``responses``
    (``NODE:DOF`` texts) also sweep_responses.png); returns its rows."""
    deck = read_deck(deck_path)
    measured = parse_responses(responses, deck)
    frequencies = parse_frequencies(freq)
    drives = parse_drives(amps)
    if node is None or dof is None:
        d_node, d_dof = default_drive_point(deck)
        node = d_node if node is None else node
        dof = d_dof if dof is None else dof
    spec = SweepSpec(deck=deck, deck_text_hash=deck_hash(deck_path), frequencies=frequencies,
                     drives=drives, node=node, dof=dof, direction=direction,
                     baselines=tuple(baselines), dt=dt, responses=measured,
                     criterion=Criterion(tol=tol, window=window, max_cycles=max_cycles,
                                         samples_per_cycle=samples_per_cycle,
                                         extrapolate=extrapolate, predict=predict))
    start = time.perf_counter()
    echo(f"sweep {deck_path}: node {node} dof {dof}, {len(frequencies)} frequencies "
         f"{frequencies[0]:g}-{frequencies[-1]:g} Hz, drive {', '.join(f'{d:g}' for d in drives)}"
         f", {direction or 'each point from rest'}"
         + (f", baselines {','.join(baselines)}" if baselines else ""))

    def on_point(row: dict) -> None:
        flag = "" if row["converged"] else "  NOT CONVERGED (cap)"
        flag += "  irregular" if row["irregular"] else ""
        echo(f"  {row['config']:<10} F={row['drive']:<10.5g} {row['direction'] or '-':<4} "
             f"{row['frequency_hz']:8.4f} Hz  X={row['amplitude']:.5e}  "
             f"{row['cycles']:4d} cycles  {row['wall_s']:6.1f} s{flag}")

    done = []
    try:
        rows = run_sweep(spec, out, workers=workers, scheduler=scheduler,
                         overwrite=overwrite, on_point=lambda row: (done.append(row),
                                                                    on_point(row)))
    except KeyboardInterrupt:
        echo(f"interrupted: {len(done)} point(s) finished in this call are kept in {out}; "
             "the same command resumes the sweep")
        raise
    curves = baseline_curves(spec)
    length, force, unit_t = deck.units.system if deck.units is not None else ("in", "lbf", "s")
    plot_sweep(Path(out) / "sweep.png", rows, curves, title=Path(deck_path).name, units=length)
    if measured:
        plot_responses(Path(out) / "sweep_responses.png", rows, measured,
                       {r: baseline_curves(spec, response=r) for r in measured},
                       title=Path(deck_path).name, units=length, force=force, time=unit_t)
    for a in attenuations(rows, curves):
        echo(f"peak attenuation at drive {a['drive']:g}: {a['attenuation_db']:.2f} dB vs "
             f"{a['baseline']} (peak {a['baseline_peak']:.4e} -> {a['deck_peak']:.4e})")
    echo(f"wrote {Path(out) / 'sweep.csv'} and {Path(out) / 'sweep.png'}"
         + (f" and {Path(out) / 'sweep_responses.png'}" if measured else "") + " "
         f"({len(rows)} points, {time.perf_counter() - start:.1f} s)")
    return rows
