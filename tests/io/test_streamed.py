"""The shared rules of streamed output files: never clobber, resume by checked truncation."""

from __future__ import annotations

import pytest

from x3dpd.io._streamed import create_new, reopen_at


class Boom(Exception):
    pass


def test_existing_file_is_refused_then_kept_as_bak_with_its_companion(tmp_path):
    path, side = tmp_path / "t.txt", tmp_path / "t.txt.json"
    path.write_text("old")
    side.write_text("{old}")
    with pytest.raises(Boom, match="already exists.*--overwrite.*another --trace path"):
        create_new(str(path), overwrite=False, error=Boom, what="trace file", option="--trace")
    assert path.read_text() == "old"
    with create_new(
        str(path),
        overwrite=True,
        error=Boom,
        what="trace file",
        option="--trace",
        companions=[(str(side), str(path) + ".bak.json")],
    ) as f:
        f.write(b"new")
    assert path.read_text() == "new"
    assert (tmp_path / "t.txt.bak").read_text() == "old"
    assert (tmp_path / "t.txt.bak.json").read_text() == "{old}" and not side.exists()


def test_a_stale_companion_backup_is_removed(tmp_path):
    path = tmp_path / "t.txt"
    path.write_text("old")
    (tmp_path / "t.txt.bak.json").write_text("describes an older file")
    create_new(
        str(path),
        overwrite=True,
        error=Boom,
        what="trace file",
        option="--trace",
        companions=[(str(tmp_path / "t.txt.json"), str(path) + ".bak.json")],
    ).close()
    assert not (tmp_path / "t.txt.bak.json").exists()


def test_a_directory_is_never_moved(tmp_path):
    with pytest.raises(Boom, match="is a directory"):
        create_new(str(tmp_path), overwrite=True, error=Boom, what="energy file", option="--energy")
    assert tmp_path.is_dir()


def test_reopen_cuts_after_the_checked_prefix(tmp_path):
    path = tmp_path / "e.csv"
    path.write_bytes(b"h\n1\n2\n3\n")
    seen = []
    with reopen_at(
        str(path), 4, error=Boom, what="energy file", check=lambda f: seen.append(f.read(4))
    ) as f:
        f.write(b"9\n")
    assert seen == [b"h\n1\n"] and path.read_bytes() == b"h\n1\n9\n"


def test_a_failed_check_leaves_the_file_whole_and_closed(tmp_path):
    path = tmp_path / "e.csv"
    path.write_bytes(b"h\n1\n2\n")
    opened = []

    def check(f):
        opened.append(f)
        raise Boom("not this file")

    with pytest.raises(Boom, match="not this file"):
        reopen_at(str(path), 2, error=Boom, what="energy file", check=check)
    assert opened[0].closed and path.read_bytes() == b"h\n1\n2\n"
    with pytest.raises(Boom, match="cannot open energy file .* to resume"):
        reopen_at(
            str(tmp_path / "missing.csv"), 0, error=Boom, what="energy file", check=lambda f: None
        )
