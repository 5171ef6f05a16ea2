"""Output files of the post-processing commands: never replace one without ``--overwrite``."""

from __future__ import annotations

import os

from x3dpd.errors import InputError


def refuse_existing(paths, overwrite: bool) -> None:
    """InputError when an output exists (and ``overwrite`` is off) or its folder does not."""
    for p in paths:
        folder = os.path.dirname(os.path.abspath(p))
        if not os.path.isdir(folder):
            raise InputError(f"{p}: folder {folder} does not exist")
        if os.path.exists(p) and not overwrite:
            raise InputError(f"{p} exists; pass --overwrite to replace it")
