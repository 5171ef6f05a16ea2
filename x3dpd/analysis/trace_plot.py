"""Time-history plots of a trace (``x3dpd plot``).

Panels, top to bottom: each requested quantity of the chosen node DOFs (displacement from the
first output, velocity, or acceleration -- the central difference of the traced velocity,
``numpy.gradient``, second order on a uniform output grid); the energy ledger by mechanism from
the run's energy file; and the particles' kinetic energy computed from the trace,
``sum 1/2 m |v|^2 + 1/2 (2/5 m R^2) |omega|^2`` (solid spheres). Axis labels use the deck's units
(:func:`x3dpd.units.labels_for`). The trace is streamed (:func:`collect`), keeping only the
chosen columns.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from x3dpd.analysis.plots import save_figure
from x3dpd.analysis.scene import Scene

DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
QUANTITIES = ("displacement", "velocity", "acceleration")


@dataclass(frozen=True)
class Histories:
    """Per output time: ``times`` (k,), ``pos`` and ``vel`` (k, S) of the chosen (row, dof)
    pairs (``pos`` is NaN for rotational DOFs: the trace keeps no angles), particle kinetic
    energy ``ke_particles`` (k,)."""

    times: np.ndarray
    pos: np.ndarray
    vel: np.ndarray
    ke_particles: np.ndarray


def collect(
    blocks: Iterable[tuple[float, np.ndarray]], scene: Scene, picks: list[tuple[int, int]]
) -> Histories:
    """Stream ``blocks`` and keep the chosen ``(trace row, dof index 0..5)`` columns."""
    times, pos, vel, ke = [], [], [], []
    m = scene.mass
    inertia = scene.particle_inertia
    for t, data in blocks:
        times.append(t)
        pos.append([data[r, d] if d < 3 else np.nan for r, d in picks])
        vel.append([data[r, 3 + d] for r, d in picks])
        p = data[scene.particle_rows]
        ke.append(
            float(
                np.sum(0.5 * m * np.sum(p[:, 3:6] ** 2, axis=1))
                + np.sum(0.5 * inertia * np.sum(p[:, 6:9] ** 2, axis=1))
            )
        )
    k = len(times)
    return Histories(
        np.asarray(times),
        np.asarray(pos, float).reshape(k, len(picks)),
        np.asarray(vel, float).reshape(k, len(picks)),
        np.asarray(ke),
    )


def acceleration(times: np.ndarray, vel: np.ndarray) -> np.ndarray:
    """d vel / dt per column by central differences (one-sided at the ends)."""
    if times.shape[0] < 2:
        return np.full_like(vel, np.nan)
    return np.gradient(vel, times, axis=0)


def plot_trace(
    png: str | os.PathLike,
    hist: Histories,
    labels: list[str],
    quantities: list[str],
    units: dict,
    energy=None,
    title: str = "",
) -> str:
    """Write the PNG; ``labels`` name the picks ("node 9 x"), ``energy`` is an
    ``x3dpd.io.energy.EnergyData`` (or None). Returns the path."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    n_panels = (
        len(quantities)
        + (1 if energy is not None else 0)
        + (1 if hist.ke_particles.size and np.any(hist.ke_particles) else 0)
    )
    fig, axes = plt.subplots(
        max(n_panels, 1), 1, figsize=(8, 2.6 * max(n_panels, 1)), sharex=True, squeeze=False
    )
    axes = list(axes[:, 0])
    L, T = units.get("length", "in"), units.get("time", "s")
    for q in quantities:
        ax = axes.pop(0)
        for j, lab in enumerate(labels):
            rot = lab.split()[-1].startswith("r")
            if q == "displacement":
                y = hist.pos[:, j] - hist.pos[0, j] if hist.pos.shape[0] else hist.pos[:, j]
                unit = "rad" if rot else L
            elif q == "velocity":
                y = hist.vel[:, j]
                unit = f"rad/{T}" if rot else f"{L}/{T}"
            else:
                y = acceleration(hist.times, hist.vel[:, [j]])[:, 0]
                unit = f"rad/{T}^2" if rot else f"{L}/{T}^2"
            ax.plot(hist.times, y, lw=0.8, label=f"{lab} [{unit}]")
        ax.set_ylabel(q)
        ax.legend(fontsize=7, loc="upper left")
        ax.grid(True, lw=0.3)
    E = units.get("energy", "lbf in")
    if energy is not None:
        ax = axes.pop(0)
        for col in (
            "dissipated_viscoelastic",
            "dissipated_friction",
            "dissipated_dampers",
            "external_work",
            "kinetic_translation",
            "spring_energy",
        ):
            if col in energy.columns:
                ax.plot(energy.times, energy.column(col), lw=0.8, label=col.replace("_", " "))
        ax.plot(energy.times, energy.dissipated, lw=1.2, color="k", label="dissipated (total)")
        ax.set_ylabel(f"energy [{E}]")
        ax.legend(fontsize=7, loc="upper left", ncol=2)
        ax.grid(True, lw=0.3)
    if axes:
        ax = axes.pop(0)
        ax.plot(hist.times, hist.ke_particles, lw=0.8, color="C5")
        ax.set_ylabel(f"particle KE [{E}]")
        ax.grid(True, lw=0.3)
    fig.axes[-1].set_xlabel(f"time [{T}]")
    return save_figure(fig, png, title)
