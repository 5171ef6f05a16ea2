"""The design loop over the Python API: runs of a damper design and what they decide
(report Section 7.5; docs/design-guide.md, docs/design.md).

What belongs here: frequency sweeps to the steady state (``x3dpd sweep``: :mod:`~x3dpd.design.
sweep`, one point :mod:`~x3dpd.design.steady_state`, the peak search
:mod:`~x3dpd.design.auto_sweep`, replicas :mod:`~x3dpd.design.replicas`, the predicted start
:mod:`~x3dpd.design.predict`), the designs that run many configurations (``x3dpd design``:
:mod:`~x3dpd.design.explore` and its files, configurations and tables), the deck driven and
released that a design's ring-down evaluates (:mod:`~x3dpd.design.ringdown`), and the linear
baselines in closed form (:mod:`~x3dpd.design.baselines`, :mod:`~x3dpd.design.closed_form`,
:mod:`~x3dpd.design.linear_system`). Each run goes through one
:class:`~x3dpd.api.config.RunConfig`.

What does not: reading traces and measured data as a test engineer does -- FRFs, spectra, fits,
ring-down analyses of traces (x3dpd.testlab, the layer above). ``x3dpd.design.frf``, ``.fit``,
``.modal_fit`` and ``.trace_signals`` re-export their x3dpd.testlab modules for one release.
"""
