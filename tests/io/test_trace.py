"""Trace files: the pmov.m-readable format, the sidecar, resuming, and the reader's checks."""

from __future__ import annotations

import json
import os
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from x3dpd.errors import TraceError, UnstableRunError
from x3dpd.io.trace import (
    COLUMNS,
    DATA_COLUMNS,
    DEFAULT_UNITS,
    TRACE_FORMAT,
    TraceWarning,
    TraceWriter,
    read_trace,
    sha256_file,
)

IDS = [25, 26, 27, 28, 29]


def dlmread(path, sep=";"):
    """Tiny emulation of MATLAB ``dlmread(path, sep)``: a numeric matrix, one row per line."""
    rows = []
    with open(path) as f:
        for line in f:
            rows.append([float(x) for x in line.split(sep)])
    width = max(len(r) for r in rows)
    return np.array([r + [0.0] * (width - len(r)) for r in rows])


# -- format -----------------------------------------------------------------------------------


def test_rows_are_percent_9e_joined_by_semicolons(make_trace):
    data = np.arange(2 * 2 * 9, dtype=float).reshape(2, 2, 9) - 7.5
    data[0, 0, 0] = 1.0e-300
    data[1, 1, 8] = -123456789.0123
    path = make_trace("t.txt", [7, 3], [0.0, 2.5e-3], data)
    lines = path.read_bytes().decode("ascii").split("\n")
    assert lines[-1] == ""  # every row ends with a newline
    expect = []
    for i, t in enumerate([0.0, 2.5e-3]):
        for r in range(2):
            expect.append(";".join("% .9e" % v for v in [t, *data[i, r]]))  # noqa: UP031
    assert lines[:-1] == expect
    assert lines[0].startswith(" 0.000000000e+00; 1.000000000e-300;")
    assert lines[3].endswith(";-1.234567890e+08")


def test_numpy_loadtxt_reads_the_file(make_trace, synthetic):
    times, data = synthetic(4, IDS)
    path = make_trace("t.txt", IDS, times, data)
    arr = np.loadtxt(path, delimiter=";")
    assert arr.shape == (4 * len(IDS), 10)
    np.testing.assert_allclose(arr[:, 0], np.repeat(times, len(IDS)), rtol=0, atol=1e-15)
    np.testing.assert_allclose(arr[:, 1:], data.reshape(-1, 9), rtol=6e-10)


def test_pmov_indexing_with_dlmread(make_trace, synthetic):
    """pmov.m: rows = size(temp,1); tims = rows/(nump+1); x of node k at time j is
    temp((j-1)*(nump+1)+k, 2), vx is column 5 (1-based)."""
    times, data = synthetic(3, IDS, seed=3)
    path = make_trace("trace.txt", IDS, times, data)
    temp = dlmread(path, ";")
    nump = len(IDS) - 1  # pmov traces the cavity master node plus nump particles
    tims = temp.shape[0] / (nump + 1)
    assert tims == 3
    for j in range(1, 4):
        assert temp[(j - 1) * (nump + 1) + 1 - 1, 1 - 1] == pytest.approx(times[j - 1])
        for k in range(1, nump + 2):
            row = temp[(j - 1) * (nump + 1) + k - 1]
            assert row[2 - 1] == pytest.approx(data[j - 1, k - 1, 0], rel=6e-10)
            assert row[5 - 1] == pytest.approx(data[j - 1, k - 1, 3], rel=6e-10)
            assert row[7 - 1] == pytest.approx(data[j - 1, k - 1, 5], rel=6e-10)


def test_columns_align(make_trace, synthetic):
    times, data = synthetic(6, IDS, seed=5)
    path = make_trace("t.txt", IDS, times, data)
    lines = path.read_text().splitlines()
    assert {len(line) for line in lines} == {10 * 16 + 9}
    assert {tuple(i for i, c in enumerate(line) if c == ";") for line in lines} == {
        tuple(16 + 17 * i for i in range(9))
    }


finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@settings(max_examples=40, deadline=None)
@given(
    data=hnp.arrays(
        np.float64, st.tuples(st.integers(1, 4), st.integers(1, 6), st.just(9)), elements=finite
    ),
    t0=st.floats(0, 1e3),
    step=st.floats(1e-7, 1.0),
)
def test_round_trip(tmp_path_factory, data, t0, step):
    k, R, _ = data.shape
    times = t0 + step * np.arange(k)
    # the format prints 10 significant digits: consecutive output times must differ by more
    # than that resolution (real traces are DT*ITRAC apart, e.g. 1e-3 s at t <= 15 s)
    printed_times = np.array([float(f"{v:.9e}") for v in times])
    if not np.all(np.diff(printed_times) > 0):
        return
    ids = list(range(100, 100 + R))
    path = tmp_path_factory.mktemp("rt") / "t.txt"
    with TraceWriter(path, ids, {}) as w:
        w.write_block(times, data)
    tr = read_trace(path)
    printed = np.vectorize(lambda v: float(f"{v:.9e}"))
    np.testing.assert_array_equal(tr.times, printed(times))
    np.testing.assert_array_equal(tr.data, printed(data))
    assert tr.node_ids.tolist() == ids and tr.node_ids_known
    assert tr.node(ids[-1]).shape == (k, 9)
    np.testing.assert_array_equal(tr.node(ids[-1]), printed(data[:, -1, :]))


def test_nan_and_inf_are_written_and_read(make_trace):
    data = np.zeros((1, 2, 9))
    data[0, 0, 2] = np.nan
    data[0, 1, 4] = -np.inf
    path = make_trace("t.txt", [1, 2], [0.0], data)
    tr = read_trace(path)
    assert np.isnan(tr.data[0, 0, 2]) and tr.data[0, 1, 4] == -np.inf
    assert np.isnan(np.loadtxt(path, delimiter=";")[0, 3])


def test_many_blocks_streamed_in_chunks(tmp_path, synthetic, monkeypatch):
    import x3dpd.io.trace_writer as trace_mod

    monkeypatch.setattr(trace_mod, "_ROWS_PER_CHUNK", 7)  # 2 blocks of 3 rows per pass
    ids = [1, 2, 3]
    times, data = synthetic(11, ids)
    with TraceWriter(tmp_path / "a.txt", ids, {}) as w:
        w.write_block(times, data)
        assert w.blocks_written == 11
    with TraceWriter(tmp_path / "b.txt", ids, {}) as w:
        for i in range(11):
            w.write_block(times[i], data[i])
        w.flush()
        assert w.tell() == os.path.getsize(tmp_path / "b.txt")
    assert (tmp_path / "a.txt").read_bytes() == (tmp_path / "b.txt").read_bytes()


def test_write_block_rejects_bad_input(tmp_path):
    with TraceWriter(tmp_path / "t.txt", [1, 2], {}) as w:
        with pytest.raises(ValueError, match=r"\(k, 2, 9\)"):
            w.write_block([0.0], np.zeros((1, 3, 9)))
        w.write_block([0.0, 1.0], np.zeros((2, 2, 9)))
        with pytest.raises(ValueError, match="increase"):
            w.write_block([1.0], np.zeros((1, 2, 9)))
        with pytest.raises(ValueError, match="increase"):
            w.write_block([3.0, 2.0], np.zeros((2, 2, 9)))
        assert w.blocks_written == 2
    with pytest.raises(ValueError):
        TraceWriter(tmp_path / "u.txt", [], {})


def test_write_4096_nodes_fast(tmp_path):
    rng = np.random.default_rng(0)
    ids = np.arange(1, 4097)
    best = np.inf
    with TraceWriter(tmp_path / "t.txt", ids, {}) as w:
        for i in range(7):
            d = rng.normal(size=(1, 4096, 9))
            t0 = time.thread_time()  # this thread's CPU time: another busy process cannot fail it
            w.write_block([i * 1e-3], d)
            best = min(best, time.thread_time() - t0)
    print(f"write_block, 4096 nodes: {best * 1e3:.1f} ms")
    assert best < 0.05


