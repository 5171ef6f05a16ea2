"""Files that are never seen half-written: the one atomic-write helper of the package.

Used by the deck writer, restart dumps, trace sidecars and the kernel cache; it sits below every
layer so that any of them may use it.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from typing import BinaryIO


def write_atomically(
    path: str | os.PathLike, write: Callable[[BinaryIO], None], *, sync_dir: bool = True
) -> None:
    """Create or replace ``path`` so that it is never seen half-written.

    ``write(f)`` fills a temporary file in the same directory; the file is then flushed,
    ``fsync``-ed and renamed over ``path`` (:func:`os.replace`, atomic on POSIX and Windows).
    On any error the temporary file is removed and ``path`` is left as it was. The file gets
    the permissions of the file it replaces, or those of any new file (``0666`` less the
    umask, as ``open`` gives the trace beside it) -- not the ``0600`` of a temporary file.

    Parameters
    ----------
    path : str or PathLike
        Destination file.
    write : callable
        Called once with the open binary temporary file.
    sync_dir : bool
        Also ``fsync`` the directory after the rename so the new name survives a power cut.
    """
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(
        prefix="." + os.path.basename(path) + ".", suffix=".tmp", dir=directory
    )
    try:
        if hasattr(os, "fchmod"):
            os.fchmod(fd, _new_file_mode(path))
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    if sync_dir:
        _fsync_dir(directory)


def _new_file_mode(path: str) -> int:
    """Permission bits for ``path``: those of the existing file, else 0666 less the umask."""
    try:
        return os.stat(path).st_mode & 0o7777
    except OSError:
        mask = os.umask(0o022)
        os.umask(mask)
        return 0o666 & ~mask


def _fsync_dir(directory: str) -> None:
    try:
        dfd = os.open(directory, os.O_RDONLY)
    except OSError:  # pragma: no cover - platforms without directory handles (Windows)
        return
    try:
        os.fsync(dfd)
    except OSError:  # pragma: no cover
        pass
    finally:
        os.close(dfd)
