"""Nastran SOL 103 modes from an OP2 file, read with pyNastran (an optional dependency).

What is read: the real eigenvector table (OUGV1, table code 7) -- one shape per mode, six
components per GRID in the grid's displacement (output) coordinate system -- and, when present,
the real eigenvalue summary LAMA for each mode's frequency f = CYCLES [Hz] and GENERALIZED MASS.
Without LAMA the frequency comes from the eigenvector table's eigenvalue lambda:
f = sqrt(|lambda|) / (2 pi), as Nastran prints CYCLES. Scalar and extra points (SPOINT, EPOINT)
have their one value as component 1 and NaN elsewhere. OP2 values are 32-bit floats (about 7
significant digits). An OP2 declares no units (``units`` is None); no damping either.

pyNastran 1.4.1 (the latest release) declares numpy<2 but its OP2 reader works on numpy 2 except
that three of its modules take ``numpy.in1d`` (removed in numpy 2.4) at import: the import
below lends numpy an ``in1d`` for the duration of the import and takes it back. Reading also
touches ``numpy.chararray`` (deprecated in numpy 2.4, so a DeprecationWarning, silenced here); a
numpy that removes it will need a shim like ``in1d``'s or a newer pyNastran.
"""

from __future__ import annotations

import contextlib
import io
import struct
import warnings

import numpy as np

from x3dpd.errors import ModeFileError
from x3dpd.deck.modes.modeset import ModeSet, sorted_mode_set

#: How to get the optional OP2 reader (say it in errors).
INSTALL_HINT = (
    'pip install -e ".[nastran]" && pip install --no-deps pyNastran==1.4.1 in x3dpd\'s '
    "folder (the extra installs cpylog, pyNastran's logger; pyNastran's numpy<2 pin is not "
    "needed for reading OP2 files)"
)

#: pyNastran grid types with one value (scalar, extra and modal points).
_SCALAR_POINTS = (2, 3, 4)


@contextlib.contextmanager
def numpy_in1d_for_import():
    """Lend numpy the ``in1d`` that numpy 2.4 removed (pyNastran 1.4.1 takes it at import),
    then take it back; does nothing on a numpy that still has it."""
    lent = not hasattr(np, "in1d")
    if lent:
        np.in1d = lambda ar1, ar2, **kw: np.isin(np.ravel(ar1), ar2, **kw)
    try:
        yield
    finally:
        if lent:
            del np.in1d


def pynastran_op2():
    """pyNastran's OP2 class (ImportError when pyNastran or cpylog is missing)."""
    with numpy_in1d_for_import():
        from pyNastran.op2.op2 import OP2
    return OP2


def read_modes_op2(path) -> ModeSet:
    """Read the real modes of an OP2 file; every problem is a ModeFileError naming the file."""
    _check_looks_like_op2(path)
    try:
        OP2 = pynastran_op2()
        from cpylog import SimpleLogger
    except ImportError as e:
        raise ModeFileError(
            path, f"reading OP2 files needs pyNastran ({e}); install it with: {INSTALL_HINT}"
        ) from None
    model = OP2(log=SimpleLogger(level="critical"), debug=None)
    model.set_results(["eigenvectors", "eigenvalues"])
    try:
        # pyNastran 1.4.1 touches np.chararray (deprecated in numpy 2.4) and prints its own
        # diagnostics of a bad table: neither is the user's concern, the error below says it
        with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
            warnings.simplefilter("ignore")
            model.read_op2(str(path), build_dataframe=False, skip_undefined_matrices=True)
    except struct.error:
        raise ModeFileError(
            path,
            "the file ends inside an OP2 record (cut short?); expected a whole Nastran OP2 file",
        ) from None
    except Exception as e:  # noqa: BLE001 -- pyNastran raises AssertionError, ValueError, ...
        raise ModeFileError(
            path,
            f"pyNastran cannot read it as an OP2 file ({_short(e)}); "
            "expected a Nastran OP2 written with PARAM,POST,-1",
        ) from None
    tables = dict(model.eigenvectors)
    if not tables:
        raise ModeFileError(
            path,
            "no real eigenvectors (SOL 103 OUGV1, table code 7) in the "
            f"file; it holds {_result_names(model)}. Expected a SOL 103 "
            "run with DISPLACEMENT(PLOT)=ALL",
        )
    if len(tables) > 1:
        raise ModeFileError(
            path,
            f"eigenvectors of {len(tables)} subcases ({', '.join(map(str, tables))}); expected one",
        )
    (vectors,) = tables.values()
    if getattr(vectors, "is_complex", False) or np.iscomplexobj(vectors.data):
        raise ModeFileError(path, "complex eigenvectors; expected real normal modes (SOL 103)")
    modes = np.asarray(vectors.modes, dtype=np.int64)
    shapes = np.array(vectors.data, dtype=np.float64)
    node_ids = np.asarray(vectors.node_gridtype[:, 0], dtype=np.int64)
    scalar = np.isin(vectors.node_gridtype[:, 1], _SCALAR_POINTS)
    shapes[:, scalar, 1:] = np.nan
    if np.isnan(shapes[:, :, 0]).any() or np.isnan(shapes[:, ~scalar]).any():
        raise ModeFileError(path, "NaN in the eigenvectors; expected finite numbers")
    freq, modal_mass = _frequencies(path, model, vectors, modes)
    return sorted_mode_set(str(path), modes, freq, node_ids, shapes, modal_mass=modal_mass)


def _frequencies(path, model, vectors, modes):
    """(f [Hz], generalized mass or None) per mode: LAMA where it has every mode, else the
    eigenvector table's eigenvalues."""
    for lama in model.eigenvalues.values():
        lama_modes = np.asarray(lama.mode, dtype=np.int64)
        if set(modes.tolist()) <= set(lama_modes.tolist()):
            row = {m: i for i, m in enumerate(lama_modes.tolist())}
            take = np.array([row[m] for m in modes.tolist()])
            freq = np.asarray(lama.cycles, dtype=np.float64)[take]
            mass = np.asarray(lama.generalized_mass, dtype=np.float64)[take]
            return freq, mass
    eigns = np.asarray(vectors.eigns, dtype=np.float64)
    if eigns.shape != modes.shape:
        raise ModeFileError(
            path,
            "the eigenvector table gives no eigenvalue per mode and there "
            "is no LAMA table; expected one of them",
        )
    return np.sqrt(np.abs(eigns)) / (2.0 * np.pi), None


def _check_looks_like_op2(path) -> None:
    """A Fortran-record OP2 starts with the 4-byte record length 4 (either byte order), or with
    8 (64-bit OP2). Anything else is not an OP2, whatever its name."""
    with open(path, "rb") as f:
        head = f.read(4)
    if len(head) < 4:
        raise ModeFileError(path, f"{len(head)} bytes long; expected a Nastran OP2 file")
    if head not in (b"\x04\0\0\0", b"\0\0\0\x04", b"\x08\0\0\0", b"\0\0\0\x08"):
        text = head.decode("ascii", errors="replace")
        raise ModeFileError(
            path,
            f"does not start as an OP2 file does (it starts {text!r}); "
            "expected a binary Nastran OP2 (PARAM,POST,-1)",
        )


def _result_names(model) -> str:
    names = [
        n.decode("latin-1") if isinstance(n, bytes) else str(n)
        for n in getattr(model, "table_names", [])
    ]
    return "the tables " + ", ".join(names) if names else "no tables"


def _short(e: Exception) -> str:
    text = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
    return text if len(text) < 160 else text[:157] + "..."
