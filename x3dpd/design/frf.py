"""Moved to :mod:`x3dpd.testlab.frf`; this name re-exports it for one release."""

from x3dpd.testlab.frf import *  # noqa: F403
