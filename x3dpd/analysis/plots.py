"""Quick-look plots of a run (``x3dpd run --plot PNG``).

matplotlib is imported lazily, with the non-interactive Agg backend, so that importing x3dpd
and running without ``--plot`` never loads it.
"""

from __future__ import annotations

import os

import numpy as np


def first_node_history(trace_path: str | os.PathLike, n_rows: int) -> tuple[np.ndarray, np.ndarray]:
    """Times and x coordinates of the first traced node, reading one line in ``n_rows``.

    Streams the file (a 15 s run of a 512-particle deck is over a gigabyte) and stops at a cut
    last line.
    """
    times, xs = [], []
    with open(trace_path, "rb") as f:
        for k, line in enumerate(f):
            if k % n_rows:
                continue
            if not line.endswith(b"\n"):
                break
            t, x = line.split(b";", 2)[:2]
            times.append(float(t))
            xs.append(float(x))
    return np.asarray(times), np.asarray(xs)


def _sidecar_units(trace_path) -> dict:
    """The units the trace's sidecar records (the deck's UNITS), {} without one."""
    import json

    try:
        with open(os.fspath(trace_path) + ".json", encoding="utf-8") as f:
            units = json.load(f).get("units")
    except (OSError, ValueError, AttributeError):
        return {}
    return units if isinstance(units, dict) else {}


def plot_run(
    png: str | os.PathLike, trace_path: str | os.PathLike, node_ids, energy=None, title: str = ""
) -> str:
    """Write a PNG: the first TRACE node's x displacement and the energy dissipated vs time.

    Parameters
    ----------
    png : output file.
    trace_path : the run's trace; ``node_ids`` its traced node ids (row order).
    energy : the run's energy ledger as read by ``x3dpd.io.energy.read_energy`` (anything with
        ``times``, ``columns``, ``column(name)`` and ``dissipated``); the lower panel is left out
        without it.
    title : figure title (the deck's title, for instance).

    Returns the PNG's path.
    """
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    node_ids = list(node_ids)
    units = _sidecar_units(trace_path)
    t, x = first_node_history(trace_path, len(node_ids))
    panels = 2 if energy is not None else 1
    fig, axes = plt.subplots(panels, 1, figsize=(8, 3.2 * panels), sharex=True, squeeze=False)
    ax = axes[0, 0]
    u = x - x[0] if x.size else x
    ax.plot(t, u, lw=0.8, color="C0")
    ax.set_ylabel(f"node {node_ids[0]} x displacement [{units.get('length', 'in')}]")
    ax.grid(True, lw=0.3)
    if energy is not None:
        ax2 = axes[1, 0]
        et = energy.times
        for col, color in (
            ("dissipated_viscoelastic", "C1"),
            ("dissipated_friction", "C2"),
            ("dissipated_dampers", "C3"),
        ):
            if col in energy.columns:
                ax2.plot(
                    et,
                    energy.column(col),
                    lw=0.8,
                    color=color,
                    label=col.replace("dissipated_", ""),
                )
        ax2.plot(et, energy.dissipated, lw=1.2, color="k", label="total dissipated")
        if "external_work" in energy.columns:
            ax2.plot(
                et,
                energy.column("external_work"),
                lw=0.8,
                ls="--",
                color="C4",
                label="external work",
            )
        ax2.set_ylabel(f"energy [{units.get('energy', 'lbf in')}]")
        ax2.legend(fontsize=7, loc="upper left")
        ax2.grid(True, lw=0.3)
    axes[-1, 0].set_xlabel("time [s]")
    return save_figure(fig, png, title)


def save_figure(fig, png: str | os.PathLike, title: str | None = None) -> str:
    """Title (the first line of ``title``), tight layout, write ``png`` at 110 dpi, close."""
    import matplotlib.pyplot as plt

    if title:
        fig.suptitle(title.splitlines()[0], fontsize=9)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return os.fspath(png)


__all__ = ["first_node_history", "plot_run", "save_figure"]
