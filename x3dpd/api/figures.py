"""Figures, movies and exports of a run, for the tools above the API (re-exports;
docs/visualize.md):

* :func:`plot_run` -- ``x3dpd run --plot``'s figures of a trace and its energy ledger;
* :func:`collect`, :func:`plot_trace`, :data:`QUANTITIES`, :data:`DOF_NAMES` -- ``x3dpd plot``;
* :func:`write_movie`, :data:`VIEWS` -- ``x3dpd movie``;
* :func:`write_vtk_series`, :func:`write_lammps_dump` -- ``x3dpd export``;
* :class:`Scene`, :func:`scene_from_model` -- the geometry these draw.
"""

from __future__ import annotations

from x3dpd.analysis.export import write_lammps_dump, write_vtk_series
from x3dpd.analysis.movie import VIEWS, write_movie
from x3dpd.analysis.plots import plot_run
from x3dpd.analysis.scene import Scene, scene_from_model
from x3dpd.analysis.trace_plot import DOF_NAMES, QUANTITIES, collect, plot_trace

__all__ = ["DOF_NAMES", "QUANTITIES", "VIEWS", "Scene", "collect", "plot_run", "plot_trace",
           "scene_from_model", "write_lammps_dump", "write_movie", "write_vtk_series"]
