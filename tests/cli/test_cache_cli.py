"""``x3dpd cache``: the kernel cache's variants listed from its manifest, and cleared -- never
outside the cache's kernels/ folder, never without --yes (or a yes at the prompt), and a
missing or unreadable cache is one line, exit 2, nothing deleted (issue 32 item 3)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from cli_helpers import folder_state, refused, run_cli

from x3dpd.solver.variants import source_hash

STALE = "0123456789abcdef"
STEM = "advance_00011000000110000_0_regularized_none_lee_radok_"
OLD_STEM = "advance_10000000000000000_0_regularized_none_lee_radok_"


def _write(path: Path, size: int) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"x" * size)


@pytest.fixture
def cache(tmp_path) -> Path:
    """A kernel cache of these sources (one variant in its manifest, 10 000 bytes of its own
    files) and of older ones (one variant, no manifest: 3 000 bytes), the machine's compile-time
    log beside them, and a link to a folder outside the cache."""
    root = tmp_path / "cache"
    here = root / "kernels" / source_hash()
    _write(here / f"{STEM}.py", 1000)
    _write(here / f"{STEM}__pairs.py", 1000)
    _write(here / "__pycache__" / f"{STEM}.advance_packed-179.py311.nbi", 2000)
    _write(here / "__pycache__" / f"{STEM}.advance_packed-179.py311.1.nbc", 6000)
    entry = {
        "label": "walls+pairs+walls_translate+one_particle_kind",
        "effects": {"walls": True, "pairs": True},
        "compile_seconds": 12.3,
        "first_user": "x3dpd decks/beam_64.inp",
        "compiled": "2026-11-28T09:00:00+00:00",
        "last_compiled": "2026-11-28T09:00:00+00:00",
        "compiles": 1,
        "loads": 4,
        "last_loaded": "2026-11-28T10:00:00+00:00",
        "source_hash": source_hash(),
    }
    manifest = {"format": 1, "source_hash": source_hash(), "numba": "0.68.1"}
    (here / "manifest.json").write_text(json.dumps({**manifest, "variants": {STEM: entry}}))
    old = root / "kernels" / STALE
    _write(old / f"{OLD_STEM}.py", 1000)
    _write(old / "__pycache__" / f"{OLD_STEM}.advance_packed-170.py311.nbi", 2000)
    (root / "kernels" / "compile_times.json").write_text("[12.3]")
    outside = tmp_path / "outside"
    _write(outside / "keep.txt", 10)
    os.symlink(outside, root / "kernels" / "linked")
    return root


def test_the_listing_shows_each_variant_its_cost_size_and_the_total(cache, capsys):
    assert run_cli("cache", "--dir", cache) == 0
    out = capsys.readouterr().out
    assert f"kernel cache {cache} (--dir)" in out
    line = next(x for x in out.splitlines() if "walls+pairs+walls_translate" in x)
    assert "12.3" in line and "0.0 MB" in line and "2026-11-28" in line and "beam_64" in line
    assert f"sources {source_hash()} (this x3dpd's sources): 1 variant," in out
    assert f"sources {STALE} (other sources: stale): 1 variant" in out
    assert OLD_STEM not in out  # listed with --all only
    assert "total: 2 variants" in out and "12.3 s of compiling recorded" in out
    assert "1 not in a manifest" in out
    assert "shared kernels" in out
    assert run_cli("cache", "--dir", cache, "--all") == 0
    assert f"{OLD_STEM} (not in the manifest)" in capsys.readouterr().out


def test_the_json_listing_has_the_manifest_entries_and_sizes(cache, capsys):
    assert run_cli("cache", "--dir", cache, "--json") == 0
    data = json.loads(capsys.readouterr().out)
    assert data["source_hash"] == source_hash()
    here = next(f for f in data["folders"] if f["current"])
    (row,) = here["variants"]
    assert row["name"] == STEM and row["size"] == 10_000
    assert row["entry"]["compile_seconds"] == 12.3 and row["entry"]["loads"] == 4
    old = next(f for f in data["folders"] if not f["current"])
    assert old["variants"][0]["size"] == 3000 and old["variants"][0]["entry"] == {}


def test_the_env_var_selects_the_cache(cache, capsys, monkeypatch):
    monkeypatch.setenv("X3DPD_CACHE_DIR", str(cache))
    assert run_cli("cache") == 0
    assert f"kernel cache {cache} (X3DPD_CACHE_DIR)" in capsys.readouterr().out


def test_clear_asks_for_yes_and_deletes_nothing_without_it(cache, capsys):
    refused(capsys, "cache", "--dir", cache, "--clear", message="add --yes", folder=cache)


def test_clear_deletes_the_variants_and_nothing_else(cache, capsys, tmp_path):
    assert run_cli("cache", "--dir", cache, "--clear", "--yes") == 0
    assert "deleted 2 variants" in capsys.readouterr().out
    kernels = cache / "kernels"
    assert sorted(p.name for p in kernels.iterdir()) == ["compile_times.json"]
    assert (tmp_path / "outside" / "keep.txt").read_bytes() == b"x" * 10  # the link's target
    # an emptied cache lists as such
    assert run_cli("cache", "--dir", cache) == 0
    assert "nothing compiled yet" in capsys.readouterr().out


def test_clear_stale_keeps_these_sources(cache, capsys):
    assert run_cli("cache", "--dir", cache, "--clear", "--stale", "--yes") == 0
    left = sorted(p.name for p in (cache / "kernels").iterdir())
    assert left == sorted([source_hash(), "compile_times.json"])


@pytest.mark.parametrize(
    "args, message",
    [
        (["--stale"], "go with --clear"),
        (["--yes"], "go with --clear"),
        (["--clear", "--json", "--yes"], "does not go with --clear"),
    ],
)
def test_option_mistakes_are_one_line(cache, capsys, args, message):
    refused(capsys, "cache", "--dir", cache, *args, message=message, folder=cache)


def test_a_missing_or_foreign_or_damaged_cache_is_one_line_and_nothing_is_deleted(
    cache, capsys, tmp_path
):
    refused(capsys, "cache", "--dir", tmp_path / "nowhere", message="no kernel cache at")
    foreign = tmp_path / "home"
    _write(foreign / "thesis.tex", 100)
    for args in ([], ["--clear", "--yes"]):
        refused(
            capsys,
            "cache",
            "--dir",
            foreign,
            *args,
            message="is not an x3dpd kernel cache",
            folder=foreign,
        )
    (cache / "kernels" / source_hash() / "manifest.json").write_text("{damaged")
    for args in ([], ["--clear", "--yes"]):
        refused(capsys, "cache", "--dir", cache, *args, message="manifest", folder=cache)
    before = folder_state(cache)
    assert before  # the damaged cache is all still there


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads every folder")
def test_an_unreadable_cache_is_one_line(cache, capsys):
    (cache / "kernels").chmod(0)
    try:
        refused(capsys, "cache", "--dir", cache, message="permission denied")
    finally:
        (cache / "kernels").chmod(0o755)
