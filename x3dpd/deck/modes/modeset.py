"""A linear structure given by its modes: :class:`ModeSet`, what every mode-file reader returns.

A mode r of an undamped linear structure M q'' + K q = 0 is a pair (omega_r, phi_r) with
K phi_r = omega_r^2 M phi_r; the natural frequency is f_r = omega_r / (2 pi) [Hz]. A shape is
*mass-normalised* when phi_r^T M phi_r = 1 (generalized mass m_r = 1), so its values have units
1/sqrt(mass) [1/sqrt(F T^2/L)]; a file that gives another generalized mass m_r has shapes
scaled by sqrt(m_r) and :meth:`ModeSet.mass_normalised` divides that out.

Values are stored per node (grid) and component, the components in the order x, y, z
(translations, [L]) then rx, ry, rz (rotations, [rad]); NaN where the file gives no value.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from x3dpd.errors import ModeFileError
from x3dpd.units import parse_units

#: Component names in shape order (DOF codes 1-6).
DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
_DOF_BY_NAME = {
    **{n: i + 1 for i, n in enumerate(DOF_NAMES)},
    **{str(i + 1): i + 1 for i in range(6)},
    "tx": 1,
    "ty": 2,
    "tz": 3,
}


def parse_dof(text) -> int:
    """DOF code 1-6 from ``1``-``6`` or a name ``x y z rx ry rz`` (also ``tx ty tz``;
    case-insensitive). Raises ValueError saying what was expected."""
    key = str(text).strip().lower()
    if key.endswith(".0") and key[:-2].isdigit():  # spreadsheets write 3 as 3.0
        key = key[:-2]
    if key not in _DOF_BY_NAME:
        raise ValueError(
            f"DOF {str(text).strip()!r}: expected 1-6 or one of {', '.join(DOF_NAMES)}"
        )
    return _DOF_BY_NAME[key]


@dataclass(frozen=True, eq=False)
class ModeSet:
    """Modes read from a file (or built by :func:`modes_from_matrices`).

    Attributes
    ----------
    path : str
        The file as given (used in error messages).
    mode_numbers : (M,) int64
        The file's mode numbers (1-based as the file has them), increasing.
    freq_hz : (M,) float64
        Natural frequencies f_r [Hz], finite and >= 0.
    node_ids : (N,) int64
        The file's node (grid) ids, increasing.
    shapes : (M, N, 6) float64
        phi_r at each node: translations x, y, z then rotations rx, ry, rz (mass-normalised:
        [L / sqrt(M)] and [rad / sqrt(M)], M the unit of mass); NaN where the file gives no
        value.
    damping : (M,) float64 or None
        Modal viscous damping ratios zeta_r in [0, 1) when the file gives them.
    modal_mass : (M,) float64 or None
        Generalized masses m_r = phi_r^T M phi_r > 0 when the file gives them.
    units : (length, force, time) or None
        The unit system the file declares, in :mod:`x3dpd.units` names.

    Construction checks all of this and raises :class:`~x3dpd.errors.ModeFileError` naming
    ``path`` when something does not hold.
    """

    path: str
    mode_numbers: np.ndarray
    freq_hz: np.ndarray
    node_ids: np.ndarray
    shapes: np.ndarray
    damping: np.ndarray | None = None
    modal_mass: np.ndarray | None = None
    units: tuple[str, str, str] | None = None

    def __post_init__(self):
        put = object.__setattr__
        put(self, "path", str(self.path))
        put(self, "mode_numbers", _ints(self, self.mode_numbers, "mode numbers"))
        put(self, "node_ids", _ints(self, self.node_ids, "node ids"))
        put(self, "freq_hz", np.array(self.freq_hz, dtype=np.float64).reshape(-1))
        put(self, "shapes", np.array(self.shapes, dtype=np.float64))
        for name in ("damping", "modal_mass"):
            value = getattr(self, name)
            if value is not None:
                put(self, name, np.array(value, dtype=np.float64).reshape(-1))
        if self.units is not None:
            try:
                put(self, "units", parse_units(self.units))
            except ValueError as e:
                raise ModeFileError(self.path, f"units: {e}") from None
        _check(self)
        for name in ("mode_numbers", "freq_hz", "node_ids", "shapes", "damping", "modal_mass"):
            value = getattr(self, name)
            if value is not None:
                value.flags.writeable = False

    @property
    def n_modes(self) -> int:
        return len(self.mode_numbers)

    @property
    def n_nodes(self) -> int:
        return len(self.node_ids)

    def select(self, modes=None, band=None) -> ModeSet:
        """The modes whose numbers are in ``modes`` (an int or an iterable of ints) and whose
        frequency lies in ``band`` = (lo, hi) [Hz], both ends included; None keeps all.
        Raises ModeFileError for a mode number the file does not have, a band with lo > hi, or a
        selection that keeps no mode."""
        keep = np.ones(self.n_modes, dtype=bool)
        if modes is not None:
            wanted = np.atleast_1d(np.asarray(modes)).reshape(-1)
            if wanted.size == 0 or not np.issubdtype(wanted.dtype, np.integer):
                raise ModeFileError(
                    self.path, f"modes to select must be mode numbers (integers); got {modes!r}"
                )
            missing = sorted(set(wanted.tolist()) - set(self.mode_numbers.tolist()))
            if missing:
                raise ModeFileError(
                    self.path,
                    f"no mode {', '.join(map(str, missing))} in the "
                    f"file; it has modes {_ranges(self.mode_numbers)}",
                )
            keep &= np.isin(self.mode_numbers, wanted)
        if band is not None:
            try:
                lo, hi = (float(b) for b in band)
            except (TypeError, ValueError):
                raise ModeFileError(
                    self.path, f"band must be (lo, hi) in Hz; got {band!r}"
                ) from None
            if np.isnan(lo) or np.isnan(hi) or lo > hi:
                raise ModeFileError(self.path, f"band ({lo:g}, {hi:g}) Hz: expected lo <= hi")
            among = keep.copy()
            keep &= (self.freq_hz >= lo) & (self.freq_hz <= hi)
            if not keep.any():
                raise ModeFileError(
                    self.path,
                    f"no mode between {lo:g} and {hi:g} Hz; the "
                    f"modes are at {_freqs(self.freq_hz[among])} Hz",
                )
        return self._subset(keep)

    def mass_normalised(self) -> ModeSet:
        """The same modes with phi_r / sqrt(m_r), so that every generalized mass is 1 (the
        shapes as they are when the file gives no modal mass)."""
        if self.modal_mass is None:
            return self
        scale = 1.0 / np.sqrt(self.modal_mass)
        return ModeSet(
            self.path,
            self.mode_numbers,
            self.freq_hz,
            self.node_ids,
            self.shapes * scale[:, None, None],
            self.damping,
            np.ones_like(self.modal_mass),
            self.units,
        )

    def _subset(self, keep) -> ModeSet:
        def pick(a):
            return None if a is None else a[keep]

        return ModeSet(
            self.path,
            self.mode_numbers[keep],
            self.freq_hz[keep],
            self.node_ids,
            self.shapes[keep],
            pick(self.damping),
            pick(self.modal_mass),
            self.units,
        )

    def __repr__(self) -> str:
        return (
            f"ModeSet({self.path!r}, {self.n_modes} modes {_ranges(self.mode_numbers)} at "
            f"{_freqs(self.freq_hz)} Hz, {self.n_nodes} nodes)"
        )


def sorted_mode_set(
    path, mode_numbers, freq_hz, node_ids, shapes, damping=None, modal_mass=None, units=None
) -> ModeSet:
    """A ModeSet with modes in increasing mode number and nodes in increasing id (the order
    every reader returns), after checking that neither repeats."""
    mode_numbers = _ints_or_error(path, mode_numbers, "mode numbers")
    node_ids = _ints_or_error(path, node_ids, "node ids")
    _unique(path, mode_numbers, "mode number")
    _unique(path, node_ids, "node id")
    om, on = np.argsort(mode_numbers, kind="stable"), np.argsort(node_ids, kind="stable")
    shapes = np.asarray(shapes, dtype=np.float64)
    if shapes.shape != (len(mode_numbers), len(node_ids), 6):
        raise ModeFileError(
            path,
            f"shapes have shape {shapes.shape}; expected ({len(mode_numbers)}, {len(node_ids)}, 6)",
        )

    def by_mode(a):
        return None if a is None else np.asarray(a, dtype=np.float64).reshape(-1)[om]

    return ModeSet(
        path,
        mode_numbers[om],
        by_mode(freq_hz),
        node_ids[on],
        shapes[om][:, on],
        by_mode(damping),
        by_mode(modal_mass),
        units,
    )


def _ints_or_error(path, values, what) -> np.ndarray:
    a = np.asarray(values).reshape(-1)
    if a.dtype.kind in "iu":
        return a.astype(np.int64)
    if a.dtype.kind == "f" and np.all(np.isfinite(a)) and np.all(a == np.round(a)):
        return a.astype(np.int64)
    raise ModeFileError(path, f"{what} must be integers; got {a[:5].tolist()}")


def _ints(ms: ModeSet, values, what) -> np.ndarray:
    return _ints_or_error(ms.path, values, what)


def _unique(path, values: np.ndarray, what: str) -> None:
    uniq, counts = np.unique(values, return_counts=True)
    if (counts > 1).any():
        dup = uniq[counts > 1]
        raise ModeFileError(
            path,
            f"{what} {', '.join(map(str, dup[:5].tolist()))} appears more "
            f"than once; expected each {what} once",
        )


def _check(ms: ModeSet) -> None:
    """Everything a ModeSet promises; raises ModeFileError naming the file."""
    p, m, n = ms.path, len(ms.mode_numbers), len(ms.node_ids)
    if m == 0:
        raise ModeFileError(p, "the file holds no modes; expected at least one")
    if n == 0:
        raise ModeFileError(p, "the file gives no node values; expected at least one node")
    _unique(p, ms.mode_numbers, "mode number")
    _unique(p, ms.node_ids, "node id")
    if (ms.mode_numbers < 1).any():
        bad = ms.mode_numbers[ms.mode_numbers < 1][0]
        raise ModeFileError(p, f"mode number {bad}: expected mode numbers >= 1")
    if ms.shapes.shape != (m, n, 6):
        raise ModeFileError(
            p,
            f"shapes have shape {ms.shapes.shape}; expected ({m}, {n}, 6) "
            "(modes, nodes, components x y z rx ry rz)",
        )
    _per_mode(ms, ms.freq_hz, "frequency", "Hz", lambda f: f >= 0, ">= 0")
    if ms.damping is not None:
        _per_mode(ms, ms.damping, "damping ratio", "", lambda z: (z >= 0) & (z < 1), "in [0, 1)")
    if ms.modal_mass is not None:
        _per_mode(ms, ms.modal_mass, "modal mass", "", lambda mm: mm > 0, "> 0")
    if np.isinf(ms.shapes).any():
        r, i, c = np.argwhere(np.isinf(ms.shapes))[0]
        raise ModeFileError(
            p,
            f"mode {ms.mode_numbers[r]} has an infinite value at node "
            f"{ms.node_ids[i]} {DOF_NAMES[c]}; expected finite numbers",
        )
    empty = np.isnan(ms.shapes).all(axis=(1, 2))
    if empty.any():
        raise ModeFileError(
            p,
            f"mode {ms.mode_numbers[empty][0]} has no shape values; expected "
            "a value at one node and component at least",
        )


def _per_mode(ms: ModeSet, values, what, unit, ok, expected) -> None:
    if values.shape != ms.mode_numbers.shape:
        raise ModeFileError(
            ms.path, f"{len(values)} {what} values for {ms.n_modes} modes; expected one per mode"
        )
    with np.errstate(invalid="ignore"):
        bad = ~np.isfinite(values) | ~ok(values)
    if bad.any():
        r = int(np.argmax(bad))
        raise ModeFileError(
            ms.path,
            f"mode {ms.mode_numbers[r]} has {what} {values[r]:g}"
            f"{' ' + unit if unit else ''}; expected a finite number "
            f"{expected}",
        )


def _ranges(numbers) -> str:
    """'1-4, 7, 9-10' from integers."""
    nums = sorted({int(x) for x in np.asarray(numbers).reshape(-1)})
    parts, start = [], None
    for i, x in enumerate(nums):
        if start is None:
            start = x
        if i + 1 == len(nums) or nums[i + 1] != x + 1:
            parts.append(str(start) if start == x else f"{start}-{x}")
            start = None
    return ", ".join(parts)


def _freqs(freq_hz: Iterable[float]) -> str:
    f = [f"{x:.4g}" for x in freq_hz]
    return ", ".join(f if len(f) <= 6 else f[:3] + ["..."] + f[-2:])
