"""One point of a frequency sweep: drive a deck with F sin(w (t - t0)) until its steady state.

The run goes through the Python API (:func:`x3dpd.api.run`): the deck's USRFRC drive is replaced
by a sine on the chosen node and DOF -- or, in a base drive, the node is moved on U sin(w (t -
t0)) (a prescribed motion, x3dpd.design.drive; the deck comes without its USRFRC card) -- the
node is recorded at >= ``samples_per_cycle`` samples
per drive period (not at the deck's trace interval), and a
:class:`~x3dpd.analysis.steady_state.SteadyStateMonitor` watches every computed chunk and ends
the run as soon as the criterion of ``x3dpd/analysis/steady_state.py`` is met, or at the cap.
A point of a chain starts from the previous point's final state (``initial_state``), its drive
phase origin at the time it starts; by default the structure is first put on its predicted
steady-state motion (:mod:`x3dpd.design.predict`; ``Criterion.predict``).
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, field, replace

from x3dpd.api import run as run_deck, run_config
from x3dpd.api.decks import Deck
from x3dpd.api.measurements import SteadyStateMonitor, cycles_for_interval
from x3dpd.api.stepper import process_compile_seconds
from x3dpd.api.traces import ENERGY_COLUMNS, ROLLING_COLUMN
from x3dpd.design.drive import BASE_QUANTITIES, base_motion_spec, displacement_amplitude
from x3dpd.design.predict import continued_base_start, predicted_start
from x3dpd.design.replicas import jittered
from x3dpd.errors import InputError

#: Ledger columns summed as the energy dissipated by the particles, and by everything.
PARTICLE_LOSSES = ("dissipated_viscoelastic", "dissipated_friction")
ALL_LOSSES = PARTICLE_LOSSES + ("dissipated_dampers",)
#: The ledger column of the base's (actuator's) work, a base drive's input per cycle.
BASE_WORK = "external_work"


def _ledger_columns(width: int, base: bool) -> dict[str, int]:
    """The ledger columns a point measures per cycle -> their positions in an energy row of
    ``width`` values: the losses (and the rolling loss, ``ROLLING_COLUMN``, which a scene with a
    rolling law adds after ``ENERGY_COLUMNS``), and for a base drive the base's work."""
    names = ENERGY_COLUMNS + ((ROLLING_COLUMN,) if width > len(ENERGY_COLUMNS) else ())
    fed = ALL_LOSSES + ((ROLLING_COLUMN,) if ROLLING_COLUMN in names else ())
    fed += (BASE_WORK,) if base else ()
    return {name: names.index(name) for name in fed}


@dataclass(frozen=True)
class Criterion:
    """Steady-state criterion settings (see x3dpd/analysis/steady_state.py).

    ``tol`` relative tolerance; ``window`` cycles per window; ``min_windows`` windows discarded
    at least; ``max_cycles`` the cap; ``samples_per_cycle`` recording rate; ``extrapolate``
    allow the Prony limit for responses that are linear enough; ``replicas`` runs of each point
    (particles started a hair apart), pooled into one answer (x3dpd.design.replicas), each of
    which may stop once its transient is out and it kept ``replica_cycles`` cycles.
    """

    tol: float = 0.01
    window: int = 5
    min_windows: int = 3
    max_cycles: int = 400
    samples_per_cycle: int = 200
    extrapolate: bool = True
    predict: bool = True
    replicas: int = 1
    replica_cycles: int = 50

    def problems(self) -> list[tuple[str, str]]:
        """The settings that cannot measure a steady state, as ``(setting, what it must be)``:
        a tolerance is a fraction (0 < tol < 1); a window two cycles at least; the cap three
        windows (the transient's and two to compare); 20 samples a cycle; one replica."""
        rules = (
            ("tol", 0.0 < self.tol < 1.0, "a fraction 0 < tol < 1 (0.01: 1 %)"),
            ("window", self.window >= 2, "2 or more cycles"),
            ("max_cycles", self.max_cycles >= 3 * self.window,
             f"3 x window ({3 * self.window}) or more cycles"),
            ("samples_per_cycle", self.samples_per_cycle >= 20, "20 or more"),
            ("replicas", self.replicas >= 1, "1 or more"),
        )  # fmt: skip
        return [(name, must) for name, ok, must in rules if not ok]


