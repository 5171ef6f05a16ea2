"""Moved to :mod:`x3dpd.testlab.trace_signals`; this name re-exports it for one release."""

from x3dpd.testlab.trace_signals import *  # noqa: F403
