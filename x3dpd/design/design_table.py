"""``DIR/design.csv``: one row per configuration and evaluation point (docs/design.md).

A sweep's or dwell's row is a point of the configuration's deck (``config`` = deck in its
sweep.csv) with what the designer compares: the added mass and mass ratio, the baselines'
amplitudes at the same frequency and drive and the attenuation against each,
20 log10(X_baseline / X) [dB], the configuration's peak attenuation over the band (the peak of
its points against the peak of the closed-form baseline curve, x3dpd.analysis.design_plots.
attenuations), the ledger's dissipation per cycle split into viscoelastic, friction and
dampers, and the convergence flags. A ring-down's rows are % zeta at amplitudes spread over the
ring-down's range (``RINGDOWN_POINTS``), with the structure's own zeta where it is linear.

Each point carries the 95 % half-widths of its amplitude, phase and dissipation per cycle
(``amplitude_ci``, ``phase_ci``, ``dissipated_per_cycle_ci``: x3dpd.analysis.confidence), and
each configuration's score the half-width ``score_ci`` that follows from its peak point's
(dB: 20 / ln 10 x ci / X), at least the tolerance the points were computed to,
20 log10(1 + tol) dB: a difference smaller than that is numerical noise, not a design's.

The best configuration (``best`` = 1 on its rows) is the one whose worst peak attenuation over
the drive levels (vs the undamped baseline, else vs added mass; without either, the smallest
peak amplitude) is largest -- for a ring-down the largest mean % zeta -- among those whose
added mass is within the design's ``mass_budget`` (``within_budget``) and whose every point
converged -- and only when its score's interval does not overlap the runner-up's. Otherwise
no configuration is best, and the leader's rows say ``no significant difference`` from the
runner-up (``verdict``).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from x3dpd.api.figures import attenuations
from x3dpd.design.closed_form import baseline_curves

#: design.csv columns, in order.
COLUMNS = (
    "config",
    "material",
    "radius",
    "count",
    "cavities",
    "fill_ratio",
    "cavity_length",
    "clearance",
    "dt",
    "stiffness_scale",
    "temperature",
    "added_mass",
    "mass_ratio",
    "evaluation",
    "drive",
    "frequency_hz",
    "direction",
    "amplitude",
    "amplitude_ci",
    "phase",
    "phase_ci",
    "acceleration",
    "amplitude_db",
    "zeta_percent",
    "zeta_ci_percent",
    "baseline_zeta_percent",
    "baseline_undamped",
    "baseline_added_mass",
    "attenuation_undamped_db",
    "attenuation_added_mass_db",
    "peak_amplitude",
    "peak_attenuation_undamped_db",
    "peak_attenuation_added_mass_db",
    "dissipated_viscoelastic_per_cycle",
    "dissipated_friction_per_cycle",
    "dissipated_dampers_per_cycle",
    "dissipated_rolling_per_cycle",
    "dissipated_per_cycle",
    "dissipated_per_cycle_ci",
    "input_work_per_cycle",
    "cycles",
    "replicas",
    "converged",
    "extrapolated",
    "irregular",
    "within_budget",
    "score",
    "score_ci",
    "best",
    "verdict",
    "notes",
)
#: Rows per ring-down (amplitudes evenly spread in dB over its range).
RINGDOWN_POINTS = 25
SPLIT = (
    "dissipated_viscoelastic",
    "dissipated_friction",
    "dissipated_dampers",
    "dissipated_rolling",
)


def _db(reference: float, value: float) -> float:
    return 20.0 * math.log10(reference / value) if reference > 0 and value > 0 else math.nan


def _config_columns(c) -> dict:
    v = c.made.values
    return {
        "config": c.made.config.name,
        **{
            k: v[k]
            for k in (
                "material",
                "radius",
                "count",
                "cavities",
                "fill_ratio",
                "cavity_length",
                "clearance",
                "dt",
                "stiffness_scale",
                "added_mass",
            )
        },
        "temperature": v.get("temperature", math.nan),
        "mass_ratio": v.get("mass_ratio", math.nan),
        "notes": " | ".join(v.get("notes", ())),
    }


def design_rows(design, configs) -> list[dict]:
    """Every configuration's rows (module doc), the best one marked."""
    kind = design.evaluation.kind
    rows = []
    for c in configs:
        mine = _ringdown_rows(c) if kind == "ringdown" else _sweep_rows(c)
        base = {**_config_columns(c), "evaluation": kind}
        rows.extend({**base, **r} for r in mine)
    mark_best(rows, design.mass_budget, kind, design.evaluation.criterion.tol)
    return rows


