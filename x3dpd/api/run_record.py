"""Steps 4-6 of :func:`x3dpd.api.run` (docs/running.md; steps 1-3 in
:mod:`x3dpd.api.run_steps`, whose :class:`~x3dpd.api.run_steps.RunPlan` they share):

4. :func:`start_recording` -- the recorder and the sink the rows go to, the row at t0;
5. :func:`step` -- step to TMAX (or a stop, a signal), taking restart dumps (:func:`dump`);
6. :func:`summarise` -- the :class:`RunResult`: trace, energy ledger, summary, final state.
"""

from __future__ import annotations

import os
import time

from x3dpd import __version__
from x3dpd.api.loop import Interrupts, Sink, note_energy, relative_residual, step_loop
from x3dpd.api.results import FinalState, Recorder, RunResult
from x3dpd.api.run_steps import RunPlan
from x3dpd.api.stepping import auto_summary
from x3dpd.physics.usrfrc import is_user_file
from x3dpd.solver.compile_log import record_compile_seconds


def dump(plan: RunPlan, reason: str) -> None:
    """A restart dump (when writing files): the state, where the trace and energy files stand
    and what the run was asked, so that a resumed run continues bit for bit."""
    if not plan.writes:
        return
    config, files = plan.config, plan.config.files
    sim, writer, ewriter = plan.sim, plan.writer, plan.ewriter
    if plan.auto:
        writer.describe(step=sim.step_record())
    writer.flush()
    ewriter.flush()
    from x3dpd.io.restart import save_restart

    extra = {"variable_step": sim.checkpoint()} if plan.auto else {}
    save_restart(
        files.dump,
        sim.state.to_arrays(),
        {
            **extra,
            "reason": reason,
            "x3dpd_version": __version__,
            "deck_path": config.deck_path,
            "deck_abspath": os.path.abspath(config.deck_path),
            "deck_sha256": plan.deck_sha,
            "deck_key": config.key,
            "dt": config.step.dt,
            "itrac": config.itrac,
            "t0": config.model.t0,
            "step": int(sim.clock),
            "time": sim.time,
            "trace": {
                "path": files.trace,
                "bytes": writer.tell(),
                "blocks": writer.blocks_written,
            },
            "energy": {
                "path": files.energy,
                "bytes": ewriter.tell(),
                "rows": ewriter.rows_written,
            },
            "options": plan.options,
            "energy_scale": sim.state.scale,
            "effects": sorted(sim.effects),
        },
    )
    plan.stats.dumps += 1


def start_recording(plan: RunPlan):
    """Step 4: the recorder (rows kept in memory when the run keeps its trace) and the sink
    that writes rows to it and the open files; on a fresh start (no dump, no initial state) the
    row at t0. Returns (recorded node ids, recorder, sink)."""
    config, sim, writer, stats = plan.config, plan.sim, plan.writer, plan.stats
    ids = config.model.node_ids[sim.trace_nodes]
    recorder = Recorder(ids, sim.energy_columns, config.keep_trace)
    sink = Sink(writer, plan.ewriter, recorder)
    if plan.auto and plan.writes:  # the sidecar's record of the steps used, as of the last row
        sink.on_close = lambda: writer.describe(step=sim.step_record())
    if plan.meta is None and config.initial_state is None:
        snap = sim.snapshot()
        sink.write(snap.times, snap.data, snap.energy)
        note_energy(stats, snap.energy)
    stats.setup_seconds = time.perf_counter() - stats.wall_start
    stats.t_start = sim.time
    plan.steps_before = sim.steps_taken if plan.auto else 0
    return ids, recorder, sink


def step(plan: RunPlan, sink, ids):
    """Step 5: step to TMAX in chunks (x3dpd.api.loop.step_loop), a restart dump every TREST and
    at the end; ``stop`` or a signal (``handle_signals``) ends the run early. Returns the status
    ("complete", "stopped", "interrupted") and the signal handler (its ``exit_status``)."""
    config = plan.config
    with sink, Interrupts(config.handle_signals) as intr:
        stopped = step_loop(
            plan.sim,
            sink,
            config.steps,
            config.trest_steps,
            plan.stats,
            config.progress,
            lambda reason: dump(plan, reason),
            intr,
            config.stop,
            ids,
            config.stop_every,
        )
        if intr.signum:
            dump(plan, "interrupted")
            status = "interrupted"
            sink.close("interrupted")
        else:
            status = "stopped" if stopped else "complete"
            dump(plan, "stopped" if stopped else "end")
    return status, intr


def summarise(plan: RunPlan, recorder, status: str) -> RunResult:
    """Step 6: the :class:`RunResult` of the run as it stands: its trace and energy ledger (when
    kept), the summary ``x3dpd run`` prints, and the final state a chained run continues from."""
    config, sim = plan.config, plan.sim
    summary = _summary(plan, status)
    if plan.auto:
        auto_summary(summary, sim, plan.steps_before)
    final = FinalState(
        state=sim.state.copy(),
        deck_key=config.key,
        dt=config.step.dt,
        time=sim.time,
        checkpoint=sim.checkpoint() if plan.auto else None,
    )
    meta = {"status": status, "dt": config.step.dt, "itrac": config.itrac}
    return RunResult(
        trace=recorder.trace(meta),
        energy=recorder.energy(),
        summary=summary,
        final_state=final,
        model=config.model,
    )


def _summary(plan: RunPlan, status: str) -> dict:
    """The summary of the run as it stands (docs/python-api.md, ``result.summary``)."""
    config, files, sim, stats = plan.config, plan.config.files, plan.sim, plan.stats
    applied, columns = config.applied, sim.energy_columns
    wall = time.perf_counter() - stats.wall_start
    compile_s = float(sim.compile_seconds) + float(getattr(sim, "_load_seconds", 0.0))
    if getattr(sim, "compiled_here", False) and not getattr(sim, "compile_logged", False):
        record_compile_seconds(compile_s)  # the estimate of the next first run's progress line
        sim.compile_logged = True
    rate = stats.timed_steps / stats.timed_seconds if stats.timed_seconds > 0 else float("nan")
    e = stats.last_energy
    return {
        "status": status,
        "t_start": stats.t_start,
        "t_end": sim.time,
        "steps": stats.steps,
        "dt": sim.dt,
        "itrac": sim.itrac,
        "wall_s": wall,
        "step_wall_s": stats.timed_seconds,
        "compile_s": compile_s,
        "steps_per_s": rate,
        "effects": sorted(sim.effects),
        "energy_scale": float(sim.state.scale),
        "residual": relative_residual(stats, sim),
        "relative_residual": relative_residual(stats, sim),
        "residual_energy": float(e[11]) if e is not None else 0.0,
        "energy_tolerance": float(sim.energy_tolerance),
        "last_energy": dict(zip(columns, map(float, e))) if e is not None else None,
        "usrfrc": list(applied),
        "usrfrc_replaced": list(config.replaced),
        "trace_file": files.trace if files else None,
        "code_files": [spec for spec in applied if is_user_file(spec)],
        "energy_file": files.energy if files else None,
        "restart_file": files.dump if files else None,
        "dumps": stats.dumps,
        "units": list(getattr(sim.model, "units", ("in", "lbf", "s"))),
    }
