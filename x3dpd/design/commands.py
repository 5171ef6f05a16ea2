"""What ``x3dpd sweep`` and ``x3dpd ringdown`` do, callable from Python too.

Each function reads the deck or trace, runs the library, writes DIR's files and reports progress
through ``echo`` (a callable taking one line).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from x3dpd.api.cluster import check_scheduler
from x3dpd.api.figures import attenuations, plot_responses, plot_sweep
from x3dpd.api.decks import read_deck, with_temperature
from x3dpd.design.drive import check_levels, displacement_amplitude, parse_amplitudes
from x3dpd.design.spec import (
    SweepSpec,
    check_base,
    check_node,
    default_drive_point,
    parse_auto_band,
    parse_frequencies,
    parse_responses,
)
from x3dpd.design.steady_state import Criterion, cap_flag
from x3dpd.design.sweep import baseline_curves, deck_hash, read_csv, run_sweep
from x3dpd.design.sweep_measured import measured_curves, read_measured
from x3dpd.errors import InputError
from x3dpd.units import labels_for, standard_gravity


#: the CLI's defaults (``x3dpd sweep --help``)
DEFAULT_CRITERION = Criterion()


# Over 80 lines: the sweep's one flow: options checked, points planned, run and written.
def sweep_command(
    deck_path: str,
    *,
    freq: str,
    amps: Sequence[str],
    node: int | None = None,
    dof: int | None = None,
    direction: str | None = None,
    baselines: Sequence[str] = (),
    out: str,
    workers: int | None = None,
    scheduler: str | None = None,
    dt: float | None = None,
    criterion: Criterion = DEFAULT_CRITERION,
    overwrite: bool = False,
    responses: Sequence[str] = (),
    drive: str = "force",
    measured_files: Sequence[str] = (),
    measured_scale: float = 1.0,
    temperature: str | None = None,
    echo: Callable[[str], None] = print,
) -> list[dict]:
    """Run a sweep into ``out`` (sweep.csv, sweep.png, points/; with ``responses``
    (``NODE:DOF`` texts) also sweep_responses.png); returns its rows. ``drive`` "force" (a
    sine force on the node) or "base" (the node moved, x3dpd.design.drive; sweep.png then
    shows the transmissibility at the responses). ``criterion`` how each point is measured
    (x3dpd.design.steady_state.Criterion). ``measured_files``: measured FRFs
    (``FILE[@NODE:DOF]``) drawn on the plots (x3dpd.design.sweep_measured). ``temperature``
    (not None): the operating temperature over the deck's TEMPERATURE card's."""
    deck = read_deck(deck_path)
    if temperature is not None:
        deck = with_temperature(deck, temperature)
    system = deck.unit_system
    quantity, drives = parse_amplitudes(amps, drive, standard_gravity(system))
    measured = parse_responses(responses, deck)
    auto = parse_auto_band(freq)
    frequencies = (auto.lo, auto.hi) if auto else parse_frequencies(freq)
    check_levels(quantity, drives, frequencies, units=labels_for(system))
    if quantity != "force":
        node, dof, measured = check_base(deck, node, dof, measured)
    elif node is None or dof is None:
        d_node, d_dof = default_drive_point(deck)
        node = d_node if node is None else node
        dof = d_dof if dof is None else dof
    check_node(deck, node)
    if dof not in (1, 2, 3):
        raise InputError(f"--dof {dof}: the sweep measures a translation, dof 1, 2 or 3")
    points = list(measured) + ([] if quantity != "force" else [(node, dof)])
    frfs = read_measured(measured_files, points, measured_scale)
    check_scheduler(scheduler)  # before anything is written
    spec = SweepSpec(
        deck=deck,
        deck_text_hash=deck_hash(deck_path) + (f"@{temperature}" if temperature else ""),
        frequencies=() if auto else frequencies,
        auto=auto,
        drives=drives,
        node=node,
        dof=dof,
        direction=direction,
        baselines=tuple(baselines),
        dt=dt,
        responses=measured,
        quantity=quantity,
        criterion=criterion,
    )
    lab = labels_for(system)
    unit = {
        "force": lab["force"],
        "displacement": lab["length"],
        "velocity": lab["velocity"],
        "acceleration": lab["acceleration"],
    }[quantity]
    start = time.perf_counter()
    what = (
        f"node {node} dof {dof}"
        if not spec.base
        else f"base node {node} dof {dof} moved at {quantity} amplitude, measured at "
        + ", ".join(f"{n}:{d}" for n, d in measured)
    )
    echo(
        f"sweep {deck_path}: {what}, "
        + (
            f"the peak in {auto.lo:g}-{auto.hi:g} Hz to {auto.resolution:g} Hz (at most "
            f"{auto.max_points} points a drive)"
            if auto
            else f"{len(frequencies)} frequencies {frequencies[0]:g}-{frequencies[-1]:g} Hz"
        )
        + f", drive {', '.join(f'{d:g}' for d in drives)}"
        f" {unit}, "
        + (
            f"chained {direction}"
            if direction
            else "each point from "
            + ("its predicted steady state" if criterion.predict else "the deck's initial state")
        )
        + (f", baselines {','.join(baselines)}" if baselines else "")
    )

    def on_point(row: dict) -> None:
        flag = cap_flag(row)
        flag += "  irregular" if row["irregular"] else ""
        if row.get("compile_s", 0.0) >= 1.0:
            flag += f"  (compiled its step loop: {row['compile_s']:.0f} s)"
        if spec.base:
            first = row["responses"][0]
            value = f"T={first['transmissibility']:.5e}"
        else:
            value = f"X={row['amplitude']:.5e} +/- {row['amplitude_ci']:.2g}"
        echo(
            f"  {row['config']:<10} {'F' if not spec.base else quantity[0].upper()}="
            f"{row['drive']:<10.5g} {row['direction'] or '-':<4} "
            f"{row['frequency_hz']:8.4f} Hz  {value}  "
            f"{row['cycles']:4d} cycles  {row['wall_s']:6.1f} s{flag}"
        )

    done = []
    try:
        rows = run_sweep(
            spec,
            out,
            workers=workers,
            scheduler=scheduler,
            overwrite=overwrite,
            on_point=lambda row: (done.append(row), on_point(row)),
        )
    except KeyboardInterrupt:
        echo(
            f"interrupted: {len(done)} point(s) finished in this call are kept in {out}; "
            "the same command resumes the sweep"
        )
        raise
    length, force, unit_t = deck.unit_system or ("in", "lbf", "s")
    if auto:  # the baselines' curves and overlays over the band the search visited
        spec = replace(spec, frequencies=tuple(sorted({r["frequency_hz"] for r in rows})))
        for p in read_csv(Path(out) / "peaks.csv"):
            state = (
                ""
                if p["converged"]
                else (
                    "  AT THE BAND'S EDGE: widen it" if p["at_edge"] else "  NOT SETTLED (points)"
                )
            )
            chain = f" {p['direction']}" if p["direction"] else ""
            echo(
                f"peak {p['config']} drive {p['drive']:g}{chain}: "
                f"{p['peak_hz']:.4f} +/- {p['peak_hz_ci']:.2g} Hz, X = {p['peak_amplitude']:.5e} "
                f"+/- {p['peak_amplitude_ci']:.2g} {length}, half-power band "
                f"{p['band_lo_hz']:.4f}-{p['band_hi_hz']:.4f} Hz, {int(p['points'])} points{state}"
            )

    def overlays(point: tuple[int, int]) -> dict:
        return measured_curves(frfs, spec, point, measured_scale)

    if spec.base:
        return _base_outputs(spec, rows, out, deck_path, length, echo, start, overlays)
    curves = baseline_curves(spec)
    plot_sweep(
        Path(out) / "sweep.png",
        rows,
        {**curves, **overlays((node, dof))},
        title=Path(deck_path).name,
        units=length,
        drive_label=lambda drive: f"{drive:.5g} {force}",
    )
    if measured:
        plot_responses(
            Path(out) / "sweep_responses.png",
            rows,
            measured,
            {r: {**baseline_curves(spec, response=r), **overlays(r)} for r in measured},
            title=Path(deck_path).name,
            units=length,
            force=force,
            time=unit_t,
        )
    for a in attenuations(rows, curves):
        echo(
            f"peak attenuation at drive {a['drive']:g}: {a['attenuation_db']:.2f} dB vs "
            f"{a['baseline']} (peak {a['baseline_peak']:.4e} -> {a['deck_peak']:.4e})"
        )
    echo(
        f"wrote {Path(out) / 'sweep.csv'} and {Path(out) / 'sweep.png'}"
        + (f" and {Path(out) / 'sweep_responses.png'}" if measured else "")
        + " "
        f"({len(rows)} points, {time.perf_counter() - start:.1f} s)"
    )
    return rows


def _base_outputs(
    spec: SweepSpec,
    rows: list[dict],
    out,
    deck_path: str,
    length: str,
    echo: Callable[[str], None],
    start: float,
    overlays,
) -> list[dict]:
    """A base drive's sweep.png (the transmissibility at each response, baselines overlaid) and
    its peak attenuation (the first response's transmissibility against each baseline's)."""

    def base(f, drive):
        w = 2.0 * np.pi * np.asarray(f, float)
        return np.array(
            [displacement_amplitude(drive, spec.quantity, x) for x in np.atleast_1d(w)]
        ).reshape(np.shape(w))

    curves = {r: baseline_curves(spec, response=r) for r in spec.responses}
    system = spec.deck.unit_system
    lab, g = labels_for(system), standard_gravity(system)
    unit = {
        "displacement": lab["length"],
        "velocity": lab["velocity"],
        "acceleration": lab["acceleration"],
    }[spec.quantity]

    def drive_label(drive: float) -> str:
        extra = f" ({drive / g:.4g} g)" if spec.quantity == "acceleration" else ""
        return f"{drive:.5g} {unit}{extra}"

    plot_responses(
        Path(out) / "sweep.png",
        rows,
        spec.responses,
        {r: {**c, **overlays(r)} for r, c in curves.items()},
        title=Path(deck_path).name,
        units=length,
        base=base,
        drive_label=drive_label,
    )
    first = spec.responses[0]
    at_first = [
        {**r, **m, "amplitude": m["transmissibility"]}
        for r in rows
        for m in r.get("responses", ())
        if (m["response_node"], m["response_dof"]) == first
    ]
    t_curves = {key: (f, x / base(f, key[1])) for key, (f, x) in curves[first].items()}
    for a in attenuations(at_first, t_curves):
        echo(
            f"peak attenuation at drive {a['drive']:g}: {a['attenuation_db']:.2f} dB vs "
            f"{a['baseline']} (peak transmissibility at {first[0]}:{first[1]} "
            f"{a['baseline_peak']:.4g} -> {a['deck_peak']:.4g})"
        )
    echo(
        f"wrote {Path(out) / 'sweep.csv'} and {Path(out) / 'sweep.png'} "
        f"({len(rows)} points, {time.perf_counter() - start:.1f} s)"
    )
    return rows
