"""The goldens' tolerance on another machine (tests/golden_compare.py), tested itself: it must
pass a replay whose arithmetic really differs as another CPU's does, fail a physical change
of 1e-4, and the solver's setup must not depend on the instruction set numpy picks.

Another CPU is emulated on this one the way its libraries see it: ``OPENBLAS_CORETYPE=Haswell``
makes OpenBLAS take the kernels of an AVX2 CPU, ``NPY_DISABLE_CPU_FEATURES=X86_V4`` makes numpy
take its AVX2 loops on an AVX-512 CPU (both read at import, so in a process of their own).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from golden_compare import ROOT, agree_across_machines, regen

from x3dpd.io.trace import read_trace

GOLDEN = ROOT / "tests" / "golden"
PROVENANCE = json.loads((GOLDEN / "PROVENANCE.json").read_text())["cases"]
CASES = {c["deck"]: c for c in regen.load_cases()}


def _avx2_environment() -> dict:
    """This process's environment with OpenBLAS and numpy on an AVX2 CPU's code paths."""
    from numpy._core._multiarray_umath import __cpu_features__

    env = dict(os.environ, OPENBLAS_CORETYPE="Haswell")
    if __cpu_features__.get("X86_V4"):
        env["NPY_DISABLE_CPU_FEATURES"] = "X86_V4"
    return env


def _replay(deck: str, trace: Path, *, env=None, deck_path: Path | None = None):
    case = dict(CASES[deck])
    argv = regen.case_argv(case, trace)
    if deck_path is not None:
        argv[0] = str(deck_path)
    res = subprocess.run(
        [sys.executable, "-m", "x3dpd", *argv],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert res.returncode == 0, res.stderr
    return read_trace(trace)


_RUN_AND_KEEP = """
import sys, numpy as np, x3dpd
result = x3dpd.run(sys.argv[1], tmax=float(sys.argv[2]), trace=sys.argv[3])
np.save(sys.argv[4], result.trace.data)
"""


def test_another_cpus_blas_replays_within_the_bound(tmp_path):
    """decks/beam_64_modal.inp on OpenBLAS's and numpy's AVX2 code paths: its modal
    coefficients differ in the last bit, so the run differs from this machine's at full
    precision (the emulation is real), yet its trace stays within the rounding bound of the
    golden over the compared window."""
    import x3dpd

    deck = "beam_64_modal.inp"
    tmax = CASES[deck]["tmax"]
    trace, data = tmp_path / "avx2.trace.txt", tmp_path / "avx2.npy"
    subprocess.run(
        [sys.executable, "-c", _RUN_AND_KEEP, f"decks/{deck}", repr(tmax), trace, data],
        cwd=ROOT,
        env=_avx2_environment(),
        check=True,
        timeout=900,
    )
    here = x3dpd.run(ROOT / "decks" / deck, tmax=tmax).trace.data
    assert not np.array_equal(np.load(data), here), "the emulated CPU computed the same bits"
    ok, text = agree_across_machines(
        read_trace(trace), read_trace(regen.golden_path(deck)), PROVENANCE[deck]
    )
    assert ok, text


def _changed_modulus(deck: str, tmp_path: Path, factor: float) -> Path:
    """A copy of the deck beside it (its mode files resolve) with PDMP E0 times ``factor``."""
    src = ROOT / "decks" / deck
    lines = src.read_text().split("\n")
    assert regen.changed_record(lines, "PDMP", lambda f: True, regen.PDMP_E0, lambda v: v * factor)
    copy = src.with_name(f".changed_{tmp_path.name}_{deck}")
    copy.write_text("\n".join(lines))
    return copy


@pytest.mark.parametrize("deck", ["beam_64.inp", "beam_64_modal.inp", "chassis_128.inp"])
def test_a_physical_change_fails_its_golden(deck, tmp_path):
    """The particles' modulus 1e-4 larger: a real physical change, far below what a plot shows,
    must fail the tolerance another machine gets."""
    copy = _changed_modulus(deck, tmp_path, 1.0 + 1e-4)
    try:
        a = _replay(deck, tmp_path / "changed.trace.txt", deck_path=copy.relative_to(ROOT))
    finally:
        copy.unlink()
    b = read_trace(regen.golden_path(deck))
    ok, text = agree_across_machines(a, b, PROVENANCE[deck])
    assert not ok, "a change of 1e-4 in E0 passed: " + text


_SETUP_ARRAYS = """
import dataclasses, sys, numpy as np
from x3dpd.deck import read_deck
from x3dpd.model.build import build_model
from x3dpd.solver.state import build_setup
model = build_model(read_deck(sys.argv[1]))
setup = build_setup(model, model.dt)
arrays = {f.name: getattr(setup, f.name) for f in dataclasses.fields(setup)}
np.savez(sys.argv[2], **{k: v for k, v in arrays.items() if isinstance(v, np.ndarray)})
"""


def test_the_solver_setup_does_not_depend_on_numpys_instruction_set(tmp_path):
    """Every array the step loop starts from, for every runnable shipped deck with contacts,
    is the same bits whether numpy runs its AVX-512 or its AVX2 loops (numpy's exp differs
    between them in the last bit: the Maxwell step factors once did)."""
    from numpy._core._multiarray_umath import __cpu_features__

    if not __cpu_features__.get("X86_V4"):
        pytest.skip("this CPU has no AVX-512 loops to compare numpy's AVX2 ones with")
    env = dict(os.environ, NPY_DISABLE_CPU_FEATURES="X86_V4")
    for deck in ("beam_64.inp", "beam_512.inp", "beam_64_modal.inp", "chassis_128.inp"):
        files = []
        for tag, e in (("here", None), ("avx2", env)):
            out = tmp_path / f"{tag}_{deck}.npz"
            subprocess.run(
                [sys.executable, "-c", _SETUP_ARRAYS, str(ROOT / "decks" / deck), str(out)],
                env=e,
                check=True,
                timeout=300,
            )
            files.append(np.load(out))
        here, avx2 = files
        differ = [k for k in here.files if not np.array_equal(here[k], avx2[k], equal_nan=True)]
        assert differ == [], f"{deck}: {differ} depend on numpy's instruction set"


def test_every_golden_has_its_rounding_envelope():
    for case in regen.load_cases():
        if case.get("refused"):
            continue
        prov = PROVENANCE[case["deck"]]
        assert len(prov["rounding_envelope"]) == prov["blocks"], case["deck"]
        assert len(prov["rounding_nudges"]) == len(regen.NUDGES), case["deck"]
