"""The output files of the test-lab commands (DIR/<name>.csv, .png ...): refused when they exist
without ``--overwrite``, each replaced at once."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path

from x3dpd.errors import InputError


def output_paths(out: str | os.PathLike, names: Sequence[str], overwrite: bool) -> list[Path]:
    """DIR/``names``, refused (InputError) when one exists and ``overwrite`` is off."""
    paths = [Path(out) / n for n in names]
    existing = [p for p in paths if p.exists()]
    if existing and not overwrite:
        raise InputError(f"{existing[0]} exists; give --overwrite to replace it, or another --out")
    return paths


def write_pair(paths: Sequence[Path], csv_text: str, plot: Callable[[str], object]) -> None:
    """DIR/<name>.csv and .png, each replaced at once (the figure drawn to a temporary name)."""
    from x3dpd._files import write_atomically

    csv, png = paths
    csv.parent.mkdir(parents=True, exist_ok=True)
    tmp = png.with_name("." + png.name + ".tmp.png")
    try:
        plot(str(tmp))
        write_atomically(csv, lambda f: f.write(csv_text.encode()))
        os.replace(tmp, png)
    finally:
        if tmp.exists():
            tmp.unlink()
