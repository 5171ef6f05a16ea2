"""``--freq auto:LO:HI``: a sweep that finds each response's peak and half-power band with as
few points as it can (issue 30 item 3; the search: x3dpd.analysis.peak_search).

Every simulated configuration, drive level and chain direction searches on its own: the
coarse pass first, then one refinement point at a time at the fitted peak, all groups'
points of a round run together on the sweep's executor (x3dpd.design.sweep.Executor). With a
direction the coarse points form a chain in that order (the particles carried from point to
point, as in a fixed sweep); a refinement point continues from the state of the computed
point just before it in the chain's direction -- the next higher frequency for ``down``, the
next lower for ``up`` -- so that it, too, is reached by sweeping from the chain's start.
Without a direction each point starts on its own (predicted start). Closed-form baselines are
evaluated at the frequencies the deck's search visited, and their peaks exactly.

Finished points are stored as in a fixed sweep (DIR/points): a rerun proposes the same
frequencies from the same rows, finds them stored and goes on where it stopped.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from x3dpd.api.measurements import PeakSearch
from x3dpd.design.spec import SweepSpec
from x3dpd.design.steady_state import run_point
from x3dpd.design.replicas import pooled
from x3dpd.design.sweep import point_maker, replica_count

#: peaks.csv columns, in order.
PEAK_COLUMNS = (
    "config",
    "drive",
    "direction",
    "peak_hz",
    "peak_hz_ci",
    "peak_amplitude",
    "peak_amplitude_ci",
    "band_lo_hz",
    "band_hi_hz",
    "points",
    "converged",
    "at_edge",
)


def peak_value(row: dict) -> tuple[float, float]:
    """(amplitude, its 95 % half-width) a search maximizes: the driven node's for a force
    drive, the first measured response's for a base drive."""
    if row.get("drive_quantity", "force") != "force" and row.get("responses"):
        first = row["responses"][0]
        return first["amplitude"], first.get("amplitude_ci", math.nan)
    return row["amplitude"], row.get("amplitude_ci", math.nan)


@dataclass
class _Group:
    """One search: a configuration, drive and direction, its points' rows and states."""

    config: str
    drive: float
    direction: str
    point: object  # (f, direction, replica) -> SweepPoint
    search: PeakSearch
    replicas: int = 1
    rows: list = field(default_factory=list)
    #: (frequency, replica) -> (row, state) of chain points
    states: dict = field(default_factory=dict)

    def measured(self) -> list[tuple[float, float, float]]:
        """(frequency, amplitude, half-width) of every point, its replicas pooled."""
        return [(r["frequency_hz"], *peak_value(r)) for r in pooled(self.rows, self.search.tol)]

    def upstream(self, f: float, replica: int):
        """(row, state) of the replica's computed point just before ``f`` in the chain's
        direction."""
        mine = [g for g, r in self.states if r == replica]
        if self.direction == "down":
            above = [g for g in mine if g > f]
            return self.states[(min(above), replica)] if above else None
        below = [g for g in mine if g < f]
        return self.states[(max(below), replica)] if below else None


@dataclass(frozen=True)
class AutoJob:
    """One sweep's searches: its ``spec`` (``spec.auto`` set), ``store`` (its folder,
    x3dpd.design.sweep.SweepDir), the ``simulated`` (config, deck) pairs and
    ``finished_row(row, computed)``, told of each point as it finishes (stored ones too, with
    ``computed`` False)."""

    spec: SweepSpec
    store: object
    simulated: list
    finished_row: object


def _groups(job: AutoJob) -> list[_Group]:
    spec, band = job.spec, job.spec.auto
    directions = {None: ("",), "up": ("up",), "down": ("down",), "both": ("up", "down")}[
        spec.direction
    ]
    return [
        _Group(
            config,
            drive,
            direction,
            point_maker(spec, config, deck, drive),
            PeakSearch(band.lo, band.hi, band.resolution, band.max_points, spec.criterion.tol),
            replica_count(spec, deck),
        )
        for config, deck in job.simulated
        for drive in spec.drives
        for direction in directions
    ]


