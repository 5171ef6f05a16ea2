"""Figures, movies and exports, for the tools above the API (re-exports; docs/visualize.md,
docs/design.md). Each figure module loads matplotlib only when it draws.

* :func:`plot_run` -- ``x3dpd run --plot``'s figures of a trace and its energy ledger;
* :func:`collect`, :func:`plot_trace`, :data:`QUANTITIES`, :data:`DOF_NAMES` -- ``x3dpd plot``;
* :func:`write_movie`, :data:`VIEWS` -- ``x3dpd movie``;
* :func:`write_vtk_series`, :func:`write_lammps_dump` -- ``x3dpd export``;
* :class:`Scene`, :func:`scene_from_model` -- the geometry these draw;
* :func:`plot_frf`, :func:`plot_spectrum`, :func:`plot_fit`, :func:`plot_modal_fit`,
  :class:`Curve` -- ``x3dpd frf`` and ``x3dpd fit``;
* :func:`plot_sweep`, :func:`plot_responses`, :func:`plot_configurations`,
  :func:`plot_ringdown`, :func:`attenuations` (a sweep's peak attenuation against its
  baselines) -- ``x3dpd sweep`` and ``x3dpd ringdown``;
* :func:`plot_attenuation_vs_mass`, :func:`plot_damping_families` -- ``x3dpd design``'s charts.
"""

from __future__ import annotations

from x3dpd.analysis.design_charts import plot_attenuation_vs_mass, plot_damping_families
from x3dpd.analysis.design_plots import (
    attenuations,
    plot_configurations,
    plot_responses,
    plot_ringdown,
    plot_sweep,
)
from x3dpd.analysis.export import write_lammps_dump, write_vtk_series
from x3dpd.analysis.frf_plots import Curve, plot_fit, plot_frf, plot_modal_fit, plot_spectrum
from x3dpd.analysis.movie import VIEWS, write_movie
from x3dpd.analysis.plots import plot_run
from x3dpd.analysis.scene import Scene, scene_from_model
from x3dpd.analysis.trace_plot import DOF_NAMES, QUANTITIES, collect, plot_trace

__all__ = [
    "DOF_NAMES",
    "QUANTITIES",
    "VIEWS",
    "Curve",
    "Scene",
    "attenuations",
    "collect",
    "plot_attenuation_vs_mass",
    "plot_configurations",
    "plot_damping_families",
    "plot_fit",
    "plot_frf",
    "plot_modal_fit",
    "plot_responses",
    "plot_ringdown",
    "plot_run",
    "plot_spectrum",
    "plot_sweep",
    "plot_trace",
    "scene_from_model",
    "write_lammps_dump",
    "write_movie",
    "write_vtk_series",
]