@dataclass(frozen=True)
class SweepPoint:
    """One frequency point: which deck (``config``), drive, where, and its place in a chain."""

    config: str
    deck: Deck
    frequency_hz: float
    drive: float
    node: int
    dof: int
    direction: str = ""  # "" (from the deck's initial state), "up" or "down"
    dt: float | None = None
    criterion: Criterion = field(default_factory=Criterion)
    #: (node, dof) pairs measured besides the driven one
    responses: tuple[tuple[int, int], ...] = ()
    #: "force", or a base drive's amplitude quantity (x3dpd.design.drive)
    quantity: str = "force"
    #: which of the point's replicas (x3dpd.design.replicas; 0: the deck as it is)
    replica: int = 0

    @property
    def key(self) -> str:
        """A file-name-safe identity, stable across runs (resuming)."""
        letter = BASE_QUANTITIES.get(self.quantity, "F")
        return (
            f"{self.config}_{letter}{self.drive:.6e}_{self.direction or 'rest'}"
            f"_{self.frequency_hz:.6f}Hz" + (f"_r{self.replica}" if self.replica else "")
        )

    @property
    def base(self) -> bool:
        """Whether the node is moved (a base drive) rather than forced."""
        return self.quantity != "force"

    def base_amplitude(self) -> float:
        """A base drive's displacement amplitude U at this frequency [length]."""
        return displacement_amplitude(self.drive, self.quantity, 2.0 * math.pi * self.frequency_hz)


def run_point(point: SweepPoint, previous=None) -> tuple[dict, object]:
    """Run one point to its steady state; returns (row, final state).

    ``previous`` is the (row, final state) of the point before in a chain, or None to start
    from the deck's initial state.
    """
    if point.dof not in (1, 2, 3):
        raise InputError(f"--dof {point.dof}: the sweep measures a translation, dof 1, 2 or 3")
    crit = point.criterion
    params = point.deck.parameters
    t_start = float(previous[0]["t_end"]) if previous is not None else float(params.time)
    # a point runs at a fixed step: its own, else the deck's DTMAX
    dt = float(point.dt or params.dtmax)
    period = 1.0 / point.frequency_hz
    # a structure without particles has no scatter to average: a deterministic answer
    watch = _Watch(point, t_start, deterministic=not has_particles(point.deck))
    # a replica's particles start a hair apart: everything below runs its deck
    point = replace(point, deck=jittered(point.deck, point.replica))
    usrfrc, motion = _drive_specs(point, t_start)
    wall = _time.perf_counter()
    config = run_config(
        point.deck,
        tmax=t_start + (crit.max_cycles + 1) * period,
        dt=dt,
        usrfrc=usrfrc,
        usrfrc_mode="replace",
        motion=motion,
        itrac=max(1, int(period / (crit.samples_per_cycle * dt))),
        trace_nodes=tuple(n for n, _ in watch.measured),
        keep_trace=False,
        initial_state=previous[1] if previous is not None else None,
        stop=watch.stop,
        stop_every=crit.samples_per_cycle,
    )
    compiled_before = process_compile_seconds()  # the predicted start may build the loop
    state, start = _start(point, previous, config, t_start)
    result = run_deck(config.starting_from(state))
    wall = _time.perf_counter() - wall
    row = _row(point, watch, start, t_start, result.summary)
    row["compile_s"] = process_compile_seconds() - compiled_before
    row["wall_s"] = wall
    return row, result.final_state


