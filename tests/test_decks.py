"""Every shipped deck: generated as tools/make_decks.py says, checked, and replayed against a
committed golden trace.

Golden tolerances
-----------------
A run is deterministic on one machine type: the step loop is single-threaded, sums forces in a
fixed order (contact lists are kept in a fixed order and restored as saved), and is compiled
with ``fastmath`` off (x3dpd/_jit.py), so the same build on the same CPU reproduces a golden bit
for bit; the 10-digit trace text then matches exactly. Across machines, libm's ``exp``, ``sin``,
``pow`` and ``sqrt``-based Hertz terms may differ in the last bit, so the comparison allows
``rtol = 1e-9`` (``|a - b| <= atol + rtol |b|``, the ``numpy.isclose`` rule) and ``atol = 1e-12``
trace units (in, in/s, rad/s: far below anything physical, it only absorbs round-off noise
around values that are zero in exact arithmetic, such as the z velocities of particles that
never touched a z wall).

Particle motion is chaotic: a last-bit difference grows roughly like ``exp(lambda t)`` through
the contacts, so the goldens are short (0.01-0.02 s of simulated time for the beam decks, the
full 1.2e-5 s impact of decks/impact_wall.inp, one at a time under ~10 s of wall time once the
step loop is compiled). A long golden could only be compared statistically.

When a change is *meant* to change results, regenerate with ``python tools/regen_goldens.py``
(docs/running.md); tests/golden/PROVENANCE.json records version, commit, date and machine.
"""

from __future__ import annotations

import importlib.util
import json
import os
from pathlib import Path

import numpy as np
import pytest

from x3dpd.cli import main
from x3dpd.api.outputs import deck_key
from x3dpd.deck import read_deck
from x3dpd.io.trace import read_trace
from x3dpd.io.tracediff import compare_traces
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model

ROOT = Path(__file__).resolve().parents[1]
DECKS = ROOT / "decks"
GOLDEN = ROOT / "tests" / "golden"
RTOL = 1e-9
ATOL = 1e-12
CROSS_CPU_TOL = 1e-6  # of each column's largest |value|; see _agree_across_cpus


def _tool(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "tools" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


regen = _tool("regen_goldens")
CASES = regen.load_cases()
SHIPPED = sorted(p.name for p in DECKS.glob("*.inp"))


def test_every_shipped_deck_has_a_case():
    assert sorted(c["deck"] for c in CASES) == SHIPPED


def test_generated_decks_are_up_to_date():
    """decks/beam_*.inp and decks/impact_wall.inp are exactly what tools/make_decks.py writes."""
    make = _tool("make_decks")
    for name, text in make.all_decks().items():
        assert (DECKS / name).read_text() == text, (
            f"decks/{name} differs from tools/make_decks.py; rerun it"
        )


def test_shipped_decks_carry_a_provenance_header():
    for name in SHIPPED:
        first = (DECKS / name).read_text().splitlines()[0]
        assert first.startswith("$"), f"decks/{name} does not start with a $ comment header"


@pytest.mark.parametrize(
    "name",
    [
        "beam_1.inp",
        "beam_64.inp",
        "beam_512.inp",
        "cylinder_64.inp",
        "capsule_64.inp",
        "impact_wall.inp",
        "appendix_a_cube.inp",
        "beam_64_modal.inp",
        "chassis_128.inp",
        "shaker_fig9.inp",
    ],
)
def test_check_is_clean(name):
    """`x3dpd check` finds nothing to warn about in the runnable decks (exit 0). beam_512 runs
    at half the report's step for that: at 5e-7 s its wall impacts last 4.75 steps."""
    model = build_model(read_deck(DECKS / name))
    report = check_model(model)
    assert not report.errors
    assert [w.code for w in report.warnings] == [], [w.headline for w in report.warnings]
    assert report.exit_status == 0


def test_printed_appendix_a_is_flagged_by_check():
    model = build_model(read_deck(DECKS / "appendix_a.inp"))
    codes = {w.code for w in check_model(model).warnings}
    assert {"particles-outside", "wall-penetration"} <= codes


def _run(capsys, argv):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    out, err = capsys.readouterr()
    return exc.value.code or 0, out, err


def _agree_across_cpus(a, b, report) -> None:
    """A golden made on another CPU: glibc's math (FMA variants of sin, exp ...) and LLVM's
    code for another CPU round differently, and the chaos of many contacts amplifies that by
    about 10x per simulated millisecond (beam_64: 1e-12 of a column's scale at 8 ms, 1e-3 at
    20 ms). What does not depend on rounding: the structure's nodes over the whole window (they
    integrate the particles' forces: 2e-8 of their scale between znver4 and znver5 builds) and
    every node over the window's first quarter (below 1e-9). A physical change moves either by
    far more than CROSS_CPU_TOL."""
    scale = np.maximum(np.abs(b.data).max(axis=(0, 1)), 1e-300)
    rel = np.abs(a.data - b.data) / scale
    structure = ~np.isin(a.node_ids, _particle_ids(a))
    quarter = a.times <= a.times[0] + 0.25 * (a.times[-1] - a.times[0])
    worst_structure = rel[:, structure].max(initial=0.0)
    worst_early = rel[quarter].max(initial=0.0)
    assert worst_structure <= CROSS_CPU_TOL and worst_early <= CROSS_CPU_TOL, (
        report.format() + f"\n(golden from another CPU) structure nodes differ by "
        f"{worst_structure:.3g}, all nodes in the first quarter by {worst_early:.3g} of the "
        f"column scale (tolerance {CROSS_CPU_TOL:g})"
    )


def _particle_ids(trace) -> np.ndarray:
    deck = read_deck(ROOT / trace.meta["deck_path"]) if trace.meta.get("deck_path") else None
    if deck is None:
        return np.zeros(0, np.int64)
    model = build_model(deck)
    return model.node_ids[model.particle_start :]


@pytest.mark.parametrize("case", CASES, ids=[c["deck"] for c in CASES])
def test_replay_matches_golden(case, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    trace = tmp_path / (Path(case["deck"]).stem + ".trace.txt")
    code, out, err = _run(capsys, regen.case_argv(case, trace))
    if case.get("refused"):
        # the report's printed Appendix A deck: walls through the particle cloud
        assert code == 2, err
        assert "deep in wall triangle" in err and "decks/appendix_a_cube.inp" in err
        assert not trace.exists()
        return
    assert code == 0, err
    golden = regen.golden_path(case["deck"])
    assert golden.is_file(), f"no golden for {case['deck']}: run tools/regen_goldens.py"
    prov = json.loads((GOLDEN / "PROVENANCE.json").read_text())["cases"][case["deck"]]
    assert prov["deck_key"] == deck_key(read_deck(DECKS / case["deck"])), (
        f"the cards of decks/{case['deck']} changed since its golden was made: if that is "
        f"intended, run tools/regen_goldens.py {case['deck']}"
    )
    a, b = read_trace(trace), read_trace(golden)
    assert a.times.size == b.times.size and a.status == "complete"
    report = compare_traces(a, b, rtol=RTOL, atol=ATOL)
    if prov["machine"].get("llvm_cpu") == regen.llvm_cpu():
        assert report.agree, report.format()
    else:
        _agree_across_cpus(a, b, report)
    assert os.path.getsize(trace.with_name(trace.name[: -len(".trace.txt")] + ".energy.csv")) > 0
