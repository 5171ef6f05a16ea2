"""The NPZ mode file: a numpy ``.npz`` archive whose arrays are named as :class:`ModeSet`'s fields.

=============== ============ ========= ==================================================
array           shape        dtype     meaning
=============== ============ ========= ==================================================
mode_numbers    (M,)         integer   mode numbers (>= 1)
freq_hz         (M,)         float     natural frequencies [Hz]
node_ids        (N,)         integer   node (grid) ids
shapes          (M, N, 6)    float     x y z rx ry rz at each node; NaN = no value
damping         (M,)         float     optional: modal damping ratios
modal_mass      (M,)         float     optional: generalized masses
units           (3,)         str       optional: LENGTH FORCE TIME (x3dpd.units names)
=============== ============ ========= ==================================================

No other array may be present (a misspelt optional name would otherwise be lost silently).
"""

from __future__ import annotations

import zipfile

import numpy as np

from x3dpd._files import write_atomically
from x3dpd.errors import ModeFileError
from x3dpd.deck.modes.modeset import ModeSet, sorted_mode_set

REQUIRED = ("mode_numbers", "freq_hz", "node_ids", "shapes")
OPTIONAL = ("damping", "modal_mass", "units")


def read_modes_npz(path) -> ModeSet:
    """Read an NPZ mode file; every problem is a ModeFileError naming the file."""
    try:
        archive = np.load(path, allow_pickle=False)
    except (zipfile.BadZipFile, ValueError, EOFError, OSError) as e:
        raise ModeFileError(
            path,
            f"not a numpy .npz archive ({_short(e)}); expected one written "
            "by numpy.savez with arrays " + ", ".join(REQUIRED),
        ) from None
    if not isinstance(archive, np.lib.npyio.NpzFile):
        raise ModeFileError(
            path, "a single .npy array, not a .npz archive; expected arrays " + ", ".join(REQUIRED)
        )
    with archive:
        names = set(archive.files)
        unknown = sorted(names - set(REQUIRED) - set(OPTIONAL))
        missing = [n for n in REQUIRED if n not in names]
        if unknown:
            raise ModeFileError(
                path,
                f"unknown array(s) {', '.join(unknown)}; expected "
                f"{', '.join(REQUIRED)} and optionally "
                f"{', '.join(OPTIONAL)}",
            )
        if missing:
            raise ModeFileError(
                path,
                f"no array {', '.join(missing)}; it holds {', '.join(sorted(names)) or 'nothing'}",
            )
        try:
            arrays = {n: archive[n] for n in names}
        except (ValueError, OSError, zipfile.BadZipFile) as e:
            raise ModeFileError(path, f"an array cannot be read ({_short(e)})") from None
    for name in ("mode_numbers", "freq_hz", "node_ids", "damping", "modal_mass"):
        if name in arrays and arrays[name].ndim != 1:
            raise ModeFileError(
                path, f"array {name} has shape {arrays[name].shape}; expected one dimension"
            )
    for name, a in arrays.items():
        if name != "units" and a.dtype.kind not in "iuf":
            raise ModeFileError(path, f"array {name} holds {a.dtype} values; expected numbers")
    m, n = len(arrays["mode_numbers"]), len(arrays["node_ids"])
    if arrays["shapes"].shape != (m, n, 6):
        raise ModeFileError(
            path,
            f"array shapes has shape {arrays['shapes'].shape}; expected "
            f"({m}, {n}, 6) for {m} modes and {n} nodes",
        )
    for name in ("freq_hz", "damping", "modal_mass"):
        if name in arrays and arrays[name].shape != (m,):
            raise ModeFileError(
                path,
                f"array {name} has {arrays[name].size} values for {m} modes; expected one per mode",
            )
    units = None
    if "units" in arrays:
        u = arrays["units"]
        if u.dtype.kind != "U" or u.shape != (3,):
            raise ModeFileError(
                path, f"array units is {u.dtype} {u.shape}; expected 3 strings LENGTH FORCE TIME"
            )
        units = tuple(str(x) for x in u)
    return sorted_mode_set(
        str(path),
        arrays["mode_numbers"],
        arrays["freq_hz"],
        arrays["node_ids"],
        arrays["shapes"],
        damping=arrays.get("damping"),
        modal_mass=arrays.get("modal_mass"),
        units=units,
    )


def write_modes_npz(path, modes: ModeSet) -> None:
    """Write ``modes`` as an NPZ mode file (atomically; uncompressed ``numpy.savez``)."""
    arrays = {n: getattr(modes, n) for n in REQUIRED}
    for name in ("damping", "modal_mass"):
        if getattr(modes, name) is not None:
            arrays[name] = getattr(modes, name)
    if modes.units is not None:
        arrays["units"] = np.array(modes.units, dtype=str)
    write_atomically(path, lambda f: np.savez(f, **arrays))


def _short(e: Exception) -> str:
    text = str(e).splitlines()[0] if str(e) else type(e).__name__
    return text if len(text) < 120 else text[:117] + "..."
