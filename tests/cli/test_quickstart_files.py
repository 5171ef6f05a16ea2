"""The README's quick start, ``x3dpd decks/beam_64.inp --tmax 0.05 --plot beam_64.png`` run in the
repository root, leaves no file that .gitignore does not cover (run here in a scratch git
repository with the project's .gitignore and deck, for a shorter time)."""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest
from cli_helpers import DECKS, ROOT, run_cli

GIT = shutil.which("git")


@pytest.mark.skipif(GIT is None, reason="needs git")
def test_quick_start_outputs_are_ignored(tmp_path, monkeypatch):
    (tmp_path / "decks").mkdir()
    shutil.copy(DECKS / "beam_64.inp", tmp_path / "decks" / "beam_64.inp")
    shutil.copy(ROOT / ".gitignore", tmp_path / ".gitignore")

    def git(*args):
        return subprocess.run(
            [GIT, "-c", "user.email=t@t", "-c", "user.name=t", *args],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            check=True,
        ).stdout

    git("init", "-q")
    git("add", "-A")
    git("commit", "-q", "-m", "scratch")
    monkeypatch.chdir(tmp_path)
    assert run_cli("decks/beam_64.inp", "--tmax", 0.002, "--plot", "beam_64.png", "--quiet") == 0
    made = sorted(os.listdir(tmp_path))
    assert "beam_64.png" in made and "beam_64.trace.txt.json" in made
    assert git("status", "--porcelain", "--untracked-files=all") == ""
