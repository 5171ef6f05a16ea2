"""The code in docs/python-api.md runs as written (from the repository's root)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "python-api.md"
BLOCKS = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)


@pytest.mark.parametrize("code", BLOCKS, ids=[f"block{i}" for i in range(len(BLOCKS))])
def test_python_api_doc_example_runs(code, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    exec(compile(code, str(DOC), "exec"), {})
    out = capsys.readouterr().out
    if "dissipated_friction" in code:
        assert "of the drive's work" in out and "replaced: ['sine:node=9" in out
        assert "0.05 -> 0.1 s complete" in out
