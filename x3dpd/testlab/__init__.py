"""The test lab: what a test engineer does with a run or a measurement, over the Python API and
the design loop's baselines (docs/testing-like-a-test-engineer.md).

What belongs here: the commands that read traces and measured data and estimate what a
laboratory would -- ``x3dpd frf`` and ``x3dpd spectrum`` (:mod:`~x3dpd.testlab.frf`, the drive
and responses of a trace: :mod:`~x3dpd.testlab.trace_signals`), the single-mode and multi-mode
fits of measured FRFs (``x3dpd fit``: :mod:`~x3dpd.testlab.fit`, :mod:`~x3dpd.testlab.modal_fit`),
the ring-down's damping against amplitude (``x3dpd ringdown``: :mod:`~x3dpd.testlab.ringdown`),
and the closed-form baselines they overlay (:mod:`~x3dpd.testlab.frf_baselines`). The
estimators themselves are x3dpd.analysis's and the measured-data readers x3dpd.io's, reached
through x3dpd.api.

What does not: running decks to a steady state, sweeps, designs, the predicted start
(x3dpd.design, which this package may use: a ring-down of a deck is run by the design loop's
x3dpd.design.ringdown). Layers: cli -> testlab -> design -> api (tests/meta/test_layering.py).
"""
