"""Run a study's settings: each through :func:`x3dpd.run`, serially or on a Dask cluster.

Every run records at the same output times whatever its step (an interval that all the ladder's
steps divide), so traces compare row by row. A run that goes unstable is a result too: its row
says so and has no error. Runs are timed by the API (``step_wall_s``: stepping only, compiling
excluded); runs that share a machine slow each other, so for timings to trust use one worker
on an otherwise idle machine.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from x3dpd.study.scene import Scene, measure
from x3dpd.study.settings import Setting, deck_for


@dataclass(frozen=True)
class Job:
    """Everything one run needs (picklable, for Dask workers)."""

    deck: object          # x3dpd.deck.Deck
    setting: Setting
    tmax: float | None
    usrfrc: tuple
    out_interval: float   # output interval [s]: every step of the ladder divides it
    scene: Scene


def run_job(job: Job) -> dict:
    """One run: ``setting``, ``status``, ``wall_s_per_sim_s``, the scene's quantities and the
    measured node's ``signal``."""
    import x3dpd

    s = job.setting
    itrac = max(1, int(round(job.out_interval / s.dt)))
    row = {"setting": s, "status": "complete"}
    if s.auto:
        return _run_auto(job, row)
    try:
        res = x3dpd.run(deck_for(job.deck, s), tmax=job.tmax, dt=s.dt, friction=s.friction,
                        usrfrc=job.usrfrc, itrac=itrac,
                        trace_nodes=_nodes(job.deck, job.scene))
    except x3dpd.UnstableRunError as exc:
        row.update(status="unstable", wall_s_per_sim_s=math.nan, message=str(exc))
        return row
    sm = res.summary
    span = sm["t_end"] - sm["t_start"]
    row["wall_s_per_sim_s"] = sm["step_wall_s"] / span if span > 0 else math.nan
    row["steps"] = sm["steps"]
    row["residual"] = sm["residual"]
    row.update(measure(res, job.scene))
    return row


def _run_auto(job: Job, row: dict) -> dict:
    """The step chosen by accuracy between DTMIN and DTMAX (x3dpd.study.variable_step); its
    rows come every DTMAX steps' worth of time (an impact's peak force is then not sampled)."""
    import time
    from dataclasses import replace
    from types import SimpleNamespace

    import x3dpd
    from x3dpd.deck.cards import Trace, Usrfrc
    from x3dpd.errors import UnstableRunError
    from x3dpd.solver.simulation import ENERGY_COLUMNS
    from x3dpd.study.variable_step import VariableStep

    s = job.setting
    deck = replace(deck_for(job.deck, s), trace=Trace(tuple(_nodes(job.deck, job.scene))))
    if job.usrfrc:
        deck = replace(deck, usrfrc=(Usrfrc(tuple(job.usrfrc)),))
    model = x3dpd.build(deck)
    dtmin = deck.parameters.dtmin
    dtmin = dtmin if 0.0 < dtmin < s.dt else s.dt / 1024.0
    interval = s.dt * max(1, int(round(job.out_interval / s.dt)))
    t_end = job.tmax if job.tmax is not None else model.tmax
    vs = VariableStep(model, dtmin=dtmin, dtmax=s.dt, interval=interval, friction=s.friction)
    t = time.perf_counter()
    try:
        res = vs.run(t_end)
    except UnstableRunError as exc:
        row.update(status="unstable", wall_s_per_sim_s=math.nan, message=str(exc))
        return row
    wall = time.perf_counter() - t
    span = res.times[-1] - res.times[0]
    tr = SimpleNamespace(time=res.times, node_ids=model.node_ids[model.trace_nodes],
                         position=res.data[:, :, :3], velocity=res.data[:, :, 3:6])
    energy = {c: res.energy[:, k] for k, c in enumerate(ENERGY_COLUMNS)}
    row["wall_s_per_sim_s"] = wall / span if span > 0 else math.nan
    row["steps"] = res.n_steps
    row["residual"] = float(res.energy[-1, 11] / max(res.state.scale, 1e-300))
    row["message"] = "steps: " + ", ".join(f"{dt:.3g} s from t = {t0:.4g} s"
                                            for t0, dt in res.steps[1:])
    row.update(measure(SimpleNamespace(trace=tr, energy=energy, model=model), job.scene))
    if job.scene.kind == "impact":
        row["peak_force"] = math.nan
    return row


def _nodes(deck, scene: Scene):
    """Trace the measured node and every particle for an impact, the measured node otherwise."""
    if scene.kind != "impact":
        return [scene.node]
    first = min(p.nodlim for p in deck.pdmp)
    return sorted({scene.node} | {n.nid for n in deck.nodes if n.nid > first})


def run_jobs(jobs, *, workers: int = 1, scheduler: str | None = None, done=None) -> list[dict]:
    """Run ``jobs`` (in order of the result list): in this process when ``workers`` is 1 and no
    ``scheduler`` is given, else on a Dask ``LocalCluster`` of ``workers`` processes or the
    cluster at ``scheduler``. ``done(row)`` is called as each run finishes."""
    if workers <= 1 and scheduler is None:
        rows = []
        for job in jobs:
            rows.append(run_job(job))
            if done:
                done(rows[-1])
        return rows
    from dask.distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler is None:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
    client = Client(scheduler if scheduler is not None else cluster)
    try:
        futures = [client.submit(run_job, job, pure=False) for job in jobs]
        index = {f.key: k for k, f in enumerate(futures)}
        rows: list = [None] * len(jobs)
        for future in as_completed(futures):
            rows[index[future.key]] = future.result()
            if done:
                done(rows[index[future.key]])
        return rows
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