# -- existing files, sidecar, status -----------------------------------------------------------


def test_refuses_to_replace_existing_trace(tmp_path):
    path = tmp_path / "trace.txt"
    path.write_text("precious\n")
    with pytest.raises(TraceError, match="--overwrite.*--trace"):
        TraceWriter(path, [1], {})
    assert path.read_text() == "precious\n"
    assert not (tmp_path / "trace.txt.json").exists()


def test_overwrite_keeps_a_backup(make_trace, synthetic, tmp_path):
    ids = [1, 2]
    t, d = synthetic(2, ids)
    first = make_trace("t.txt", ids, t, d, sidecar={"run": 1})
    old = first.read_bytes()
    make_trace("t.txt", ids, t[:1], d[:1], sidecar={"run": 2}, overwrite=True)
    assert (tmp_path / "t.txt.bak").read_bytes() == old
    assert json.loads((tmp_path / "t.txt.bak.json").read_text())["run"] == 1
    assert read_trace(tmp_path / "t.txt.bak").times.size == 2
    make_trace("t.txt", ids, t, d, sidecar={"run": 3}, overwrite=True)  # replaces older .bak
    assert json.loads((tmp_path / "t.txt.bak.json").read_text())["run"] == 2
    assert read_trace(first).meta["run"] == 3


def test_overwrite_without_old_sidecar_drops_stale_backup_sidecar(tmp_path):
    (tmp_path / "t.txt.bak.json").write_text("{}")
    (tmp_path / "t.txt").write_text(" 0.0;1;2;3;4;5;6;7;8;9\n")
    TraceWriter(tmp_path / "t.txt", [1], {}, overwrite=True).close()
    assert (tmp_path / "t.txt.bak").exists()
    assert not (tmp_path / "t.txt.bak.json").exists()


def test_cannot_create_in_missing_directory(tmp_path):
    with pytest.raises(TraceError, match="cannot create"):
        TraceWriter(tmp_path / "nope" / "t.txt", [1], {})


def test_sidecar_contents(tmp_path):
    deck = tmp_path / "deck.inp"
    deck.write_text("TITLE\nx\n")
    side = {
        "deck_path": str(deck),
        "deck_sha256": sha256_file(deck),
        "dt": 5e-7,
        "itrac": 2000,
        "effects": frozenset({"gravity", "wall_contact"}),
        "title": "x",
        "status": "ignored",
        "format": "ignored",
    }
    path = tmp_path / "t.txt"
    with TraceWriter(path, np.array([25, 26]), side, units={"length": "m", "velocity": "m/s"}) as w:
        meta = json.loads((tmp_path / "t.txt.json").read_text())
        assert meta["status"] == "running" and meta["blocks"] == 0
        w.write_block([0.0, 1e-3], np.zeros((2, 2, 9)))
    meta = json.loads((tmp_path / "t.txt.json").read_text())
    import hashlib

    assert meta["format"] == TRACE_FORMAT
    assert meta["columns"] == list(COLUMNS)
    assert meta["units"] == {**DEFAULT_UNITS, "length": "m", "velocity": "m/s"}
    assert meta["node_ids"] == [25, 26]
    assert meta["deck_sha256"] == hashlib.sha256(b"TITLE\nx\n").hexdigest()
    assert meta["deck_path"] == str(deck)
    assert meta["x3dpd_version"]
    assert meta["dt"] == 5e-7 and meta["itrac"] == 2000
    assert meta["effects"] == ["gravity", "wall_contact"]
    assert meta["title"] == "x"
    assert meta["status"] == "complete" and meta["blocks"] == 2
    assert meta["bytes"] == os.path.getsize(path) and meta["last_time"] == 1e-3
    assert read_trace(path).units["length"] == "m"
    assert not [p for p in os.listdir(tmp_path) if p.endswith(".tmp")]


def _status(path):
    return json.loads(open(str(path) + ".json").read())["status"]