def _drive_specs(point: SweepPoint, t_start: float) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(usrfrc, motion) of a point: the sine force on its node, or a base drive's motion,
    with its phase origin at ``t_start``."""
    if point.base:
        amplitude = point.base_amplitude()
        spec = base_motion_spec(point.node, point.dof, amplitude, point.frequency_hz, t_start)
        return (), (spec,)
    force = (
        f"sine:node={point.node},dof={point.dof},amp={float(point.drive)!r},"
        f"hz={float(point.frequency_hz)!r},t0={float(t_start)!r}"
    )
    return (force,), ()


def _start(point: SweepPoint, previous, config, t_start: float):
    """(the state the point's run starts from, how it started: "predicted", "previous" or
    "deck"): by default the structure on its predicted motion (x3dpd.design.predict); a chained
    base drive's base moved onto this point's motion (energy booked)."""
    state = config.initial_state
    start = "previous" if previous is not None else "deck"
    if point.criterion.predict:
        predicted = predicted_start(point, previous, config, t_start)
        if predicted is not None:
            state, start = predicted, "predicted"
    if point.base and start == "previous":
        # the base leaves the previous point's motion for this one's (energy booked)
        state = continued_base_start(point, previous, config, t_start)
    return state, start


class _Watch:
    """The steady-state monitors of a point (its driven node, then each response) and the
    ``stop`` the run calls with every chunk."""

    def __init__(self, point: SweepPoint, t_start: float, deterministic: bool):
        crit = point.criterion
        # R replicas, pooled, reach tol if each reaches tol sqrt(R) (x3dpd.design.replicas)
        tol = crit.tol * math.sqrt(max(crit.replicas, 1))
        self.measured = [(point.node, point.dof)] + list(point.responses)
        self.monitors = [
            SteadyStateMonitor(
                2.0 * math.pi * point.frequency_hz,
                t0=t_start,
                t_start=t_start,
                window=crit.window,
                tol=tol,
                min_windows=crit.min_windows,
                max_cycles=crit.max_cycles,
                extrapolate=crit.extrapolate,
                deterministic=deterministic,
                replica_cycles=crit.replica_cycles if crit.replicas > 1 else None,
            )
            for _ in self.measured
        ]
        self.base = point.base
        # the monitor that measures the point's energies, cycles and how it ended: the driven
        # node's; a base drive's first response (the base itself is steady from its first cycle)
        self.lead = 1 if point.base and point.responses else 0
        self.cols: dict[str, int] = {}  # the ledger columns measured, set by the first block

    def stop(self, block) -> bool:
        if not self.cols:
            self.cols.update(_ledger_columns(block.energy.shape[1], self.base))
        ledger = {name: block.energy[:, j] for name, j in self.cols.items()}
        done = True
        for k, (watch, (_, dof)) in enumerate(zip(self.monitors, self.measured)):
            done &= watch.feed(
                block.time,
                block.position[:, k, dof - 1],
                block.velocity[:, k, dof - 1],
                ledger if k == self.lead else None,
            )
        return done


def _row(point: SweepPoint, watch: _Watch, start: str, t_start: float, summary: dict) -> dict:
    """The point's row (docs/design-guide.md lists the columns) but its compile and wall
    times."""
    ss = watch.monitors[0].result()
    whole = watch.monitors[watch.lead].result()
    loss = whole.dissipated_per_cycle
    losses = ALL_LOSSES + (ROLLING_COLUMN,)
    _, dissipated_hw = whole.energy_interval(losses)
    if point.base:  # the base's work per cycle, from the ledger
        work = loss.get(BASE_WORK, math.nan)
    else:  # steady state: the drive's work per cycle, pi F X sin(-phi), equals the dissipation
        work = math.pi * point.drive * ss.amplitude * math.sin(-math.radians(ss.phase_deg))
    row = {
        "config": point.config,
        "frequency_hz": point.frequency_hz,
        "drive": point.drive,
        "drive_quantity": point.quantity,
        "direction": point.direction,
        **response_columns(ss, point),
        # the rolling loss (a scene with a rolling law) is the particles' too
        "dissipated_per_cycle": sum(loss.get(name, math.nan) for name in ALL_LOSSES)
        + loss.get(ROLLING_COLUMN, 0.0),
        "dissipated_per_cycle_ci": dissipated_hw,
        "dissipated_particles_per_cycle": sum(loss.get(name, math.nan) for name in PARTICLE_LOSSES)
        + loss.get(ROLLING_COLUMN, 0.0),
        # the ledger's split (x3dpd design's columns; sweep.csv keeps the two sums)
        **{f"{name}_per_cycle": loss.get(name, math.nan) for name in losses},
        "input_work_per_cycle": work,
        "cycles": whole.cycles,
        "kept_cycles": whole.kept,
        "stopped_by": whole.method,
        "extrapolated": whole.extrapolated,
        "irregular": whole.irregular,
        "method": "simulated",
        "start": start,
        "t_start": t_start,
        "t_end": float(summary["t_end"]),
        "steps": int(summary["steps"]),
        "compile_s": math.nan,
        "wall_s": math.nan,
        "response_node": point.node,
        "response_dof": point.dof,
        "replica": point.replica,
    }
    if point.responses:
        row["responses"] = [
            response_columns(w.result(), point, node, dof)
            for w, (node, dof) in zip(watch.monitors[1:], point.responses)
        ]
    if point.base:  # the base's own row says whether the point (every node) converged
        row["converged"] = all(w.converged for w in watch.monitors)
    return row


def has_particles(deck: Deck) -> bool:
    """Whether a deck has particle nodes (nodes above the first PDMP card's NODLIM)."""
    if not deck.pdmp:
        return False
    nodlim = min(card.nodlim for card in deck.pdmp)
    return any(node.nid > nodlim for node in deck.nodes)


def response_columns(
    ss, point: SweepPoint, node: int | None = None, dof: int | None = None
) -> dict:
    """The columns of a node measured at ``point`` (its driven node, or a ``--response``):
    accelerance = acceleration / |F| for a force drive, transmissibility = acceleration /
    the base's (w^2 U) for a base drive (the other of the two nan)."""
    w = 2.0 * math.pi * point.frequency_hz
    out = {
        "amplitude": ss.amplitude,
        "amplitude_ci": ss.amplitude_hw,
        "phase": ss.phase_deg,
        "phase_ci": ss.phase_hw_deg,
        "velocity": ss.velocity,
        "acceleration": ss.acceleration,
        "accelerance": math.nan if point.base else ss.acceleration / abs(point.drive),
        "transmissibility": (
            ss.acceleration / (w * w * point.base_amplitude()) if point.base else math.nan
        ),
        "peak": ss.peak,
        "mean": ss.mean,
        "spread": ss.spread,
        "tau_cycles": ss.tau,
        "measured_amplitude": ss.measured_amplitude,
        "change": ss.change,
        "converged": ss.converged,
    }
    if node is not None:
        out = {"response_node": node, "response_dof": dof, **out}
    return out


def cap_flag(row: dict) -> str:
    """How a progress line marks a point stopped at its cap: NOT CONVERGED and, when its
    cycles' autocorrelation time is known, about how many kept cycles an interval of its own
    would need (x3dpd.analysis.confidence: 50 of them) -- the run a ``--max-cycles`` must
    allow, or the work ``--replicas`` share out. Empty for a converged point."""
    if row["converged"]:
        return ""
    tau = row.get("tau_cycles", math.nan)
    if math.isnan(tau):
        return "  NOT CONVERGED (cap)"
    return (
        f"  NOT CONVERGED (cap; tau {tau:.0f} cycles: an interval needs about "
        f"{cycles_for_interval(tau):.0f} kept cycles)"
    )