def run_auto(jobs: list[AutoJob], executor) -> list[list[_Group]]:
    """Search every job's simulated configurations at every drive and direction, the rounds
    of all jobs together on ``executor`` (module docstring). Returns each job's searches,
    their rows filled."""
    searches = [_groups(job) for job in jobs]
    while True:
        todo, found = [], False
        for job, groups in zip(jobs, searches):
            for g in groups:
                found |= _propose(g, job, todo)
        if found:
            continue  # stored points change the next proposals: propose again first
        if not todo:
            return searches
        executor.run(todo)


def _propose(g: _Group, job: AutoJob, todo: list) -> bool:
    """Queue the search's next points on ``todo`` (those not stored); whether any were stored
    (kept, and the caller proposes again before running)."""
    fresh = g.search.next_frequencies(g.measured())
    if not fresh:
        return False
    chained = bool(g.direction)
    found = False
    if chained and not g.rows:  # the coarse pass: one chain per replica, in the direction
        fresh = sorted(fresh, reverse=g.direction == "down")
        for r in range(g.replicas):
            found |= _load_chain(g, [g.point(f, g.direction, r) for f in fresh], job, todo)
        return found
    for f in fresh:
        for r in range(g.replicas):
            point = g.point(f, g.direction, r)
            done = job.store.load(point, need_state=chained)
            if done is not None:
                _keep(g, point, done, job.finished_row, computed=False)
                found = True
                continue
            previous = g.upstream(f, r) if chained else None
            todo.append((run_point, [point], previous, _finisher(g, job)))
    return found


def _load_chain(g: _Group, chain: list, job: AutoJob, todo) -> bool:
    """Load a coarse chain's stored points; queue the rest of it. Whether any was stored."""
    previous, found = None, False
    for k, point in enumerate(chain):
        done = job.store.load(point, need_state=True)
        if done is None:
            todo.append((run_point, chain[k:], previous, _finisher(g, job)))
            return found
        _keep(g, point, done, job.finished_row, computed=False)
        previous, found = done, True
    return found


def _keep(g: _Group, point, result, finished_row, computed: bool = True) -> None:
    row, state = result
    g.rows.append(row)
    if g.direction:
        g.states[(point.frequency_hz, point.replica)] = (row, state)
    finished_row(row, computed)


def _finisher(g: _Group, job: AutoJob):
    def finished(point, chain_len, result) -> None:
        job.store.save(point, result[0], result[1], keep_state=bool(g.direction))
        _keep(g, point, result, job.finished_row)

    return finished


def write_peaks(path, groups: list[_Group]) -> list[dict]:
    """peaks.csv (columns :data:`PEAK_COLUMNS`), written atomically; returns its rows."""
    from x3dpd.design.sweep_table import _cell, write_atomic

    peaks = peak_rows(groups)
    lines = [",".join(PEAK_COLUMNS)] + [",".join(_cell(p[c]) for c in PEAK_COLUMNS) for p in peaks]
    write_atomic(path, ("\n".join(lines) + "\n").encode())
    return peaks


def peak_rows(groups: list[_Group]) -> list[dict]:
    """peaks.csv's rows: each search's fitted peak (x3dpd.analysis.peak_search.Peak)."""
    out = []
    for g in groups:
        if not g.rows:
            continue
        p = g.search.peak(g.measured())
        out.append(
            {
                "config": g.config,
                "drive": g.drive,
                "direction": g.direction,
                "peak_hz": float(p.frequency_hz),
                "peak_hz_ci": float(p.frequency_ci),
                "peak_amplitude": float(p.amplitude),
                "peak_amplitude_ci": float(p.amplitude_ci),
                "band_lo_hz": float(p.band_lo_hz),
                "band_hi_hz": float(p.band_hi_hz),
                "points": p.points,
                "converged": p.converged,
                "at_edge": p.at_edge,
            }
        )
    return out


def visited(spec: SweepSpec, groups: list[_Group]) -> SweepSpec:
    """The spec with the frequencies the searches visited (for closed-form baselines)."""
    freqs = sorted({r["frequency_hz"] for g in groups for r in g.rows})
    return replace(spec, frequencies=tuple(freqs))