def test_status_on_exit(tmp_path):
    with pytest.raises(KeyboardInterrupt), TraceWriter(tmp_path / "a.txt", [1], {}) as w:
        w.write_block([0.0], np.zeros((1, 1, 9)))
        raise KeyboardInterrupt
    assert _status(tmp_path / "a.txt") == "interrupted"
    with pytest.raises(UnstableRunError), TraceWriter(tmp_path / "b.txt", [1], {}):
        raise UnstableRunError("blew up", time=1.0)
    assert _status(tmp_path / "b.txt") == "unstable"
    with pytest.raises(RuntimeError), TraceWriter(tmp_path / "c.txt", [1], {}):
        raise RuntimeError
    assert _status(tmp_path / "c.txt") == "interrupted"
    w = TraceWriter(tmp_path / "d.txt", [1], {})
    w.close("unstable")
    w.close()  # idempotent
    assert _status(tmp_path / "d.txt") == "unstable"
    with pytest.raises(ValueError):
        TraceWriter(tmp_path / "e.txt", [1], {}).close("exploded")


def test_flush_fsyncs_and_updates_sidecar(tmp_path, monkeypatch):
    synced = []
    real = os.fsync
    monkeypatch.setattr(os, "fsync", lambda fd: (synced.append(fd), real(fd)))
    path = tmp_path / "t.txt"
    with TraceWriter(path, [1, 2], {}) as w:
        w.write_block([0.0], np.ones((1, 2, 9)))
        synced.clear()
        w.flush()
        assert synced  # the data (and the sidecar) were fsync'ed
        meta = json.loads((tmp_path / "t.txt.json").read_text())
        assert meta["status"] == "running" and meta["blocks"] == 1
        assert meta["bytes"] == w.tell() == os.path.getsize(path) == 2 * 170


# -- resuming ---------------------------------------------------------------------------------


def test_resume_reproduces_an_uninterrupted_run(tmp_path, synthetic):
    ids = [4, 5, 6]
    times, data = synthetic(8, ids)
    with TraceWriter(tmp_path / "ref.txt", ids, {}) as w:
        w.write_block(times, data)
    path = tmp_path / "t.txt"
    with pytest.raises(KeyboardInterrupt), TraceWriter(path, ids, {}) as w:
        w.write_block(times[:3], data[:3])
        w.flush()
        dump = (w.tell(), w.blocks_written)  # what a restart dump records
        w.write_block(times[3:5], data[3:5])
        raise KeyboardInterrupt
    with open(path, "ab") as f:
        f.write(b" 9.0e-03; 1.0")  # a row cut short by the interruption
    with TraceWriter(path, ids, {}, append_at=dump) as w:
        assert w.blocks_written == 3 and w.tell() == dump[0]
        with pytest.raises(ValueError, match="increase"):
            w.write_block(times[2], data[2])
        w.write_block(times[3:], data[3:])
    assert path.read_bytes() == (tmp_path / "ref.txt").read_bytes()
    meta = json.loads((tmp_path / "t.txt.json").read_text())
    assert meta["status"] == "complete" and meta["blocks"] == 8


