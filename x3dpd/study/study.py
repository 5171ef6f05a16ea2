"""Run a study and judge it: errors against the finest run, the Pareto front, the verdict."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from x3dpd.api.cluster import check_scheduler
from x3dpd.errors import InputError, UnstableRunError
from x3dpd.study.execute import Job, run_jobs
from x3dpd.study.scene import QUANTITIES, Scene, classify, trace_norm
from x3dpd.study.settings import Setting, ladder

#: Fewest output rows a study's window gets (its output interval shrinks to give them).
MIN_ROWS = 100

_NAMES = {
    "peak_force": "peak force",
    "restitution": "restitution",
    "contact_time": "contact time",
    "amplitude": "amplitude",
    "power_per_cycle": "power dissipated per cycle",
    "dissipated": "energy dissipated",
}


@dataclass
class StudyResult:
    """``rows`` (one dict per run, in ladder order), ``scene``, ``verdict`` (one line),
    ``reference`` (the finest run's row), ``spread`` (chaotic scenes: run-to-run spread of the
    main quantity, relative), ``files`` written."""

    rows: list
    scene: Scene
    verdict: str
    reference: dict
    spread: float
    files: tuple = ()


# Over 80 lines: the study's one flow: ladder, runs, verdict, CSV and figure.
def run_study(
    deck,
    out=None,
    *,
    tmax=None,
    tol=0.01,
    workers=1,
    scheduler=None,
    dts=None,
    usrfrc=(),
    motion=(),
    overwrite=False,
    progress=None,
    fidelity=True,
    stiffness=(),
    walls=(),
    temperature=None,
) -> StudyResult:
    """Run the study of ``deck`` (a path) and write ``out/study.csv`` and ``out/study.png``.

    ``tmax`` ends every run (default the deck's TMAX); ``tol`` is the accepted relative error of
    the main quantity; ``dts`` replaces the default ladder DTMAX x (1/4 ... 8) and may hold
    ``"auto"``: the step chosen by accuracy, also run whenever the deck's DTMIN < DTMAX;
    ``usrfrc`` replaces the deck's USRFRC card (as ``x3dpd run --usrfrc``); ``motion``
    prescribes motions (as ``x3dpd run --motion``: a base-driven deck's shaker drives every
    run); ``fidelity=False`` runs the step ladder only (no elastic or bare-Coulomb variants,
    each a kernel compile); ``stiffness`` adds softer contacts: each a scale of the particles'
    moduli (0.1, 0.01 ...), run at the deck's step lengthened by scale^(-2/5)
    (:func:`x3dpd.api.soft_step`). Raises InputError when ``out`` holds a study and
    ``overwrite`` is not set, when a stiffness scale is not in (0, 1] or the deck's contacts are
    not Hertz (a HOOKE card), or when the finest run goes unstable. ``walls`` adds wall choices
    at the deck's step: ``"rigid"`` (no WALLMAT) or a material of x3dpd.materials on every
    cavity (:func:`x3dpd.study.settings.wall_records`); the deck's own walls are not repeated
    (InputError on a HOOKE deck, whose walls cannot be compliant, and on an unknown material).
    ``temperature`` runs every setting at that operating temperature over the deck's
    TEMPERATURE card's (as ``x3dpd run --temperature``).
    """
    import x3dpd

    cards = x3dpd.load_deck(deck, temperature=temperature)
    model = x3dpd.build(cards, usrfrc=usrfrc, motion=motion)
    files = ()
    if out is not None:
        out = Path(out)
        files = (out / "study.csv", out / "study.png")
        existing = [f for f in files if f.exists()]
        if existing and not overwrite:
            raise InputError(f"{existing[0]} exists; pass --overwrite to replace it")
    stiffness = tuple(float(f) for f in stiffness)
    if any(not 0.0 < f <= 1.0 for f in stiffness):
        raise InputError(f"--stiffness-scale: expected scales in (0, 1], got {stiffness}")
    if stiffness and cards.hooke is not None:
        raise InputError(
            "--stiffness-scale: scales the particles' Hertz moduli (PDMP E0, E1 "
            "...); this deck's contacts follow its HOOKE card"
        )
    scene = classify(model, usrfrc, motion)
    walls = _wall_choices(cards, walls)
    dt_deck = float(model.dt)
    dts = list(dts or [])
    own_auto = cards.parameters.dtmin < cards.parameters.dtmax
    auto = "auto" in dts or own_auto
    dts = [d for d in dts if d != "auto"] or None
    settings = ladder(
        dt_deck,
        dts=dts,
        viscoelastic=fidelity and scene.viscoelastic,
        friction=fidelity and scene.friction,
        chaotic=scene.chaotic,
        stiffness=stiffness,
        friction_law=scene.friction_law,
        walls=walls,
    )
    if auto:  # the deck's own DTMIN ... DTMAX, else up to the coarsest step of the ladder
        settings.append(
            Setting(
                dt_deck if own_auto else max(s.dt for s in settings),
                auto=True,
                friction=scene.friction_law,
            )
        )
    steps = sorted({s.dt for s in settings if not s.auto})
    if scene.kind == "impact":
        interval = steps[0]
    else:
        # the deck's output interval, or finer when the window would hold fewer than
        # MIN_ROWS rows (a short window's amplitude needs rows to be seen at all)
        window = (tmax if tmax is not None else model.tmax) - model.t0
        base = min(model.itrac * dt_deck, window / MIN_ROWS)
        interval = steps[-1] * max(1, math.ceil(base / steps[-1] - 1e-9))
    jobs = [Job(cards, s, tmax, tuple(usrfrc), interval, scene, tuple(motion)) for s in settings]
    check_scheduler(scheduler)
    rows = run_jobs(jobs, workers=workers, scheduler=scheduler, done=progress)
    ref = rows[0]
    if ref["status"] != "complete":
        raise UnstableRunError(
            f"the finest run ({ref['setting'].label}) went unstable: {ref.get('message', '')}"
        )
    spread = _judge(rows, ref, scene)
    verdict = make_verdict(rows, scene, tol, spread)
    result = StudyResult(rows, scene, verdict, ref, spread, tuple(str(f) for f in files))
    if out is not None:
        from x3dpd.study.report import write_csv, write_png

        os.makedirs(out, exist_ok=True)
        write_csv(files[0], result)
        write_png(files[1], result, title=f"{Path(deck).name}: {_NAMES[scene.main]}")
    return result


def _wall_choices(cards, walls) -> tuple:
    """The wall choices to run: ``walls`` without the deck's own (rigid when it has no WALLMAT
    card), each checked (a known material, a deck whose walls can be compliant)."""
    from x3dpd.study.settings import wall_records

    walls = tuple(dict.fromkeys(w.strip().lower() for w in walls if w.strip()))
    if any(w != "rigid" for w in walls) and cards.hooke is not None:
        raise InputError(
            "--walls: this deck's contacts follow its HOOKE card, whose wall "
            "stiffness KN is given directly; wall materials apply to the Hertz law"
        )
    for w in walls:
        wall_records(cards, w)  # an unknown material is refused before any run
    return tuple(w for w in walls if not (w == "rigid" and not cards.wallmat))


def _judge(rows, ref, scene: Scene) -> float:
    """Fill each row's errors (relative to ``ref``), ``trace_norm``, ``pareto``; return the
    chaotic spread (0 when not chaotic)."""
    for r in rows:
        if r["status"] != "complete":
            r["error"] = math.nan
            continue
        for q in QUANTITIES[scene.kind]:
            base = ref.get(q, math.nan)
            r[f"{q}_error"] = abs(r[q] - base) / abs(base) if base else math.nan
        r["error"] = r[f"{scene.main}_error"]
        r["stiffness_scale"] = r["setting"].stiffness
        r["trace_norm"] = (
            trace_norm(r["signal"], ref["signal"]) if scene.kind != "impact" else math.nan
        )
    spread = 0.0
    if scene.chaotic:
        same = [
            r[scene.main]
            for r in rows
            if r["status"] == "complete" and (r["setting"].own or r["setting"].repeat)
        ]
        if len(same) > 1:
            spread = float(np.std(same, ddof=1) / abs(np.mean(same)))
    ok = sorted(
        (r for r in rows if r["status"] == "complete" and not r["setting"].repeat),
        key=lambda r: (r["wall_s_per_sim_s"], r["error"]),
    )
    best = math.inf
    for r in rows:
        r["pareto"] = False
    for r in ok:
        if r["error"] < best:
            r["pareto"] = True
            best = r["error"]
    return spread


def make_verdict(rows, scene: Scene, tol: float, spread: float) -> str:
    """One line: the cheapest setting within ``tol`` (or the run-to-run spread, if larger)
    against the deck's own setting."""
    name = _NAMES[scene.main]
    accept = max(tol, spread)
    pool = [r for r in rows if r["status"] == "complete" and not r["setting"].repeat]
    own = next(r for r in rows if r["setting"].own)
    within = [r for r in pool if r["error"] <= accept]
    if not within:  # the reference's quantity is zero or undefined: nothing to compare
        return (
            f"the {name} of the finest run is {pool[0].get(scene.main, math.nan):.4g}: "
            f"nothing to compare in this window; use a longer --tmax"
        )
    prefix = ""
    if scene.chaotic:
        prefix = (
            f"chaotic scene (trajectories part ways; compared as statistics): the "
            f"{name} varies by {spread:.2%} between perturbed repeats; "
        )
    if own["status"] != "complete":
        cheap = min(within, key=lambda r: r["wall_s_per_sim_s"])
        return (
            prefix + f"the deck's setting ({own['setting'].label}) goes unstable; "
            f"{cheap['setting'].label} gives the {name} within {cheap['error']:.2%} at "
            f"{cheap['wall_s_per_sim_s']:.3g} s per simulated second"
        )
    cheap = min(within, key=lambda r: r["wall_s_per_sim_s"])
    c_own, c_cheap = own["wall_s_per_sim_s"], cheap["wall_s_per_sim_s"]
    if cheap is own:
        ref = pool[0]
        return (
            prefix + f"the deck's setting ({own['setting'].label}) is the cheapest within "
            f"{accept:.2%}: its {name} is within {own['error']:.2%} of the finest run "
            f"({ref['setting'].label}), which takes {ref['wall_s_per_sim_s'] / c_own:.2g}x "
            f"the time"
        )
    if c_cheap < c_own:
        return (
            prefix + f"{cheap['setting'].label} gives the same {name} within "
            f"{cheap['error']:.2%} at {c_own / c_cheap:.2g}x less time than the deck's "
            f"setting ({own['setting'].label}, {own['error']:.2%})"
        )
    return (
        prefix + f"the deck's setting ({own['setting'].label}) errs by {own['error']:.2%} "
        f"in the {name}; {cheap['setting'].label} is the cheapest within {accept:.2%} "
        f"({cheap['error']:.2%}) at {c_cheap / c_own:.2g}x the time"
    )
