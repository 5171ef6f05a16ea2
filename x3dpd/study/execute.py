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

from x3dpd.api.cluster import connect_scheduler
from x3dpd.study.scene import Scene, measure
from x3dpd.study.settings import Setting, deck_for


@dataclass(frozen=True)
class Job:
    """Everything one run needs (picklable, for Dask workers)."""

    deck: object  # x3dpd.deck.Deck
    setting: Setting
    tmax: float | None
    usrfrc: tuple
    out_interval: float  # output interval [s]: every step of the ladder divides it
    scene: Scene
    motion: tuple = ()  # prescribed motions (x3dpd run --motion)


def run_job(job: Job) -> dict:
    """One run: ``setting``, ``status``, ``wall_s_per_sim_s``, ``cpu_s_per_sim_s`` (the
    process's CPU time over the run per simulated second, after a two-step run of the same
    deck has compiled or loaded its step loop: what the run costs on a loaded machine, where
    wall time also counts the other jobs), the scene's quantities and the
    measured node's ``signal``. The step chosen by accuracy (``auto``) runs
    ``x3dpd.run(dt="auto")`` up to the setting's DTMAX; its rows come every output interval, a
    whole number of DTMAX steps, so an impact's peak force is not sampled (NaN)."""
    import time
    from dataclasses import replace

    import x3dpd

    s = job.setting
    itrac = max(1, int(round(job.out_interval / s.dt)))
    row = {"setting": s, "status": "complete"}
    deck = deck_for(job.deck, s)
    if s.auto:  # up to s.dt; down to the deck's DTMIN when it gives one, else s.dt / 1024
        par = deck.parameters
        dtmin = par.dtmin if par.dtmin < par.dtmax else 0.0
        deck = replace(deck, parameters=replace(par, dtmin=dtmin, dtmax=s.dt))
    try:
        config = x3dpd.run_config(
            deck,
            tmax=job.tmax,
            dt="auto" if s.auto else s.dt,
            itrac=itrac,
            friction=s.friction,
            usrfrc=job.usrfrc,
            motion=job.motion,
            trace_nodes=_nodes(job.deck, job.scene),
        )
        # compile (or load) the step loop outside the CPU time: two steps of the same scene
        x3dpd.run(config, tmax=deck.parameters.time + 2.0 * s.dt, itrac=1)
        cpu = time.process_time()
        res = x3dpd.run(config)
        cpu = time.process_time() - cpu
    except x3dpd.UnstableRunError as exc:
        row.update(status="unstable", wall_s_per_sim_s=math.nan, message=str(exc))
        return row
    sm = res.summary
    span = sm["t_end"] - sm["t_start"]
    row["wall_s_per_sim_s"] = _stepping_seconds(sm) / span if span > 0 else math.nan
    row["cpu_s_per_sim_s"] = cpu / span if span > 0 else math.nan
    row["steps"] = sm["steps"]
    row["residual"] = sm["residual"]
    row.update(measure(res, job.scene))
    if s.auto:
        st = sm["step"]
        row["message"] = (
            f"steps {st['min']:.3g} .. {st['max']:.3g} s, mean {st['mean']:.3g} s"
            if st["steps"]
            else ""
        )
        if job.scene.kind == "impact":
            row["peak_force"] = math.nan
    return row


def _stepping_seconds(summary: dict) -> float:
    """The API's stepping wall time; a run so short that its only chunk included compiling or
    loading the step loop has none, so its whole wall time less that compile/load time."""
    if summary["step_wall_s"] > 0:
        return summary["step_wall_s"]
    rest = summary["wall_s"] - summary["compile_s"]
    return rest if rest > 0 else math.nan


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
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        )
    client = connect_scheduler(scheduler) if scheduler is not None else Client(cluster)
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