def noise_db(tol: float) -> float:
    """The smallest difference of scores a design resolves: 20 log10(1 + tol) dB for points
    computed to the relative tolerance ``tol`` (module doc)."""
    return 20.0 * math.log10(1.0 + tol)


def _sweep_rows(c) -> list[dict]:
    by = {(r["config"], r["drive"], r["frequency_hz"], r["direction"]): r for r in c.rows}
    curves = baseline_curves(c.spec)
    peaks = {(a["drive"], a["baseline"]): a["attenuation_db"] for a in attenuations(c.rows, curves)}
    out = []
    for r in c.rows:
        if r["config"] != "deck":
            continue
        cells = {
            k: r[k]
            for k in (
                "drive",
                "frequency_hz",
                "direction",
                "amplitude",
                "amplitude_ci",
                "phase",
                "phase_ci",
                "acceleration",
                "dissipated_per_cycle",
                "dissipated_per_cycle_ci",
                "input_work_per_cycle",
                "cycles",
                "replicas",
                "converged",
                "extrapolated",
                "irregular",
            )
        }
        cells["peak_amplitude"] = max(
            x["amplitude"] for x in c.rows if x["config"] == "deck" and x["drive"] == r["drive"]
        )
        for name in SPLIT:
            cells[f"{name}_per_cycle"] = r.get(f"{name}_per_cycle", math.nan)
        for config in ("undamped", "added-mass"):
            col = config.replace("-", "_")
            ref = by.get((config, r["drive"], r["frequency_hz"], "")) or by.get(
                (config, r["drive"], r["frequency_hz"], r["direction"])
            )
            cells[f"baseline_{col}"] = ref["amplitude"] if ref else math.nan
            cells[f"attenuation_{col}_db"] = _db(cells[f"baseline_{col}"], r["amplitude"])
            cells[f"peak_attenuation_{col}_db"] = peaks.get((r["drive"], config), math.nan)
        out.append(cells)
    return out


def _ringdown_rows(c) -> list[dict]:
    from x3dpd.api import build
    from x3dpd.design.baselines import linear_structure, without_particles

    zeta0 = math.nan
    sdof = linear_structure(build(without_particles(c.made.deck)), c.node, c.dof)
    if sdof is not None and hasattr(sdof, "k"):  # an SDOF: zeta = c / (2 sqrt(k m))
        zeta0 = 100.0 * sdof.c / (2.0 * math.sqrt(sdof.k * sdof.m))
    out = []
    for level, cols in sorted(c.ringdowns.items(), key=lambda kv: str(kv[0])):
        db = np.asarray(cols["amplitude_db"])
        zeta = np.asarray(cols["zeta_percent"])
        if db.size == 0:
            continue
        order = np.argsort(db)
        grid = np.linspace(db.min(), db.max(), RINGDOWN_POINTS)
        z = np.interp(grid, db[order], zeta[order])
        # a ring-down stored before the intervals has none: nan
        ci = np.asarray(cols.get("zeta_ci_percent", np.full(db.size, np.nan)))
        zc = np.interp(grid, db[order], ci[order])
        g = np.interp(grid, db[order], np.asarray(cols["amplitude_g"])[order])
        for x, y, e, a in zip(grid, z, zc, g):
            out.append(
                {
                    "drive": level,
                    "amplitude_db": float(x),
                    "zeta_percent": float(y),
                    "zeta_ci_percent": float(e),
                    "acceleration": float(a),
                    "converged": True,
                }
            )
    for r in out:
        r["baseline_zeta_percent"] = zeta0
    return out


