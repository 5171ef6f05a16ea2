"""``x3dpd ringdown``: the damping of a ring-down against its amplitude, from a trace file, from a
deck that is driven and then released (x3dpd.design.ringdown) with the particle-free structure
as the baseline, or from measured time histories (report Section 4.1, Figure 6).

The analysis itself (Hilbert envelope, matched-slope spline, local log decrement) is
:func:`x3dpd.analysis.ringdown.damping_vs_amplitude`.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from x3dpd.api import read_trace
from x3dpd.api.traces import trace_info
from x3dpd.api.figures import plot_ringdown
from x3dpd.api.measurements import (
    G_IN_S2,
    Ringdown,
    damping_vs_amplitude,
    read_measured_history,
    rest_offset,
)
from x3dpd.design.baselines import without_particles
from x3dpd.design.ringdown import ringdown_of_deck, signal_of
from x3dpd.design.spec import default_drive_point
from x3dpd.errors import InputError, TraceError
from x3dpd.units import standard_gravity


def ringdown_of_trace(
    path: str | os.PathLike,
    node: int,
    dof: int,
    *,
    t_from: float | None = None,
    g: float = G_IN_S2,
    **options,
) -> Ringdown:
    """The ring-down of ``node`` along ``dof`` in a trace file, from time ``t_from`` on."""
    if dof not in (1, 2, 3):
        raise InputError(f"--dof {dof}: the ring-down reads a coordinate, dof 1, 2 or 3")
    trace = read_trace(path)
    hit = np.flatnonzero(trace.node_ids == node)
    if hit.size == 0:
        raise InputError(
            f"{path}: node {node} is not in the trace (it holds nodes "
            f"{', '.join(map(str, trace.node_ids[:12]))}"
            f"{' ...' if trace.node_ids.size > 12 else ''})"
        )
    keep = trace.time >= (t_from if t_from is not None else -math.inf)
    return signal_of(trace.time[keep], trace.position[keep, hit[0]], dof, g, **options)


def ringdown_of_measured(
    path: str | os.PathLike, *, t_from: float | None = None, g: float = G_IN_S2, **options
) -> tuple[str, Ringdown]:
    """The ring-down of a measured time history (CSV or UFF, x3dpd.io.measured), from time
    ``t_from`` on: ``(label, analysis)``. A displacement is taken about its rest offset, an
    acceleration as it is (its amplitude is already in g)."""
    m = read_measured_history(path)
    keep = m.time >= (t_from if t_from is not None else -math.inf)
    x = m.signal[keep]
    return m.label, damping_vs_amplitude(
        m.time[keep], x - rest_offset(x), kind=m.kind, g=g, **options
    )


def write_outputs(
    out: str | os.PathLike, series: dict[str, Ringdown], overwrite: bool, title: str = ""
) -> tuple[Path, Path]:
    """DIR/ringdown.csv (one row per evaluation point, ``config`` first) and DIR/ringdown.png."""
    out = Path(out)
    csv, png = out / "ringdown.csv", out / "ringdown.png"
    existing = [p for p in (csv, png) if p.exists()]
    if existing and not overwrite:
        raise InputError(f"{existing[0]} exists; give --overwrite to replace it, or another --out")
    out.mkdir(parents=True, exist_ok=True)
    names = list(next(iter(series.values())).columns())
    lines = [",".join(["config", *names])]
    for config, rd in series.items():
        cols = rd.columns()
        for k in range(rd.time.size):
            lines.append(",".join([config, *(repr(float(cols[n][k])) for n in names)]))
    tmp = csv.with_name(csv.name + ".tmp")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, csv)
    plot_ringdown(png, {k: v.columns() for k, v in series.items()}, title=title)
    return csv, png


def ringdown_command(
    source: str,
    *,
    node: int | None,
    dof: int,
    out: str,
    baseline: str | None = None,
    t_from: float | None = None,
    drive_until: float = 1.0,
    ring: float = 2.0,
    no_baseline: bool = False,
    g: float | None = None,
    overwrite: bool = False,
    measured: tuple[str, ...] = (),
    temperature: str | None = None,
    echo=print,
) -> dict[str, Ringdown]:
    """``x3dpd ringdown``: a trace file, or a deck (driven, released, with its baseline);
    ``measured`` ring-downs (CSV or UFF files) are analysed the same way and overlaid;
    ``temperature`` (not None) runs a deck at that operating temperature (its TEMPERATURE
    card's replaced). ``g``: one standard gravity for dB re 1 g [length/s^2], by default in the
    deck's units (its UNITS card; a trace's, from its sidecar): 386.1 in/s^2, 9.80665 m/s^2."""
    from x3dpd.api import load_deck
    from x3dpd.api.decks import with_temperature

    src = Path(source)
    is_trace = src.name.endswith(".txt") or Path(str(src) + ".json").exists()
    if is_trace and temperature is not None:
        raise InputError(f"--temperature {temperature}: {src} is a trace; it applies to a deck")
    deck = None if is_trace else load_deck(src)
    if g is None:
        g = standard_gravity(_trace_system(src) if is_trace else deck.unit_system)
    measured_series = {}
    for path in measured:  # read and analysed first: a bad file stops before any run
        label, rd = ringdown_of_measured(path, g=g)
        measured_series[f"measured {label}"] = rd
    series: dict[str, Ringdown] = {}
    if is_trace:
        if node is None:
            raise InputError(f"{src}: give --node N (the node of the trace to analyse)")
        series["damper"] = ringdown_of_trace(src, node, dof, t_from=t_from, g=g)
        if baseline:
            series["baseline"] = ringdown_of_trace(baseline, node, dof, t_from=t_from, g=g)
    else:
        if temperature is not None:
            deck = with_temperature(deck, temperature)
        if node is None:
            node = default_drive_point(deck)[0]
        echo(f"ringdown {src}: driven to t = {drive_until:g} s, then {ring:g} s free")
        series["damper"] = ringdown_of_deck(
            deck, node, dof, drive_until=drive_until, ring=ring, g=g
        )
        if not no_baseline:
            series["baseline (no particles)"] = ringdown_of_deck(
                without_particles(deck), node, dof, drive_until=drive_until, ring=ring, g=g
            )
    series.update(measured_series)
    csv, png = write_outputs(out, series, overwrite, title=src.name)
    for name, rd in series.items():
        echo(
            f"  {name}: zeta {100 * rd.zeta.min():.3g}-{100 * rd.zeta.max():.3g} % over "
            f"{rd.amplitude_db.min():.1f} to {rd.amplitude_db.max():.1f} dB re 1 g"
        )
    echo(f"wrote {csv} and {png}")
    return series


def _trace_system(trace: Path):
    """The (length, force, time) units a trace's sidecar records, None without a sidecar (the
    trace's own reading then says what is wrong with it)."""
    try:
        units = trace_info(trace).units
    except TraceError:
        return None
    return units.get("length", "in"), units.get("force", "lbf"), units.get("time", "s")
