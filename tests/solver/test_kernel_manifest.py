"""The kernel cache's manifest (x3dpd.solver.kernel_cache; issue 32 item 3): a Simulation's
first kernel calls book its loop there -- label, effects, compile seconds, first user, dates --
from numba's own count of cache misses and hits; two processes writing at once keep both
entries; a damaged manifest is started anew by the next writer."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import types
from collections import Counter
from dataclasses import asdict
from pathlib import Path

import pytest

from x3dpd.solver import kernel_cache, variants
from x3dpd.solver.kernel_cache import (
    first_user,
    read_manifest,
    record,
    record_unwatched,
    update_manifest,
    watch_first_calls,
)
from x3dpd.solver.variants import Variant

ROOT = Path(__file__).resolve().parents[2]


def test_a_run_books_its_loop_in_the_manifest_of_its_cache():
    """decks/hooke_wall.inp's loop, in the suite's cache: compiled here (with its seconds) or
    by an earlier test or run (then loaded: counted), under the loop's label and effects."""
    from x3dpd.api import build
    from x3dpd.solver.simulation import Simulation

    sim = Simulation(build(ROOT / "decks" / "hooke_wall.inp"))
    sim.initialize()
    folder = variants.cache_dir()
    entry = read_manifest(folder)["variants"][sim.variant.name()]
    assert (
        entry["label"]
        == sim.variant.label()
        == "walls+walls_translate+normal_law=hooke+one_wall_kind"
    )
    assert entry["effects"] == asdict(sim.variant)
    assert entry["source_hash"] == folder.name == variants.source_hash()
    assert entry["compiles"] >= 1 or entry["loads"] >= 1
    if entry["compiles"]:
        assert entry["compile_seconds"] > 0 and entry["compiled"] and entry["first_user"]
    assert kernel_cache.loops_run_here()[-1] == sim.variant.label()


@pytest.fixture
def fake_loop(tmp_path, monkeypatch):
    """A generated loop module stand-in registered as variants.make_advance registers one: its
    ``advance_packed`` counts cache hits and misses as numba's dispatcher does."""
    name, stem = "x3dpd_kernels_test_fake", "advance_fake_stem"
    module = types.ModuleType(name)
    module.__file__ = str(tmp_path / f"{stem}.py")
    module.advance_packed = types.SimpleNamespace(
        stats=types.SimpleNamespace(cache_hits=Counter(), cache_misses=Counter()), overloads={}
    )
    monkeypatch.setitem(sys.modules, name, module)
    monkeypatch.setitem(variants._VARIANT_OF, name, (Variant(walls=True, pairs=True), stem))
    monkeypatch.delitem(kernel_cache._RECORDED, name, raising=False)
    events = tmp_path / "events.jsonl"
    monkeypatch.setenv(kernel_cache.EVENTS_ENV, str(events))
    return name, stem, module, events


def test_a_compile_then_a_load_then_a_recompile(fake_loop, tmp_path):
    name, stem, module, events = fake_loop
    stats = module.advance_packed.stats
    with watch_first_calls(tmp_path, name):
        stats.cache_misses["sig"] += 1  # numba compiled the loop
        module.advance_packed.overloads["sig"] = object()
    entry = read_manifest(tmp_path)["variants"][stem]
    assert entry["label"] == "walls+pairs" and entry["effects"]["pairs"] is True
    assert entry["compiles"] == 1 and entry["loads"] == 0 and entry["compile_seconds"] >= 0.0
    assert (
        entry["compiled"] == entry["last_compiled"]
        and "test_kernel_manifest" in entry["first_user"]
    )
    first, seconds = entry["compiled"], entry["compile_seconds"]
    assert entry["compile_seconds_total"] == seconds
    record(tmp_path, name, "loaded", None)
    record(tmp_path, name, "compiled", 7.256)  # compiled again (another signature, a lost file)
    entry = read_manifest(tmp_path)["variants"][stem]
    assert entry["loads"] == 1 and entry["last_loaded"]
    assert entry["compiles"] == 2 and entry["compile_seconds"] == seconds
    assert entry["compile_seconds_total"] == round(seconds + 7.26, 2)
    assert entry["compiled"] == first  # the first compile's date and user stay
    lines = [json.loads(x) for x in events.read_text().splitlines()]
    assert [e["event"] for e in lines] == ["compiled", "loaded", "compiled"]
    assert {e["label"] for e in lines} == {"walls+pairs"}


