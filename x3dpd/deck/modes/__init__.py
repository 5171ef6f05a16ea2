"""Files of modes for the MODAL deck card: a linear structure given by its natural frequencies,
damping ratios and mass-normalised shapes at nodes.

``read_modes(path)`` reads a Nastran OP2 (SOL 103 eigenvectors, with pyNastran), a universal
file (dataset 55 normal modes, with pyuff), or x3dpd's CSV and NPZ layouts, into a
:class:`ModeSet`; ``write_modes_csv`` / ``write_modes_npz`` write the last two;
``modes_from_matrices`` solves K phi = omega^2 M phi for engineers with their own matrices.
Layouts and rules: ``docs/deck-reference.md``, "Mode files (MODAL FILE records)".
"""

from __future__ import annotations

import os

from x3dpd.errors import ModeFileError
from x3dpd.deck.modes.csv_format import read_modes_csv, write_modes_csv
from x3dpd.deck.modes.matrices import modes_from_matrices
from x3dpd.deck.modes.modeset import DOF_NAMES, ModeSet, parse_dof
from x3dpd.deck.modes.npz_format import read_modes_npz, write_modes_npz
from x3dpd.deck.modes.op2_format import read_modes_op2
from x3dpd.deck.modes.uff_format import ModeFileWarning, read_modes_uff

#: fmt -> reader
READERS = {
    "op2": read_modes_op2,
    "uff": read_modes_uff,
    "csv": read_modes_csv,
    "npz": read_modes_npz,
}
#: file suffix (lower case) -> fmt
SUFFIXES = {".op2": "op2", ".uff": "uff", ".unv": "uff", ".csv": "csv", ".npz": "npz"}


def read_modes(path, fmt: str | None = None) -> ModeSet:
    """Read a file of modes.

    Parameters
    ----------
    path : str or PathLike
        The file (its name is kept as ``ModeSet.path`` and starts every error message).
    fmt : {"op2", "uff", "csv", "npz"}, optional
        The format; by default from the suffix: .op2; .uff or .unv; .csv; .npz.

    Raises :class:`~x3dpd.errors.ModeFileError` (an InputError) saying what is wrong and what
    was expected: a missing file, a file that is not what its format says, values that are not
    finite, repeated nodes or modes, no modes, a negative frequency, ...
    """
    name = os.fspath(path)
    if fmt is None:
        suffix = os.path.splitext(name)[1].lower()
        if suffix not in SUFFIXES:
            raise ModeFileError(
                name,
                f"cannot tell the format from the suffix {suffix!r}; "
                "expected .op2, .uff, .unv, .csv or .npz (or give the "
                "format)",
            )
        fmt = SUFFIXES[suffix]
    key = str(fmt).lower()
    if key not in READERS:
        raise ModeFileError(
            name, f"unknown mode-file format {fmt!r}; expected one of {', '.join(READERS)}"
        )
    if os.path.isdir(name):
        raise ModeFileError(name, "is a directory; expected a file of modes")
    if not os.path.exists(name):
        raise ModeFileError(name, "no such file")
    try:
        return READERS[key](name)
    except OSError as e:
        raise ModeFileError(name, f"cannot be read ({e.strerror or e})") from None


__all__ = [
    "DOF_NAMES",
    "READERS",
    "SUFFIXES",
    "ModeFileError",
    "ModeFileWarning",
    "ModeSet",
    "modes_from_matrices",
    "parse_dof",
    "read_modes",
    "read_modes_csv",
    "read_modes_npz",
    "read_modes_op2",
    "read_modes_uff",
    "write_modes_csv",
    "write_modes_npz",
]
