"""Nastran OP2 support is one documented install: the ``nastran`` extra brings cpylog (which
``pip install --no-deps pyNastran`` leaves out), and the install hint an OP2 read prints, the
MODAL docs and the extra agree; the docs say when an OP2 needs ``normalize=mass``."""

from __future__ import annotations

import tomllib
from pathlib import Path

from x3dpd.deck.modes.op2_format import INSTALL_HINT

ROOT = Path(__file__).resolve().parents[2]
COMMAND = 'pip install -e ".[nastran]" && pip install --no-deps pyNastran==1.4.1'


def test_the_nastran_extra_installs_cpylog_and_everyone_says_so():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    extras = project["optional-dependencies"]
    assert any(dep.startswith("cpylog") for dep in extras["nastran"])
    assert INSTALL_HINT.startswith(COMMAND)
    docs = (ROOT / "docs" / "deck-reference.md").read_text()
    assert COMMAND in docs
    op2 = docs[docs.index("### OP2") : docs.index("### UFF")]
    assert "NORM=MAX" in op2 and "normalize=mass" in op2
