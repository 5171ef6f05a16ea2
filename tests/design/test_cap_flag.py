"""The progress line of a point stopped at its cap (x3dpd.design.steady_state.cap_flag): NOT
CONVERGED, and, when its cycles' autocorrelation time tau is known, the kept cycles an
interval of its own needs -- 50 tau (x3dpd.analysis.confidence.RUN_LENGTH), at least 20."""

from __future__ import annotations

import math

from x3dpd.analysis.confidence import MIN_KEPT, RUN_LENGTH, cycles_for_interval
from x3dpd.design.steady_state import cap_flag


def test_an_interval_needs_fifty_autocorrelation_times_and_twenty_cycles():
    assert (RUN_LENGTH, MIN_KEPT) == (50, 20)
    assert cycles_for_interval(8.8676) == 50 * 8.8676
    assert cycles_for_interval(0.2) == 20
    assert math.isnan(cycles_for_interval(math.nan))


def test_the_line_says_what_a_capped_point_would_need():
    assert cap_flag({"converged": True, "tau_cycles": 3.0}) == ""
    assert cap_flag({"converged": False, "tau_cycles": math.nan}) == "  NOT CONVERGED (cap)"
    assert cap_flag({"converged": False}) == "  NOT CONVERGED (cap)"
    assert cap_flag({"converged": False, "tau_cycles": 8.8676}) == (
        "  NOT CONVERGED (cap; tau 9 cycles: an interval needs about 443 kept cycles)"
    )
