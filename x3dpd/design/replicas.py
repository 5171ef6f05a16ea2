"""Replicas of a sweep point: the same point run R times, each with its particles started a
hair apart, on as many workers, pooled into one answer with one interval (issue 30, item 4).

A damper's answer at a point is a time average over a chaotic motion; R independent runs give
R estimates m_i with 95 % half-widths h_i (x3dpd.analysis.confidence), each computed to the
looser tolerance tol sqrt(R) so that together they reach tol -- about 1/R of one run's cycles
each, on R workers at once -- or until its transient is out and it kept ``replica_cycles``
cycles (x3dpd.design.steady_state.Criterion): a chaotic bed wanders over tens of cycles, and
one run's own interval needs 50 of its autocorrelation times (x3dpd.analysis.confidence),
while R independent replicas' spread measures their means' scatter directly.

Replica 0 is the deck as it is; replica r > 0 moves every particle coordinate by a uniform
random amount of at most ``JITTER`` of the smallest particle radius (seed r): far below any
geometric tolerance, and the chaos makes the runs independent within a cycle (a one-ulp
difference grows 10x per simulated millisecond in the beam decks: tests/golden/
PROVENANCE.json's rounding envelopes).

**Pooling.** When every replica has an interval of its own: inverse-variance weighting, with
the replicas' scatter as a check -- with sigma_i = h_i / 1.96 and w_i = 1 / sigma_i^2, the
pooled mean is sum w_i m_i / sum w_i, its standard error (sum w_i)^(-1/2), scaled by
sqrt(chi^2 / (R - 1)) when the replicas disagree more than their intervals allow (chi^2 =
sum w_i (m_i - mean)^2 > R - 1: coexisting motions, a start that picks another state), and
the half-width 1.96 times that. Otherwise (replicas stopped as long enough to pool, or
periodic ones with a zero half-width): the plain mean, and the half-width from the replicas'
spread, t_{0.975, R-1} s / sqrt(R) (s their standard deviation): independent runs of the same
stationary motion, whatever its correlation within a run. Amplitude, phase and the
dissipation per cycle are pooled alike; cycles, steps and times add up. The point has
converged when every replica did and the pooled half-width is within tol of the amplitude.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from x3dpd.api.decks import Deck

#: A replica's particles start within this fraction of the smallest particle radius of the
#: deck's positions.
JITTER = 1e-6
#: (value, half-width) columns pooled; the rest are replica 0's, or summed (``SUMMED``).
POOLED = (
    ("amplitude", "amplitude_ci"),
    ("phase", "phase_ci"),
    ("dissipated_per_cycle", "dissipated_per_cycle_ci"),
)
SUMMED = ("cycles", "kept_cycles", "steps", "wall_s", "compile_s")
#: the other value columns averaged over the replicas
AVERAGED = (
    "velocity",
    "acceleration",
    "accelerance",
    "transmissibility",
    "peak",
    "mean",
    "spread",
    "tau_cycles",
    "dissipated_particles_per_cycle",
    "dissipated_viscoelastic_per_cycle",
    "dissipated_friction_per_cycle",
    "dissipated_dampers_per_cycle",
    "dissipated_rolling_per_cycle",
    "input_work_per_cycle",
    "measured_amplitude",
    "change",
)


def jittered(deck: Deck, replica: int) -> Deck:
    """Replica ``replica`` of a deck: its particle nodes moved by at most JITTER of the
    smallest particle radius along each axis (seed ``replica``; replica 0 is the deck)."""
    if replica == 0 or not deck.pdmp:
        return deck
    nodlim = min(card.nodlim for card in deck.pdmp)
    scale = JITTER * min(card.rzero for card in deck.pdmp)
    rng = np.random.default_rng(replica)
    nodes = []
    for node in deck.nodes:
        if node.nid > nodlim:
            dx, dy, dz = rng.uniform(-scale, scale, 3)
            node = replace(node, x=node.x + dx, y=node.y + dy, z=node.z + dz)
        nodes.append(node)
    return replace(deck, nodes=tuple(nodes))


def pool(values, half_widths) -> tuple[float, float]:
    """(pooled mean, its 95 % half-width) of replica estimates (module docstring)."""
    from x3dpd.api.measurements import t_quantile

    m = np.asarray(values, dtype=float)
    h = np.asarray(half_widths, dtype=float)
    if m.size == 1:
        return float(m[0]), float(h[0])
    if not np.all(np.isfinite(h)) or np.any(h == 0.0):
        # replicas without an interval of their own (stopped as long enough to pool), or
        # periodic ones: the plain mean, its interval from the replicas' own spread
        spread = float(np.std(m, ddof=1)) / math.sqrt(m.size)
        return float(np.mean(m)), t_quantile(m.size - 1) * spread
    w = (1.96 / h) ** 2
    mean = float(np.sum(w * m) / np.sum(w))
    se = float(np.sum(w)) ** -0.5
    chi2 = float(np.sum(w * (m - mean) ** 2))
    if chi2 > m.size - 1:
        se *= math.sqrt(chi2 / (m.size - 1))
    return mean, 1.96 * se


def _pooled_columns(rows: list[dict]) -> dict:
    """The pooled and averaged value columns of replica rows (module docstring)."""
    out = {}
    for value, hw in POOLED:
        if value in rows[0]:
            out[value], out[hw] = pool([r[value] for r in rows], [r[hw] for r in rows])
    for column in AVERAGED:
        if column in rows[0]:
            out[column] = float(np.mean([r[column] for r in rows]))
    return out


def pool_rows(rows: list[dict], tol: float) -> dict:
    """One row of a point's replicas (module docstring); ``replicas`` their number. It
    converged when every replica did and the pooled amplitude's half-width is within ``tol``
    of the amplitude."""
    rows = sorted(rows, key=lambda r: r.get("replica", 0))
    out = {**rows[0], **_pooled_columns(rows)}
    for column in SUMMED:
        if column in out:
            out[column] = sum(r[column] for r in rows)
    out["converged"] = all(bool(r["converged"]) for r in rows) and (
        out["amplitude_ci"] <= tol * abs(out["amplitude"])
    )
    out["irregular"] = any(bool(r["irregular"]) for r in rows)
    out["replicas"] = len(rows)
    out.pop("replica", None)
    if "responses" in out:
        out["responses"] = [
            {
                **rows[0]["responses"][k],
                **_pooled_columns([r["responses"][k] for r in rows]),
                "converged": all(bool(r["responses"][k]["converged"]) for r in rows),
            }
            for k in range(len(out["responses"]))
        ]
    return out


def pooled(rows: list[dict], tol: float) -> list[dict]:
    """Every point's replicas pooled into one row (points without replicas as they are),
    ``tol`` the points' relative tolerance."""
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        key = (r["config"], r["drive"], r["direction"], r["frequency_hz"])
        groups.setdefault(key, []).append(r)
    return [pool_rows(g, tol) if len(g) > 1 else {**g[0], "replicas": 1} for g in groups.values()]