def _score(mine: list[dict], kind: str) -> tuple[float, float]:
    """A configuration's score and its 95 % half-width (module doc): for a ring-down the mean
    % zeta (its half-width the levels' mean ``zeta_ci_percent``: the levels come from one record
    and err together), for a sweep the worst
    peak attenuation over the drive levels, its half-width from that drive's peak point."""
    if kind == "ringdown":
        zeta = [r["zeta_percent"] for r in mine]
        ci = [r.get("zeta_ci_percent", 0.0) for r in mine]
        return float(np.mean(zeta)), float(np.nan_to_num(np.mean(ci), nan=0.0))
    per_drive = {}
    for r in mine:
        att = r["peak_attenuation_undamped_db"]
        if not math.isfinite(att):
            att = r["peak_attenuation_added_mass_db"]
        if not math.isfinite(att):
            att = -20.0 * math.log10(r["peak_amplitude"])
        peak = max((x for x in mine if x["drive"] == r["drive"]), key=lambda x: x["amplitude"])
        ci = 20.0 / math.log(10.0) * peak.get("amplitude_ci", 0.0) / peak["amplitude"]
        per_drive[r["drive"]] = (att, ci)
    return min(per_drive.values())


def mark_best(rows: list[dict], budget: float | None, kind: str, tol: float) -> None:
    """``within_budget``, ``score``, ``score_ci``, ``best`` and ``verdict`` of every row
    (module doc) of points computed to the relative tolerance ``tol``: no score is more
    certain than that (a sweep's dB: ``noise_db``; a ring-down's % zeta: tol of it)."""
    scores: dict[str, tuple[float, float]] = {}
    for config in dict.fromkeys(r["config"] for r in rows):
        score, ci = _score([r for r in rows if r["config"] == config], kind)
        noise = tol * abs(score) if kind == "ringdown" else noise_db(tol)
        scores[config] = (score, max(ci, noise) if math.isfinite(ci) else math.inf)
    ok = {r["config"] for r in rows if budget is None or r["added_mass"] <= budget * (1 + 1e-12)}
    converged = {
        config
        for config in scores
        if all(bool(r.get("converged", True)) for r in rows if r["config"] == config)
    }
    ranked = sorted(
        (k for k in scores if k in ok and k in converged and math.isfinite(scores[k][0])),
        key=lambda k: -scores[k][0],
    )
    best, verdict = None, {}
    if len(ranked) == 1:
        best = ranked[0]
    elif len(ranked) > 1:
        (first, (s1, c1)), (second, (s2, c2)) = ((k, scores[k]) for k in ranked[:2])
        if s1 - c1 > s2 + c2:
            best = first
        else:
            verdict[first] = f"no significant difference from {second}"
            verdict[second] = f"no significant difference from {first}"
    for r in rows:
        r["within_budget"] = r["config"] in ok
        r["score"], r["score_ci"] = scores[r["config"]]
        r["best"] = r["config"] == best
        r["verdict"] = "best" if r["best"] else verdict.get(r["config"], "")


def _cell(v) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "1" if v else "0"
    if isinstance(v, float):  # np.float64 too: its repr is np.float64(...) on numpy 2
        return repr(float(v))
    return str(v).replace(",", ";")


def write_design_csv(path: str | os.PathLike, rows: list[dict]) -> None:
    """design.csv (columns :data:`COLUMNS`, full-precision floats), written atomically."""
    path = Path(path)
    text = (
        "\n".join(
            [",".join(COLUMNS)] + [",".join(_cell(r.get(c, "")) for c in COLUMNS) for r in rows]
        )
        + "\n"
    )
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)
