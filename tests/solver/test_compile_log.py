"""The compile-time log behind the compile-progress line's estimate (x3dpd.solver.compile_log)."""

from __future__ import annotations

import statistics

from x3dpd.solver import compile_log


def test_the_estimate_is_the_default_then_the_median_of_recorded_compiles(tmp_path, monkeypatch):
    monkeypatch.setenv("X3DPD_CACHE_DIR", str(tmp_path))
    assert compile_log.expected_compile_seconds() == compile_log.DEFAULT_SECONDS
    times = [31.0, 12.5, 18.25]
    for t in times:
        compile_log.record_compile_seconds(t)
    assert compile_log.recorded_compile_seconds() == times
    assert compile_log.expected_compile_seconds() == statistics.median(times)


def test_the_log_keeps_the_last_compiles_and_survives_a_corrupt_file(tmp_path, monkeypatch):
    monkeypatch.setenv("X3DPD_CACHE_DIR", str(tmp_path))
    for k in range(compile_log.KEEP + 5):
        compile_log.record_compile_seconds(float(k + 1))
    kept = compile_log.recorded_compile_seconds()
    assert kept == [float(k + 1) for k in range(5, compile_log.KEEP + 5)]
    compile_log._log_path().write_text("{not json")
    assert compile_log.expected_compile_seconds() == compile_log.DEFAULT_SECONDS
    compile_log.record_compile_seconds(7.0)  # starts a new log
    assert compile_log.recorded_compile_seconds() == [7.0]
