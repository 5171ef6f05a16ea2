"""compare_traces against a naive reference, tolerance rule, first-difference order."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import x3dpd.io.tracediff as td
from x3dpd.errors import TraceError
from x3dpd.io.trace import DATA_COLUMNS, TraceData
from x3dpd.io.tracediff import compare_traces


def trace(data, times=None, ids=None, known=True):
    data = np.asarray(data, dtype=float)
    k, R, _ = data.shape
    return TraceData(
        times=np.arange(k) * 1e-3 if times is None else np.asarray(times, float),
        node_ids=np.arange(10, 10 + R) if ids is None else np.asarray(ids),
        data=data,
        node_ids_known=known,
    )


def naive(a, b, rtol, atol):
    """Loop over time, node, column in order; the obvious definitions."""
    first, max_abs, max_rel = None, [0.0] * 9, [0.0] * 9
    for i, r, c in itertools.product(*map(range, a.data.shape)):
        x, y = float(a.data[i, r, c]), float(b.data[i, r, c])
        err = abs(x - y)
        rel = 0.0 if err == 0 else (err / abs(y) if y != 0 else np.inf)
        max_abs[c] = max(max_abs[c], err)
        max_rel[c] = max(max_rel[c], rel)
        if first is None and err > atol + rtol * abs(y):
            first = (a.times[i], int(a.node_ids[r]), DATA_COLUMNS[c], x, y)
    return first, max_abs, max_rel


@settings(max_examples=60, deadline=None)
@given(
    k=st.integers(1, 5),
    R=st.integers(1, 4),
    seed=st.integers(0, 2**32 - 1),
    nbad=st.integers(0, 6),
    rtol=st.sampled_from([0.0, 1e-9, 1e-3]),
    atol=st.sampled_from([0.0, 1e-12, 1e-2]),
    chunk=st.sampled_from([1 << 22, 9, 40]),
)
def test_matches_naive_reference(k, R, seed, nbad, rtol, atol, chunk):
    rng = np.random.default_rng(seed)
    b = rng.normal(size=(k, R, 9))
    b[rng.random(b.shape) < 0.1] = 0.0
    a = b.copy()
    for _ in range(nbad):
        idx = tuple(rng.integers(0, s) for s in a.shape)
        a[idx] += rng.choice([1e-13, 1e-10, 1e-6, 1e-1]) * rng.choice([-1, 1])
    ta, tb = trace(a), trace(b)
    old = td._CHUNK_VALUES
    td._CHUNK_VALUES = chunk
    try:
        rep = compare_traces(ta, tb, rtol=rtol, atol=atol)
    finally:
        td._CHUNK_VALUES = old
    first, max_abs, max_rel = naive(ta, tb, rtol, atol)
    np.testing.assert_array_equal(rep.max_abs, max_abs)
    np.testing.assert_array_equal(rep.max_rel, max_rel)
    if first is None:
        assert rep.first is None and rep.agree and rep.n_differ == 0
    else:
        d = rep.first
        assert (d.time, d.node_id, d.column, d.a, d.b) == first
        assert not rep.agree


def test_first_difference_order_time_then_node_then_column():
    b = np.ones((3, 3, 9))
    a = b.copy()
    a[2, 0, 0] = 5.0  # later time
    a[1, 2, 1] = 5.0  # same time, later node
    a[1, 1, 6] = 5.0  # first: time 1, node 11, column wx
    a[1, 1, 8] = 5.0
    rep = compare_traces(trace(a), trace(b))
    assert (rep.first.time, rep.first.node_id, rep.first.column) == (1e-3, 11, "wx")
    assert rep.n_differ == 4
    assert rep.max_abs_time[0] == 2e-3 and rep.max_abs_node[0] == 10
    assert rep.max_abs_node[2] == -1 and np.isnan(rep.max_abs_time[2])


def test_tolerance_boundary_is_inclusive():
    b = np.full((1, 1, 9), 2.0)
    a = b + 0.5
    assert compare_traces(trace(a), trace(b), rtol=0.125, atol=0.25).agree
    assert not compare_traces(trace(a), trace(b), rtol=0.125, atol=0.2).agree


def test_nan_and_inf():
    b = np.zeros((1, 1, 9))
    b[0, 0, :3] = [np.nan, np.inf, 1.0]
    assert compare_traces(trace(b.copy()), trace(b)).agree
    a = b.copy()
    a[0, 0, 2] = np.nan
    rep = compare_traces(trace(a), trace(b), atol=1e300)
    assert rep.first.column == "z" and rep.max_abs[2] == np.inf
    a = b.copy()
    a[0, 0, 3] = 1e-30  # against exact zero: relative error inf, absolute tiny
    rep = compare_traces(trace(a), trace(b), atol=1e-20)
    assert rep.agree and rep.max_rel[3] == np.inf and rep.max_abs[3] == 1e-30


def test_until_limits_the_comparison():
    b = np.zeros((5, 2, 9))
    a = b.copy()
    a[3, 1, 4] = 1.0
    assert not compare_traces(trace(a), trace(b)).agree
    rep = compare_traces(trace(a), trace(b), until=2e-3)
    assert rep.agree and rep.n_times == 3 and rep.t_end == 2e-3
    assert "traces agree within rtol=1e-09, atol=0 up to t=2.000000000e-03" in rep.format()
    with pytest.raises(TraceError, match="before the first output time"):
        compare_traces(trace(a), trace(b), until=-1.0)


def test_node_lists_must_match():
    a = np.zeros((2, 3, 9))
    with pytest.raises(TraceError, match="different nodes"):
        compare_traces(trace(a, ids=[1, 2, 3]), trace(a, ids=[1, 3, 2]))
    with pytest.raises(TraceError, match="different numbers of nodes"):
        compare_traces(trace(a, known=False), trace(np.zeros((2, 2, 9))))
    rep = compare_traces(trace(a, ids=[1, 2, 3], known=False), trace(a, ids=[7, 8, 9]))
    assert rep.agree and rep.node_ids.tolist() == [7, 8, 9]
    assert "node ids unknown" in rep.format()


def test_time_grid_mismatch():
    b = np.zeros((5, 1, 9))
    short = compare_traces(trace(b[:3]), trace(b))
    assert not short.agree and short.first is None and short.n_times == 3
    assert "B has 5 output times" in short.time_mismatch
    assert "time grids differ" in short.format()
    assert compare_traces(trace(b[:3]), trace(b), until=2e-3).agree
    # an output time that only one grid has is left out (4 common times; same span: agree)
    shifted = compare_traces(trace(b, times=[0, 1e-3, 2e-3, 3.5e-3, 4e-3]), trace(b))
    assert shifted.agree and shifted.n_times == 4 and shifted.time_mismatch is None
    assert "compared the 4 common ones" in shifted.format()
    # the last printed digit may differ: still the same output time
    assert compare_traces(trace(b, times=np.arange(5) * 1e-3 * (1 + 1e-9)), trace(b)).agree


def test_report_text_lists_every_column():
    b = np.ones((2, 2, 9))
    a = b.copy()
    a[1, 0, 3] = 1.5
    text = compare_traces(trace(a), trace(b)).format("run.txt", "ref.txt")
    lines = text.splitlines()
    assert lines[0].split()[:2] == ["column", "max"]
    assert [ln.split()[0] for ln in lines[1:10]] == list(DATA_COLUMNS)
    assert (
        "first difference: t=1.000000000e-03 node 10 column vx: run.txt=1.500000000e+00 "
        "ref.txt=1.000000000e+00" in text
    )
    assert "1 value(s) differ within rtol=1e-09, atol=0 up to t=1.000000000e-03" in text


def test_different_output_intervals_are_compared_at_common_times():
    """A every 1 ms, B every 2 ms over the same 8 ms: the 5 shared times are compared; a change
    at a time B does not have is invisible, one at a shared time is found."""
    rng = np.random.default_rng(5)
    fine = rng.normal(size=(9, 2, 9))
    t_fine = np.arange(9) * 1e-3
    a = trace(fine, times=t_fine)
    b = trace(fine[::2], times=t_fine[::2])
    rep = compare_traces(a, b)
    assert rep.agree and rep.n_times == 5 and rep.t_end == pytest.approx(8e-3)
    assert "A has 9 output times" in rep.format() and "compared the 5 common ones" in rep.format()
    odd = fine.copy()
    odd[3, 1, 4] += 1.0  # t = 3 ms: not in B
    assert compare_traces(trace(odd, times=t_fine), b).agree
    even = fine.copy()
    even[4, 1, 4] += 1.0  # t = 4 ms: in both
    rep = compare_traces(trace(even, times=t_fine), b)
    assert not rep.agree and rep.first.time == pytest.approx(4e-3) and rep.first.time_index == 4
    with pytest.raises(TraceError, match="no output time in common"):
        compare_traces(trace(fine[:2], times=[0.5e-3, 1.5e-3]), trace(fine[:2]))
