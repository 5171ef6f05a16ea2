"""The energy file: the solver's energy ledger as CSV, one row per trace output time.

``x3dpd run`` writes ``<deck stem>.energy.csv`` beside the trace. The first line is the header
(:data:`x3dpd.solver.simulation.ENERGY_COLUMNS`, and ``dissipated_rolling`` after ``residual``
in a scene with a rolling-resistance law)::

    time,kinetic_translation,kinetic_rotation,gravity_potential,spring_energy,contact_energy,
    dissipated_viscoelastic,dissipated_friction,dissipated_dampers,external_work,total_energy,
    residual

then one row per output time (t = t0 and every ITRAC steps, the trace's times). The time is
written as the trace writes it (:data:`TIME_FORMAT`, ``7.000000000e-03``: the same text as the
trace's rows of that time), every energy with 17 significant digits (:data:`VALUE_FORMAT`,
``3.7042430000000001e-03``: it reads back bit for bit). Energies are in the
deck's units (lbf·in for the report's decks). ``residual`` is the ledger's imbalance: the
change of the stored energy since t0, plus what was dissipated, minus the external work; zero
for a perfect integration (docs/running.md).

Like the trace, the file is streamed (:class:`EnergyWriter`), refuses to replace an existing
file unless asked (the old one is then kept as ``.bak``), and is truncated to a restart dump's
offset and appended when a run resumes. Read it with :func:`read_energy` or
``numpy.loadtxt(path, delimiter=",", skiprows=1)``.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from x3dpd.errors import InputError
from x3dpd.io._streamed import create_new, reopen_at

#: Format of the time column: the trace's 10 significant digits (x3dpd.io.trace.NUMBER_FORMAT).
TIME_FORMAT = "{:.9e}"
#: Format of the energy columns: 17 significant digits, enough to read a double back exactly.
VALUE_FORMAT = "{:.16e}"


class EnergyWriter:
    """Stream the energy ledger rows to a CSV file.

    Parameters
    ----------
    path : str or PathLike
    columns : sequence of str
        Header names (the ledger's columns); every row must have this many values.
    overwrite : bool
        Rename an existing file to ``path + ".bak"`` instead of refusing.
    append_at : (nbytes, nrows), optional
        Resume: the file's first ``nbytes`` bytes must hold the header and exactly ``nrows``
        rows (the values of :meth:`tell` and :attr:`rows_written` at the restart dump); the file
        is cut there and appended to.

    Raises
    ------
    InputError
        The file exists (without ``overwrite``/``append_at``), cannot be created, or does not
        match ``append_at``.
    """

    def __init__(
        self,
        path: str | os.PathLike,
        columns: Sequence[str],
        *,
        overwrite: bool = False,
        append_at: tuple[int, int] | None = None,
    ):
        self.path = os.fspath(path)
        self.columns = tuple(columns)
        self._header = (",".join(self.columns) + "\n").encode("ascii")
        self._closed = False
        if append_at is not None:
            self._open_append(*append_at)
        else:
            self._open_new(overwrite)

    def _open_new(self, overwrite: bool) -> None:
        self._f = create_new(
            self.path, overwrite=overwrite, error=InputError, what="energy file", option="--energy"
        )
        self._f.write(self._header)
        self._offset = len(self._header)
        self._rows = 0

    def _open_append(self, nbytes: int, nrows: int) -> None:
        path, nbytes, nrows = self.path, int(nbytes), int(nrows)
        if not os.path.isfile(path):
            raise InputError(
                f"cannot resume energy file {path}: it does not exist (the restart "
                f"dump expects {nrows} rows in it)"
            )

        def check(f) -> None:
            head = f.read(nbytes)
            if (
                len(head) != nbytes
                or not head.startswith(self._header)
                or not head.endswith(b"\n")
                or head.count(b"\n") != nrows + 1
            ):
                raise InputError(
                    f"cannot resume energy file {path}: its first {nbytes} bytes "
                    f"do not hold the header and {nrows} rows (is it the energy "
                    "file of this restart dump?)"
                )

        self._f = reopen_at(path, nbytes, error=InputError, what="energy file", check=check)
        self._offset = nbytes
        self._rows = nrows

    @property
    def rows_written(self) -> int:
        """Number of data rows in the file."""
        return self._rows

    def tell(self) -> int:
        """Byte offset of the end of the last row (store it in restart dumps)."""
        return self._offset

    def write_rows(self, rows: np.ndarray) -> None:
        """Append rows, an array (k, len(columns)) (or one row of len(columns))."""
        a = np.asarray(rows, dtype=np.float64)
        if a.ndim == 1:
            a = a[None]
        if a.ndim != 2 or a.shape[1] != len(self.columns):
            raise ValueError(f"energy rows must have {len(self.columns)} columns, got {a.shape}")
        if a.shape[0] == 0:
            return
        text = "".join(_row(r) for r in a.tolist()).encode("ascii")
        self._f.write(text)
        self._offset += len(text)
        self._rows += a.shape[0]

    def flush(self) -> None:
        """Flush and ``fsync`` (before a restart dump records :meth:`tell`)."""
        if not self._closed:
            self._f.flush()
            os.fsync(self._f.fileno())

    def close(self) -> None:
        if self._closed:
            return
        try:
            self.flush()
        finally:
            self._f.close()
            self._closed = True

    def __enter__(self) -> EnergyWriter:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _row(values: list[float]) -> str:
    return (
        TIME_FORMAT.format(values[0])
        + "".join("," + VALUE_FORMAT.format(v) for v in values[1:])
        + "\n"
    )


@dataclass(frozen=True)
class EnergyData:
    """An energy file in memory: ``columns`` (names) and ``data`` (k, len(columns))."""

    columns: tuple[str, ...]
    data: np.ndarray

    def column(self, name: str) -> np.ndarray:
        """One column, (k,); KeyError naming the columns when there is no such column."""
        if name not in self.columns:
            raise KeyError(f"no energy column {name!r}; the columns are {', '.join(self.columns)}")
        return self.data[:, self.columns.index(name)]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.column(name)

    @property
    def times(self) -> np.ndarray:
        return self.column("time")

    @property
    def dissipated(self) -> np.ndarray:
        """Total dissipated energy (viscoelastic + friction + dampers) per row."""
        return sum(self.column(c) for c in self.columns if c.startswith("dissipated_"))


def read_energy(path: str | os.PathLike) -> EnergyData:
    """Read an energy file; a cut last line (killed run) is dropped."""
    spath = os.fspath(path)
    try:
        with open(spath, encoding="ascii") as f:
            header = f.readline()
            lines = f.read().split("\n")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read energy file {spath}: {exc}") from None
    columns = tuple(header.strip().split(","))
    if not header.endswith("\n") or not columns or columns[0] != "time":
        raise InputError(f"{spath} is not an x3dpd energy file (its header is {header!r})")
    rows = lines[:-1]  # the text after the last newline is empty or a cut row
    try:
        data = np.array([[float(v) for v in r.split(",")] for r in rows], dtype=np.float64)
    except ValueError as exc:
        raise InputError(f"{spath}: bad energy row ({exc})") from None
    data = data.reshape(-1, len(columns))
    return EnergyData(columns, data)


def copy_backup(path: str) -> None:
    """Copy ``path`` to ``path + ".bak"`` (before a complete run's file is resumed)."""
    shutil.copy2(path, path + ".bak")


__all__ = ["EnergyData", "EnergyWriter", "read_energy"]
