"""Restart dumps: the solver state in one file, written atomically.

A dump is an *uncompressed* ``.npz`` (a ZIP archive of ``.npy`` members, readable by
``numpy.load``) holding one member per array plus a JSON member ``__x3dpd_restart__.json``::

    {"format": "x3dpd-restart/1", "x3dpd_version": "...", "arrays": [names...], "meta": {...}}

The file is written to a temporary file in the same directory, flushed, ``fsync``-ed and then
moved over ``path`` with :func:`os.replace` (the directory is ``fsync``-ed afterwards), so at
every instant ``path`` is either the previous complete dump or the new complete dump, never a
torn one. See ``docs/trace-format.md``.
"""

from __future__ import annotations

import io
import json
import os
import re
import zipfile
from collections.abc import Mapping
from typing import Any, BinaryIO

import numpy as np

from x3dpd import __version__
from x3dpd._files import write_atomically  # noqa: F401  (re-exported)
from x3dpd.errors import InputError

RESTART_FORMAT = "x3dpd-restart/1"
"""Format tag stored in every restart dump; :func:`load_restart` refuses anything else."""

META_MEMBER = "__x3dpd_restart__.json"
_NAME_RE = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.\-]*$")


def to_jsonable(obj: Any) -> Any:
    """``json.dumps`` ``default=`` hook: numpy scalars/arrays, sets and paths to plain JSON."""
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (set, frozenset)):
        return sorted(obj)
    if isinstance(obj, os.PathLike):
        return os.fspath(obj)
    raise TypeError(f"{type(obj).__name__} object is not JSON serializable")


def save_restart(
    path: str | os.PathLike, arrays: Mapping[str, np.ndarray], meta: Mapping[str, Any]
) -> None:
    """Write a restart dump atomically; the previous dump at ``path`` survives until then.

    Parameters
    ----------
    path : str or PathLike
        The dump file (conventionally ``*.npz``).
    arrays : mapping of str to ndarray
        The state. Any shape (0-d and empty included) and any non-object dtype; arrays are
        stored bit-exactly (byte order and Fortran order kept). Names: letters, digits,
        ``_ . -``, not starting with ``.`` or ``-``.
    meta : mapping
        JSON-serializable scalars and containers (time, step, trace offset, deck hash...).
        numpy scalars are converted; tuples come back as lists.

    Raises
    ------
    ValueError
        A bad array name or an object array (programming errors).
    TypeError
        ``meta`` is not JSON-serializable.
    OSError
        The file system refused; ``path`` is untouched.
    """
    names = list(arrays)
    for name in names:
        if not isinstance(name, str) or not _NAME_RE.match(name) or name == META_MEMBER:
            raise ValueError(f"restart array name {name!r} is not allowed")
    prepared = {}
    for name in names:
        arr = np.asanyarray(arrays[name])
        if arr.dtype.hasobject:
            raise ValueError(
                f"restart array {name!r} has dtype {arr.dtype}; object arrays "
                "cannot be stored (they would need pickle)"
            )
        prepared[name] = np.asarray(arr)
    header = {
        "format": RESTART_FORMAT,
        "x3dpd_version": __version__,
        "arrays": names,
        "meta": dict(meta),
    }
    header_bytes = json.dumps(header, indent=1, default=to_jsonable).encode("utf-8")

    def _write(f: BinaryIO) -> None:
        with zipfile.ZipFile(f, "w", compression=zipfile.ZIP_STORED, allowZip64=True) as zf:
            zf.writestr(META_MEMBER, header_bytes)
            for name, arr in prepared.items():
                with zf.open(name + ".npy", "w", force_zip64=True) as member:
                    np.lib.format.write_array(member, arr, allow_pickle=False)

    write_atomically(path, _write)


def load_restart(path: str | os.PathLike) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """Read a dump written by :func:`save_restart`.

    Returns
    -------
    arrays : dict of str to ndarray
        In the order they were saved.
    meta : dict
        The ``meta`` mapping given to :func:`save_restart`.

    Raises
    ------
    InputError
        The file is missing, truncated or corrupt (bad ZIP structure or CRC), or is not an
        x3dpd restart dump (no format tag, or another format/version).
    """
    spath = os.fspath(path)
    try:
        zf = zipfile.ZipFile(spath, "r")
    except FileNotFoundError:
        raise InputError(f"restart dump {spath} does not exist") from None
    except (zipfile.BadZipFile, OSError, EOFError, ValueError) as exc:
        raise InputError(
            f"{spath} is not a readable x3dpd restart dump (truncated or corrupt: {exc})"
        ) from None
    with zf:
        members = set(zf.namelist())
        if META_MEMBER not in members:
            raise InputError(
                f"{spath} is not an x3dpd restart dump (no {META_MEMBER} entry; "
                "was it written by another program?)"
            )
        try:
            header = json.loads(zf.read(META_MEMBER).decode("utf-8"))
        except (zipfile.BadZipFile, OSError, EOFError, ValueError) as exc:
            raise InputError(f"{spath}: restart dump header is corrupt ({exc})") from None
        fmt = header.get("format") if isinstance(header, dict) else None
        if fmt != RESTART_FORMAT:
            raise InputError(
                f"{spath} has format {fmt!r}; this x3dpd ({__version__}) reads "
                f"{RESTART_FORMAT!r} restart dumps only"
            )
        names = header.get("arrays")
        meta = header.get("meta")
        if not isinstance(names, list) or not isinstance(meta, dict):
            raise InputError(f"{spath}: restart dump header is corrupt (no array list or meta)")
        expected = {n + ".npy" for n in names} | {META_MEMBER}
        if members != expected:
            missing = sorted(expected - members)
            extra = sorted(members - expected)
            raise InputError(
                f"{spath}: restart dump is corrupt (missing members {missing}, "
                f"unexpected members {extra})"
            )
        arrays: dict[str, np.ndarray] = {}
        for name in names:
            try:
                raw = zf.read(name + ".npy")  # verifies the CRC-32
                arrays[name] = np.lib.format.read_array(io.BytesIO(raw), allow_pickle=False)
            except (zipfile.BadZipFile, OSError, EOFError, ValueError) as exc:
                raise InputError(
                    f"{spath}: array {name!r} of the restart dump is corrupt ({exc})"
                ) from None
    return arrays, meta
