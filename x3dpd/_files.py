"""Files that are never seen half-written: the one atomic-write helper of the package.

Used by the deck writer, restart dumps, trace sidecars and the kernel cache; it sits below every
layer so that any of them may use it.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from typing import BinaryIO


def write_atomically(path: str | os.PathLike, write: Callable[[BinaryIO], None], *,
                     sync_dir: bool = True) -> None:
    """Create or replace ``path`` so that it is never seen half-written.

    ``write(f)`` fills a temporary file in the same directory; the file is then flushed,
    ``fsync``-ed and renamed over ``path`` (:func:`os.replace`, atomic on POSIX and Windows).
    On any error the temporary file is removed and ``path`` is left as it was.

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
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp",
                               dir=directory)
    try:
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