def test_resume_checks(make_trace, synthetic, tmp_path):
    ids = [1, 2]
    t, d = synthetic(4, ids)
    with pytest.raises(TraceError, match="does not exist"):
        TraceWriter(tmp_path / "none.txt", ids, {}, append_at=(0, 0))
    path = make_trace("t.txt", ids, t, d)
    size = os.path.getsize(path)
    with pytest.raises(TraceError, match="is complete.*--overwrite"):
        TraceWriter(path, ids, {}, append_at=(size // 2, 2))
    assert os.path.getsize(path) == size
    side = json.loads((tmp_path / "t.txt.json").read_text())
    side["status"] = "interrupted"
    (tmp_path / "t.txt.json").write_text(json.dumps(side))
    with pytest.raises(TraceError, match="traces nodes"):
        TraceWriter(path, [1, 3], {}, append_at=(size // 2, 2))
    with pytest.raises(TraceError, match="only"):
        TraceWriter(path, ids, {}, append_at=(size + 1, 4))
    with pytest.raises(TraceError, match="not the end of a row"):
        TraceWriter(path, ids, {}, append_at=(size // 2 - 1, 2))
    with pytest.raises(TraceError, match="expects 3 x 2"):
        TraceWriter(path, ids, {}, append_at=(size // 2, 3))
    assert os.path.getsize(path) == size
    TraceWriter(path, ids, {}, append_at=(0, 0)).close()
    assert os.path.getsize(path) == 0


def test_resume_complete_trace_with_overwrite_keeps_copy(make_trace, synthetic, tmp_path):
    ids = [1, 2]
    t, d = synthetic(4, ids)
    path = make_trace("t.txt", ids, t, d)
    old = path.read_bytes()
    with TraceWriter(path, ids, {}, append_at=(len(old) // 2, 2), overwrite=True) as w:
        w.write_block(t[2:], d[2:] * 2)
    assert (tmp_path / "t.txt.bak").read_bytes() == old
    assert json.loads((tmp_path / "t.txt.bak.json").read_text())["status"] == "complete"
    np.testing.assert_allclose(read_trace(path).data[2:], d[2:] * 2, rtol=1e-9)


# -- reading ----------------------------------------------------------------------------------


def test_read_without_sidecar_infers_rows_per_time(make_trace, synthetic, tmp_path):
    times, data = synthetic(3, IDS)
    path = make_trace("t.txt", IDS, times, data)
    os.unlink(tmp_path / "t.txt.json")
    tr = read_trace(path)
    assert not tr.node_ids_known and tr.node_ids.tolist() == [1, 2, 3, 4, 5]
    assert tr.meta == {} and tr.units == DEFAULT_UNITS and tr.status is None
    np.testing.assert_allclose(tr.data, data, rtol=6e-10)
    tr = read_trace(path, node_ids=IDS)
    assert tr.node_ids_known and tr.node(27).shape == (3, 9)
    assert tr.columns == DATA_COLUMNS
    np.testing.assert_array_equal(tr.column("vx"), tr.data[:, :, 3])
    with pytest.raises(KeyError, match="node 99"):
        tr.node(99)


def test_single_row_file_without_sidecar(tmp_path):
    (tmp_path / "t.txt").write_text(" 0.0;1;2;3;4;5;6;7;8;9\n")
    tr = read_trace(tmp_path / "t.txt")
    assert tr.data.shape == (1, 1, 9)


def test_truncated_last_block_is_dropped_with_warning(make_trace, synthetic):
    times, data = synthetic(3, IDS)
    path = make_trace("t.txt", IDS, times, data)
    side_path = path.with_name(path.name + ".json")
    side = json.loads(side_path.read_text())
    side["status"] = "interrupted"
    side_path.write_text(json.dumps(side))
    raw = path.read_bytes()
    lines = raw.split(b"\n")
    path.write_bytes(b"\n".join(lines[: 2 * len(IDS) + 2]) + b"\n")
    with pytest.warns(TraceWarning, match="incomplete.*2 of 5 rows"):
        tr = read_trace(path)
    assert tr.times.size == 2 and tr.dropped_rows == 2
    with pytest.raises(TraceError, match="incomplete"):
        read_trace(path, strict=True)
    path.write_bytes(raw[:-40])  # last line cut short, block otherwise whole
    with pytest.warns(TraceWarning, match="cut short"):
        tr = read_trace(path)
    assert tr.times.size == 2 and tr.dropped_rows == 5


def test_complete_sidecar_but_short_file_warns(make_trace, synthetic):
    times, data = synthetic(3, IDS)
    path = make_trace("t.txt", IDS, times, data)
    raw = path.read_bytes()
    path.write_bytes(raw[: len(raw) // 3])
    with pytest.warns(TraceWarning, match="complete run of 3 output times but the file holds 1"):
        read_trace(path)


@pytest.mark.parametrize(
    "bad, line, match",
    [
        ("abc", 7, r"column 4 \(z\): 'abc' is not a number"),
        (None, 5, "expected 10 ';'-separated numbers"),
    ],
)
def test_malformed_line_is_named(make_trace, synthetic, bad, line, match):
    times, data = synthetic(3, IDS)
    path = make_trace("t.txt", IDS, times, data)
    lines = path.read_text().splitlines()
    fields = lines[line - 1].split(";")
    if bad is None:
        fields = fields[:-1]
    else:
        fields[3] = bad
    lines[line - 1] = ";".join(fields)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(TraceError, match=rf"t\.txt:{line}: {match}"):
        read_trace(path)


def test_wrong_row_count_per_time_is_reported(make_trace, synthetic, tmp_path):
    times, data = synthetic(3, IDS)
    path = make_trace("t.txt", IDS, times, data)
    side = json.loads((tmp_path / "t.txt.json").read_text())
    side["node_ids"] = [25, 26, 27]
    (tmp_path / "t.txt.json").write_text(json.dumps(side))
    with pytest.raises(
        TraceError,
        match=(
            r"t\.txt:6: time 1\.0+e-03 differs from 0\.0+e\+00 on "
            r"line 4; each output time should have 3 rows "
            r"\(from the sidecar\)"
        ),
    ):
        read_trace(path)


def test_times_must_increase(tmp_path):
    rows = [" 0.0;1;2;3;4;5;6;7;8;9", " 1.0;1;2;3;4;5;6;7;8;9", " 1.0;1;2;3;4;5;6;7;8;9"]
    (tmp_path / "t.txt").write_text("\n".join(rows) + "\n")
    with pytest.raises(TraceError, match=r"t\.txt:3: time 1\.0+e\+00 does not come after"):
        read_trace(tmp_path / "t.txt", node_ids=[1])


def test_blank_line_inside_is_an_error(tmp_path):
    rows = [" 0.0;1;2;3;4;5;6;7;8;9", "", " 1.0;1;2;3;4;5;6;7;8;9"]
    (tmp_path / "t.txt").write_text("\n".join(rows) + "\n\n")
    with pytest.raises(TraceError, match="blank line"):
        read_trace(tmp_path / "t.txt")
    (tmp_path / "t.txt").write_text(rows[0] + "\n" + rows[2] + "\n\n")  # trailing blank: fine
    assert read_trace(tmp_path / "t.txt").times.size == 2


def test_sidecar_problems(make_trace, synthetic, tmp_path):
    times, data = synthetic(2, IDS)
    path = make_trace("t.txt", IDS, times, data)
    side = tmp_path / "t.txt.json"
    side.write_text("{not json")
    with pytest.raises(TraceError, match="not readable JSON"):
        read_trace(path)
    side.write_text(json.dumps({"format": "other/2", "node_ids": IDS}))
    with pytest.raises(TraceError, match="'other/2'"):
        read_trace(path)
    side.write_text(json.dumps({"format": TRACE_FORMAT, "node_ids": []}))
    with pytest.raises(TraceError, match="node_ids"):
        read_trace(path)


def test_missing_or_empty(tmp_path):
    with pytest.raises(TraceError, match="does not exist"):
        read_trace(tmp_path / "none.txt")
    (tmp_path / "e.txt").write_text("")
    with pytest.raises(TraceError, match="empty"):
        read_trace(tmp_path / "e.txt")
    TraceWriter(tmp_path / "w.txt", [1, 2], {}).close("interrupted")
    tr = read_trace(tmp_path / "w.txt")
    assert tr.data.shape == (0, 2, 9) and tr.times.shape == (0,)


def test_crlf_file_reads(tmp_path):
    rows = [" 0.0;1;2;3;4;5;6;7;8;9", " 1.0;1;2;3;4;5;6;7;8;-9"]
    (tmp_path / "t.txt").write_bytes(("\r\n".join(rows) + "\r\n").encode())
    tr = read_trace(tmp_path / "t.txt")
    assert tr.data.shape == (2, 1, 9) and tr.data[1, 0, 8] == -9
