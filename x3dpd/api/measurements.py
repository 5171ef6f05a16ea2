"""Signals, FRFs, ring-downs and steady states, for the tools above the API (re-exports;
docs/frf.md, docs/design-guide.md):

* :data:`QUANTITY_ORDER`, :func:`estimate_frf`, :func:`amplitude_spectrum`,
  :func:`power_spectrum`, :func:`difference_gain`, :func:`central_difference`,
  :func:`check_window` -- spectra and FRFs of a trace's signals (x3dpd.analysis.frf);
* :func:`fit_sdof` -> :class:`SdofFit` -- an SDOF fitted to an FRF (x3dpd.analysis.sdof_fit);
* :func:`lscf_poles` -> :class:`PoleOrders`, :func:`pole_groups`, :func:`select_poles`,
  :func:`max_order` -- the poles of a set of FRFs (LSCF and stabilisation,
  x3dpd.analysis.lscf); :func:`refine_modes` -> :class:`ModalFit` -- their modal constants,
  residual terms and refined poles with standard errors (LSFD, x3dpd.analysis.lsfd);
  :func:`read_frf_set` -- a set of measured FRFs with their points (x3dpd.io.frf_set);
  :class:`ModeSet`, :func:`write_modes_csv` -- the mode file a multi-mode fit writes for a
  MODAL card (x3dpd.deck.modes);
* :func:`damping_vs_amplitude` -> :class:`Ringdown`, :func:`cycles_needed`, :func:`rest_offset`,
  :data:`G_IN_S2` --
  % zeta versus amplitude of a ring-down (report Section 4.1; x3dpd.analysis.ringdown);
* :class:`SteadyStateMonitor` -- whether a driven response has settled
  (x3dpd.analysis.steady_state); :func:`t_quantile`, :func:`cycles_for_interval` -- Student's
  t and the run an interval needs (x3dpd.analysis.confidence);
* :func:`read_measured_frf` -> :class:`MeasuredFrf`, :func:`read_measured_history` -- a test's
  measured FRF or time history (x3dpd.io.measured);
* the drive laws' values on a time grid: :func:`force_table`, :func:`force_values`,
  :func:`law_count`, :func:`split_specs` (USRFRC, x3dpd.physics.usrfrc), the random law's
  :data:`RANDOM_DEFAULT_PERIOD` (x3dpd.physics.random_signal) and
  :func:`motion_table`, :func:`motion_rows`, :func:`motion_history` (prescribed motion,
  x3dpd.physics.motion).
"""

from __future__ import annotations

from x3dpd.analysis.frf import (
    MIN_SEGMENT,
    QUANTITY_ORDER,
    amplitude_spectrum,
    central_difference,
    check_window,
    difference_gain,
    estimate_frf,
    power_spectrum,
)
from x3dpd.analysis.ringdown import (
    G_IN_S2,
    Ringdown,
    cycles_needed,
    damping_vs_amplitude,
    rest_offset,
)
from x3dpd.analysis.lscf import PoleOrders, lscf_poles, max_order, pole_groups, select_poles
from x3dpd.analysis.lsfd import ModalFit, refine_modes
from x3dpd.analysis.sdof_fit import SdofFit, fit_sdof
from x3dpd.analysis.confidence import cycles_for_interval, t_quantile
from x3dpd.analysis.peak_search import Peak, PeakSearch
from x3dpd.analysis.steady_state import SteadyStateMonitor
from x3dpd.deck.modes import DOF_NAMES, ModeSet, write_modes_csv
from x3dpd.io.frf_set import read_frf_set
from x3dpd.io.measured import MeasuredFrf, read_measured_frf, read_measured_history
from x3dpd.physics.motion import motion_history, motion_rows, motion_table
from x3dpd.physics.random_signal import DEFAULT_PERIOD as RANDOM_DEFAULT_PERIOD
from x3dpd.physics.usrfrc import force_table, force_values, law_count, split_specs

__all__ = [
    "DOF_NAMES",
    "G_IN_S2",
    "MIN_SEGMENT",
    "QUANTITY_ORDER",
    "RANDOM_DEFAULT_PERIOD",
    "MeasuredFrf",
    "ModalFit",
    "ModeSet",
    "PoleOrders",
    "Ringdown",
    "SdofFit",
    "Peak",
    "PeakSearch",
    "SteadyStateMonitor",
    "t_quantile",
    "cycles_for_interval",
    "amplitude_spectrum",
    "central_difference",
    "check_window",
    "cycles_needed",
    "damping_vs_amplitude",
    "difference_gain",
    "estimate_frf",
    "fit_sdof",
    "force_table",
    "force_values",
    "law_count",
    "lscf_poles",
    "max_order",
    "motion_history",
    "motion_rows",
    "motion_table",
    "pole_groups",
    "power_spectrum",
    "read_measured_frf",
    "read_frf_set",
    "read_measured_history",
    "refine_modes",
    "rest_offset",
    "select_poles",
    "split_specs",
    "write_modes_csv",
]