def test_first_calls_that_compiled_nothing_book_nothing(fake_loop, tmp_path):
    name, stem, module, events = fake_loop
    with watch_first_calls(tmp_path, name):
        pass  # the loop was already in the process
    assert not (tmp_path / "manifest.json").exists() and not events.exists()
    with pytest.raises(RuntimeError):  # a compile that failed: a miss, no machine code
        with watch_first_calls(tmp_path, name):
            module.advance_packed.stats.cache_misses["sig"] += 1
            raise RuntimeError("typing error")
    assert not (tmp_path / "manifest.json").exists()


def test_a_load_outside_the_first_calls_is_booked_at_exit(fake_loop, tmp_path):
    name, stem, module, events = fake_loop
    module.advance_packed.stats.cache_hits["sig"] += 1
    module.advance_packed.overloads["sig"] = object()
    record_unwatched()
    record_unwatched()  # once
    entry = read_manifest(tmp_path)["variants"][stem]
    assert entry["loads"] == 1 and entry["compiles"] == 0


def test_a_damaged_manifest_is_started_anew(fake_loop, tmp_path):
    name, stem, module, events = fake_loop
    (tmp_path / "manifest.json").write_text("{not json")
    with pytest.raises(kernel_cache.CacheError):
        read_manifest(tmp_path)
    record(tmp_path, name, "loaded", None)
    assert list(read_manifest(tmp_path)["variants"]) == [stem]


_WRITER = textwrap.dedent("""
    import sys
    from x3dpd.solver.kernel_cache import update_manifest
    folder, tag = sys.argv[1], sys.argv[2]
    for k in range(40):
        update_manifest(folder, lambda d: d["variants"].__setitem__(f"{tag}{k}", {"k": k}))
""")


def test_two_processes_writing_at_once_keep_every_entry(tmp_path):
    env_path = str(ROOT)
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", _WRITER, str(tmp_path), tag],
            env={"PYTHONPATH": env_path, "PATH": "/usr/bin:/bin"},
        )
        for tag in ("a", "b")
    ]
    assert [p.wait(timeout=300) for p in procs] == [0, 0]
    names = set(read_manifest(tmp_path)["variants"])
    assert names == {f"{t}{k}" for t in "ab" for k in range(40)}
    assert not list(tmp_path.glob("*.tmp*"))  # every temporary file renamed over it
    update_manifest(tmp_path, lambda d: None)
    assert len(read_manifest(tmp_path)["variants"]) == 80


def test_the_first_user_is_the_command_or_the_test(monkeypatch):
    monkeypatch.delenv("PYTEST_CURRENT_TEST", raising=False)
    monkeypatch.setattr(sys, "argv", ["/venv/bin/x3dpd", "decks/beam_64.inp", "--tmax", "0.05"])
    assert first_user() == "x3dpd decks/beam_64.inp --tmax 0.05"
    monkeypatch.setattr(sys, "argv", ["/src/x3dpd/__main__.py", "my deck.inp"])
    assert first_user() == "python -m x3dpd 'my deck.inp'"
    monkeypatch.setenv("PYTEST_CURRENT_TEST", "tests/a/test_b.py::test_c (call)")
    assert first_user() == "tests/a/test_b.py::test_c"
    monkeypatch.setattr(sys, "argv", ["x" * 300])
    assert len(first_user()) <= 200
