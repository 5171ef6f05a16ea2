"""Compare two traces value by value (``x3dpd tracediff``).

Two values ``a`` (first trace) and ``b`` (second, the reference) *differ* when

.. math:: |a - b| > \\mathrm{atol} + \\mathrm{rtol}\\,|b|

(the ``numpy.isclose`` rule). Equal values, including equal infinities and NaN against NaN,
never differ; NaN against a number always does. The relative error reported per column is
``|a - b| / |b|`` (``inf`` where ``b = 0 != a``).

The traces are compared at the output times they share (equal within 1e-3 of the finer output
interval): two runs written with different ITRAC or DT are compared where both have a row, and
the report says how many times that was. Traces that do not end at the same time (a run cut
short) do not agree, even where their values do, unless ``until`` limits the comparison to the
common span.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from x3dpd.errors import TraceError
from x3dpd.io.trace import TraceData

_TIME_MATCH = 1e-3  # times match within this fraction of the output interval
_CHUNK_VALUES = 1 << 22  # values compared per pass (bounds temporaries)


@dataclass(frozen=True)
class Difference:
    """The first place where two traces differ."""

    time: float
    node_id: int
    column: str
    a: float
    b: float
    time_index: int
    node_index: int

    @property
    def abs_error(self) -> float:
        return abs(self.a - self.b)


@dataclass(frozen=True, eq=False)
class DiffReport:
    """Result of :func:`compare_traces`.

    Attributes
    ----------
    rtol, atol : float
        Tolerances used.
    until : float or None
        Requested end time.
    n_times : int
        Output times compared (those common to both traces, up to ``until``).
    t_end : float or None
        Last time compared (None when no time was compared).
    node_ids : (R,) int64
    columns : tuple of str
        ``x y z vx vy vz wx wy wz``.
    max_abs, max_rel : (9,) float64
        Largest ``|a - b|`` and ``|a - b| / |b|`` per column.
    max_abs_time, max_abs_node : (9,) float64 / int64
        Where the largest absolute error of each column occurs (NaN / -1 when it is 0).
    first : Difference or None
        Earliest difference (time, then node order, then column).
    n_differ : int
        Number of values that differ.
    time_mismatch : str or None
        Why the traces do not cover the same time span (one ends earlier); they then do not
        agree even if all compared values do. Different output grids over the same span (another
        ITRAC or DT) are compared at their common output times, with a note.
    """

    rtol: float
    atol: float
    until: float | None
    n_times: int
    t_end: float | None
    node_ids: np.ndarray
    columns: tuple[str, ...]
    max_abs: np.ndarray
    max_rel: np.ndarray
    max_abs_time: np.ndarray
    max_abs_node: np.ndarray
    first: Difference | None
    n_differ: int
    time_mismatch: str | None = None
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def agree(self) -> bool:
        """True when every compared value is within tolerance and the time grids match."""
        return self.first is None and self.time_mismatch is None

    def format(self, name_a: str = "A", name_b: str = "B") -> str:
        """The human-readable report ``x3dpd tracediff`` prints."""
        out = [
            (f"{'column':<7} {'max |a-b|':>16}  {'at t':>16} {'node':>8}  {'max |a-b|/|b|':>16}")
        ]
        for j, col in enumerate(self.columns):
            has = self.max_abs_node[j] >= 0
            t = f"{self.max_abs_time[j]: .9e}" if has else f"{'-':>16}"
            nd = f"{self.max_abs_node[j]:>8d}" if has else f"{'-':>8}"
            out.append(f"{col:<7} {self.max_abs[j]: .9e}  {t} {nd}  {self.max_rel[j]: .9e}")
        out.extend(self.notes)
        tol = f"rtol={self.rtol:g}, atol={self.atol:g}"
        upto = f"t={self.t_end:.9e}" if self.t_end is not None else "the start"
        if self.time_mismatch:
            out.append(f"time spans differ: {self.time_mismatch}")
        if self.first is not None:
            d = self.first
            lim = self.atol + self.rtol * abs(d.b)
            out.append(
                f"first difference: t={d.time:.9e} node {d.node_id} column {d.column}: "
                f"{name_a}={d.a:.9e} {name_b}={d.b:.9e} |a-b|={d.abs_error:.3e} > "
                f"atol+rtol*|b|={lim:.3e}"
            )
            out.append(f"{self.n_differ} value(s) differ within {tol} up to {upto}")
        elif self.time_mismatch is None:
            out.append(f"traces agree within {tol} up to {upto}")
        else:
            out.append(f"values agree within {tol} up to {upto}, but the time grids differ")
        return "\n".join(out)


def _upto(tr: TraceData, until: float | None, tol: float) -> int:
    if until is None:
        return tr.times.shape[0]
    return int(np.searchsorted(tr.times, until + tol, side="right"))


# Over 80 lines: the comparison's steps on shared arrays.
def compare_traces(
    a: TraceData, b: TraceData, rtol: float = 1e-9, atol: float = 0.0, until: float | None = None
) -> DiffReport:
    """Compare trace ``a`` against reference ``b``.

    Parameters
    ----------
    a, b : TraceData
        Traces of the same nodes. When either has no sidecar (``node_ids_known`` False) only
        the number of nodes is checked.
    rtol, atol : float
        Relative and absolute tolerances (>= 0); see the module docstring for the rule.
    until : float, optional
        Compare output times ``t <= until`` only [s].

    Returns
    -------
    DiffReport

    Raises
    ------
    TraceError
        The node lists differ (a comparison would be meaningless), or ``until`` is before
        the first output time.
    """
    if rtol < 0 or atol < 0:
        raise TraceError(f"tolerances must be >= 0 (rtol={rtol}, atol={atol})")
    ida, idb = a.node_ids.tolist(), b.node_ids.tolist()
    if a.node_ids_known and b.node_ids_known:
        if ida != idb:
            raise TraceError(
                f"the traces follow different nodes: {a.path or 'A'} traces "
                f"{len(ida)} nodes ({_abbrev(ida)}), {b.path or 'B'} traces "
                f"{len(idb)} ({_abbrev(idb)})"
            )
    elif len(ida) != len(idb):
        raise TraceError(
            f"the traces follow different numbers of nodes: {a.path or 'A'} has "
            f"{len(ida)} rows per output time, {b.path or 'B'} has {len(idb)}"
        )
    node_ids = a.node_ids if a.node_ids_known or not b.node_ids_known else b.node_ids
    notes = []
    if not (a.node_ids_known and b.node_ids_known):
        notes.append(
            "(node ids unknown for a trace without sidecar: nodes numbered by row position)"
        )

    # output interval -> tolerance for "same output time"
    spacing = [np.min(np.diff(t)) for t in (a.times, b.times) if t.shape[0] > 1]
    scale = max([1.0, *(abs(t[-1]) for t in (a.times, b.times) if t.shape[0])])
    ttol = _TIME_MATCH * min(spacing) if spacing else 1e-9 * scale
    ka, kb = _upto(a, until, ttol), _upto(b, until, ttol)
    if until is not None and (ka == 0 or kb == 0):
        first_t = (a.times[:1].tolist() or b.times[:1].tolist() or [None])[0]
        raise TraceError(f"--until {until:g} is before the first output time ({first_t})")
    ia, ib = _common_times(a.times[:ka], b.times[:kb], ttol)
    if ia.size == 0:
        raise TraceError(
            f"the traces have no output time in common (A: {_span(a.times[:ka])}; "
            f"B: {_span(b.times[:kb])})"
        )
    k = int(ia.size)
    mismatch = None
    if not (ka == kb == k):
        notes.append(
            f"time grids differ: A has {ka} output times ({_span(a.times[:ka])}), B "
            f"{kb} ({_span(b.times[:kb])}); compared the {k} common ones"
        )
    if abs(a.times[ka - 1] - b.times[kb - 1]) > ttol:
        longer, shorter = ("A", "B") if a.times[ka - 1] > b.times[kb - 1] else ("B", "A")
        tt = a.times[:ka] if longer == "A" else b.times[:kb]
        other = b.times[kb - 1] if longer == "A" else a.times[ka - 1]
        mismatch = (
            f"{longer} has {ka if longer == 'A' else kb} output times (to "
            f"t={tt[-1]:.9e}), {shorter} ends at t={other:.9e}; compare the common "
            f"part with --until"
        )

    R, C = len(ida), len(a.columns)
    max_abs = np.zeros(C)
    max_rel = np.zeros(C)
    max_abs_time = np.full(C, np.nan)
    max_abs_node = np.full(C, -1, dtype=np.int64)
    first = None
    n_differ = 0
    step = max(1, _CHUNK_VALUES // max(1, R * C))
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for s in range(0, k, step):
            e = min(s + step, k)
            xa = a.data[ia[s:e]]
            xb = b.data[ib[s:e]]
            same = (xa == xb) | (np.isnan(xa) & np.isnan(xb))
            err = np.where(same, 0.0, np.abs(xa - xb))
            err[np.isnan(err)] = np.inf  # NaN against a number
            differ = err > atol + rtol * np.abs(xb)
            rel = np.where(err == 0.0, 0.0, err / np.abs(xb))
            flat = err.reshape(-1, C)
            imax = np.argmax(flat, axis=0)
            vmax = flat[imax, np.arange(C)]
            better = vmax > max_abs
            max_abs = np.where(better, vmax, max_abs)
            ti, ni = np.divmod(imax, R)
            max_abs_time = np.where(better, a.times[ia[s + ti]], max_abs_time)
            max_abs_node = np.where(better, node_ids[ni], max_abs_node)
            max_rel = np.maximum(max_rel, rel.reshape(-1, C).max(axis=0))
            cnt = int(np.count_nonzero(differ))
            if cnt and first is None:
                pos = int(np.argmax(differ.ravel()))
                ti, rest = divmod(pos, R * C)
                ni, ci = divmod(rest, C)
                first = Difference(
                    time=float(a.times[ia[s + ti]]),
                    node_id=int(node_ids[ni]),
                    column=a.columns[ci],
                    a=float(xa[ti, ni, ci]),
                    b=float(xb[ti, ni, ci]),
                    time_index=int(ia[s + ti]),
                    node_index=ni,
                )
            n_differ += cnt
    return DiffReport(
        rtol=rtol,
        atol=atol,
        until=until,
        n_times=k,
        t_end=float(a.times[ia[-1]]),
        node_ids=node_ids,
        columns=tuple(a.columns),
        max_abs=max_abs,
        max_rel=max_rel,
        max_abs_time=max_abs_time,
        max_abs_node=max_abs_node,
        first=first,
        n_differ=n_differ,
        time_mismatch=mismatch,
        notes=tuple(notes),
    )


def _common_times(ta: np.ndarray, tb: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Indices ``(ia, ib)`` of the output times the two (increasing) grids share within ``tol``."""
    if ta.size == 0 or tb.size == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    j = (
        np.clip(np.searchsorted(tb, ta), 1, tb.size - 1)
        if tb.size > 1
        else np.zeros(ta.size, np.int64)
    )
    if tb.size > 1:
        j = np.where(np.abs(tb[j - 1] - ta) <= np.abs(tb[j] - ta), j - 1, j)
    hit = np.abs(tb[j] - ta) <= tol
    return np.flatnonzero(hit).astype(np.int64), j[hit].astype(np.int64)


def _span(t: np.ndarray) -> str:
    if t.size == 0:
        return "none"
    step = f", every {np.median(np.diff(t)):.6g} s" if t.size > 1 else ""
    return f"t = {t[0]:.6g} .. {t[-1]:.6g} s{step}"


def _abbrev(items: list, n: int = 6) -> str:
    return ", ".join(map(str, items[:n])) + (", ..." if len(items) > n else "")
