"""Streamed output files (trace, energy): created without clobbering, resumed by truncation.

A run writes its trace and energy files as it goes. Two rules hold for both:

* a new file never destroys an existing one: it is refused, or with ``--overwrite`` the old file
  (and its companions, such as a trace's JSON sidecar) is first moved to ``*.bak``;
* a run resumed from a restart dump reopens the file, checks that its first ``nbytes`` are what
  the dump expects, and cuts everything after them (rows written after the dump was taken).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from typing import BinaryIO


def create_new(
    path: str,
    *,
    overwrite: bool,
    error: type[Exception],
    what: str,
    option: str,
    companions: Iterable[tuple[str, str]] = (),
) -> BinaryIO:
    """Create ``path`` for binary writing.

    An existing ``path`` raises ``error`` unless ``overwrite``; then it is moved to
    ``path + ".bak"`` and each companion ``(src, dst)`` is moved along (a stale ``dst`` whose
    ``src`` is gone is deleted: it would describe the wrong file). ``what`` names the file in
    messages ("trace file"), ``option`` the command-line option that chooses its path.
    """
    if os.path.lexists(path):
        if not overwrite:
            raise error(
                f"{what} {path} already exists; pass --overwrite to replace it (the old "
                f"one is kept as {path}.bak) or choose another {option} path"
            )
        if os.path.isdir(path):
            raise error(f"{what} path {path} is a directory")
        try:
            os.replace(path, path + ".bak")
            for src, dst in companions:
                if os.path.exists(src):
                    os.replace(src, dst)
                elif os.path.exists(dst):
                    os.unlink(dst)
        except OSError as exc:
            raise error(f"cannot move {path} to {path}.bak: {exc}") from None
    try:
        return open(path, "xb")  # noqa: SIM115 - the caller closes it
    except OSError as exc:
        raise error(f"cannot create {what} {path}: {exc.strerror or exc}") from None


def reopen_at(
    path: str, nbytes: int, *, error: type[Exception], what: str, check: Callable[[BinaryIO], None]
) -> BinaryIO:
    """Open ``path`` to continue writing at byte ``nbytes``.

    ``check(f)`` validates the file's first ``nbytes`` (raising ``error`` if they are not what
    the restart dump expects); then the file is cut at ``nbytes`` and positioned there. The file
    is closed again if anything fails.
    """
    try:
        f = open(path, "r+b")  # noqa: SIM115 - the caller closes it
    except OSError as exc:
        raise error(f"cannot open {what} {path} to resume: {exc.strerror or exc}") from None
    try:
        check(f)
        f.truncate(nbytes)
        f.seek(nbytes)
    except BaseException:
        f.close()
        raise
    return f
