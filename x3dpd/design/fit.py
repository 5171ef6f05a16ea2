"""Moved to :mod:`x3dpd.testlab.fit`; this name re-exports it for one release."""

from x3dpd.testlab.fit import *  # noqa: F403
