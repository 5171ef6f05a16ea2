"""What ``x3dpd check`` reports, for the tools above the API (re-exports; docs/running.md):

* :func:`check_model` -> :class:`CheckReport` (``errors``, ``warnings``, ``time_step``,
  ``exit_status``) of a built model; :func:`x3dpd.api.check` does the same from a deck;
* :data:`STEPS_PER_CONTACT` -- steps a Hertz contact must span (report section 2.4);
* :func:`peak_force_error` -- the relative error of the peak contact force at a time step.
"""

from __future__ import annotations

from x3dpd.model.check import CheckReport, check_model
from x3dpd.model.timestep import STEPS_PER_CONTACT, peak_force_error

__all__ = ["STEPS_PER_CONTACT", "CheckReport", "check_model", "peak_force_error"]
