"""The documented slow fallback for user forces numba cannot compile (``--usrfrc-python``)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

from x3dpd.cli import _register, cli
from x3dpd.io.trace import read_trace

DECK = Path(__file__).resolve().parents[2] / "decks" / "appendix_a_cube.inp"

# A global dict: numba cannot compile a function that reads one.
PYTHON_ONLY = """
import math
DRIVE = {"amp": 4.84040e-3, "omega": 2.0 * math.pi * 37.21}

def usrfrc(time, coords, vels, force):
    force[NODE_INDEX[25], 0] += DRIVE["amp"] * math.sin(DRIVE["omega"] * time)
"""


def _run(tmp_path, *args, quiet=True):
    from click.testing import CliRunner

    _register()
    return CliRunner().invoke(
        cli, ["run", str(DECK), "--tmax", "0.002", *(["--quiet"] if quiet else []), *args]
    )


def test_uncompilable_force_is_refused_without_the_fallback(tmp_path):
    user = tmp_path / "force.py"
    user.write_text(PYTHON_ONLY)
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "x3dpd",
            "run",
            str(DECK),
            "--tmax",
            "0.002",
            "--usrfrc",
            str(user),
            "--trace",
            str(tmp_path / "a.txt"),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2, proc.stderr
    assert "force.py:6: numba cannot compile" in proc.stderr
    assert "--usrfrc-python" in proc.stderr and "Traceback" not in proc.stderr
    assert not (tmp_path / "a.txt").exists()  # nothing written


def test_fallback_runs_and_matches_the_builtin_force(tmp_path):
    user = tmp_path / "force.py"
    user.write_text(PYTHON_ONLY)
    slow = _run(
        tmp_path,
        "--usrfrc",
        str(user),
        "--usrfrc-python",
        "--trace",
        str(tmp_path / "slow.txt"),
        quiet=False,
    )
    assert slow.exit_code == 0, slow.output
    # the summary names the code the run executed (docs/usrfrc.md)
    assert f"code run       {user} (a USRFRC Python file" in slow.output
    fast = _run(
        tmp_path,
        "--usrfrc",
        "sine:node=25,dof=1,amp=4.84040e-3,hz=37.21",
        "--trace",
        str(tmp_path / "fast.txt"),
    )
    assert fast.exit_code == 0, fast.output
    a = read_trace(tmp_path / "slow.txt").node(25)[:, 0]
    b = read_trace(tmp_path / "fast.txt").node(25)[:, 0]
    # the fallback sees the force one step late (X3D's "coordinates at last time step"
    # convention for Python-side forces): the master's displacement, driven for 2 ms, differs
    # by O(dt/T) of its amplitude, here far below 1 %
    assert np.max(np.abs(a - b)) <= 1e-2 * np.max(np.abs(b))
    assert np.max(np.abs(b)) > 0.0


def test_check_names_the_code_file_a_run_would_execute(tmp_path):
    from click.testing import CliRunner

    user = tmp_path / "force.py"
    user.write_text(PYTHON_ONLY)
    _register()
    out = CliRunner().invoke(cli, ["check", str(DECK), "--usrfrc", str(user)]).output
    assert f"{user}: a USRFRC Python file -- running this deck executes it" in out
    plain = CliRunner().invoke(cli, ["check", str(DECK)]).output
    assert "code run" not in plain
