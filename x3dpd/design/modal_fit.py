"""Moved to :mod:`x3dpd.testlab.modal_fit`; this name re-exports it for one release."""

from x3dpd.testlab.modal_fit import *  # noqa: F403
