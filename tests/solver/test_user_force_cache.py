"""Step loops that call user force files are disk-cached per (file contents, node numbering).

A structure-only deck keeps the compiles short: one mass on a spring, driven by user files.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numba
import numpy as np
import pytest

from factories import sdof_deck

from x3dpd._jit import JIT_DISABLED
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation

pytestmark = pytest.mark.skipif(JIT_DISABLED, reason="caching needs numba's compiler")

DT = 5e-7
AMP, HZ = 4.84040e-3, 37.21

SINE = textwrap.dedent(f"""
    import math
    NODE_INDEX = None  # placeholder, as in decks/appendix_c.py


    def amplitude():
        return {AMP!r}


    def usrfrc(time, coords, vels, force):
        force[NODE_INDEX[1], 0] += amplitude() * math.sin(2.0 * math.pi * {HZ!r} * time)
""")


def _constant(value: float) -> str:
    return f"def usrfrc(time, coords, vels, force):\n    force[NODE_INDEX[1], 0] += {value!r}\n"


def _run(files, steps=2000):
    model = build_model(sdof_deck(dt=DT, hz=HZ, drive=0.0))
    sim = Simulation(model, usrfrc=[str(f) for f in files], itrac=steps)
    block = sim.advance(steps)
    return sim, block.data[-1, 0]


def _probe(user: Path, cache: Path) -> dict:
    """numba's cache hits and misses of the step loop in a fresh process running ``user``."""
    tests = str(Path(__file__).resolve().parents[1])  # the probe imports tests/factories.py
    env = {
        **os.environ,
        "X3DPD_CACHE_DIR": str(cache),
        "PYTHONPATH": os.pathsep.join(filter(None, [tests, os.environ.get("PYTHONPATH")])),
    }
    proc = subprocess.run(
        [sys.executable, "-c", PROBE.format(dt=DT, user=str(user))],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_a_user_force_step_loop_is_cached_and_matches_the_builtin(tmp_path, monkeypatch):
    monkeypatch.setenv("X3DPD_CACHE_DIR", str(tmp_path / "cache"))
    user = tmp_path / "force.py"
    user.write_text(SINE)
    sim, row = _run([user])
    assert isinstance(sim.kernels.advance_packed._cache, numba.core.caching.FunctionCache)
    assert sum(sim.kernels.advance_packed.stats.cache_misses.values()) >= 1  # compiled here
    copies = sorted(p.name for p in (tmp_path / "cache").rglob("usrfrc_*.py"))
    assert len(copies) == 1
    # a second process with the same file loads the compiled loop from disk: no compile
    probe = _probe(user, tmp_path / "cache")
    assert probe["hits"] >= 1 and probe["misses"] == 0, probe
    model = build_model(sdof_deck(dt=DT, hz=HZ, drive=AMP))  # the same force, built in
    ref = Simulation(model, itrac=2000).advance(2000).data[-1, 0]
    # the same force: the two may differ only in how the sine's argument is rounded
    assert np.allclose(row, ref, rtol=1e-9, atol=1e-15)
    assert abs(row[0]) > 0.0


@pytest.mark.validate  # compiles two user-file loops of their own (72 s warm on the 2-core
# machine since the loop grew): python -m pytest -m validate
def test_an_edited_file_gets_a_new_copy_and_its_new_force(tmp_path, monkeypatch):
    monkeypatch.setenv("X3DPD_CACHE_DIR", str(tmp_path / "cache"))
    user = tmp_path / "force.py"
    user.write_text(_constant(1e-3))
    _, one = _run([user], steps=200)
    user.write_text(_constant(2e-3))
    _, two = _run([user], steps=200)
    assert len(list((tmp_path / "cache").rglob("usrfrc_*.py"))) == 2
    # a constant force from rest: x grows as F t^2 / 2m at first -- twice the force, twice x
    assert two[0] == pytest.approx(2.0 * one[0], rel=1e-9)


@pytest.mark.validate  # compiles two user-file loops of their own (72 s warm on the 2-core
# machine since the loop grew): python -m pytest -m validate
def test_two_user_files_add_up_in_order(tmp_path, monkeypatch):
    monkeypatch.setenv("X3DPD_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "a.py").write_text(_constant(1e-3))
    (tmp_path / "b.py").write_text(_constant(2e-3))
    (tmp_path / "c.py").write_text(_constant(3e-3))
    _, both = _run([tmp_path / "a.py", tmp_path / "b.py"], steps=200)
    _, single = _run([tmp_path / "c.py"], steps=200)
    assert both[0] == pytest.approx(single[0], rel=1e-12)


PROBE = """
import json
from factories import sdof_deck
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation
sim = Simulation(build_model(sdof_deck(dt={dt!r}, hz=1.0, drive=0.0)), usrfrc=[{user!r}],
                 itrac=100)
sim.advance(100)
print(json.dumps({{"hits": sum(sim.kernels.advance_packed.stats.cache_hits.values()),
                  "misses": sum(sim.kernels.advance_packed.stats.cache_misses.values())}}))
"""
