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

import pytest

from x3dpd.cli import main
from x3dpd.deck import read_deck
from x3dpd.io.trace import read_trace, sha256_file
from x3dpd.io.tracediff import compare_traces
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model

ROOT = Path(__file__).resolve().parents[1]
DECKS = ROOT / "decks"
GOLDEN = ROOT / "tests" / "golden"
RTOL = 1e-9
ATOL = 1e-12


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
            f"decks/{name} differs from tools/make_decks.py; rerun it")


def test_shipped_decks_carry_a_provenance_header():
    for name in SHIPPED:
        first = (DECKS / name).read_text().splitlines()[0]
        assert first.startswith("$"), f"decks/{name} does not start with a $ comment header"


@pytest.mark.parametrize("name", ["beam_1.inp", "beam_64.inp", "beam_512.inp",
                                  "impact_wall.inp", "appendix_a_cube.inp"])
def test_check_is_clean_but_for_the_reports_time_step(name):
    """`x3dpd check` finds nothing wrong with the geometry of the runnable decks. Its one
    remaining warning on the beam decks is the time step: it wants 50 steps per Hertz contact,
    and the report's DT = 5e-7 s gives 38 (beam_1), 9.5 (beam_64, appendix_a_cube) and 4.75
    (beam_512) at its characteristic impact speed. The decks keep the report's step."""
    model = build_model(read_deck(DECKS / name))
    report = check_model(model)
    kinds = [w.code for w in report.warnings]
    assert not report.errors
    if name == "impact_wall.inp":
        assert kinds == []
    else:
        assert kinds == ["time-step"]
        assert report.time_step.dt_deck == 5e-7


def _run(capsys, argv):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    out, err = capsys.readouterr()
    return exc.value.code or 0, out, err


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
    ref_meta = json.loads(Path(str(golden) + ".json").read_text())
    assert ref_meta["deck_sha256"] == sha256_file(DECKS / case["deck"]), (
        f"decks/{case['deck']} changed since its golden was made: if that is intended, run "
        f"tools/regen_goldens.py {case['deck']}")
    a, b = read_trace(trace), read_trace(golden)
    assert a.times.size == b.times.size and a.status == "complete"
    report = compare_traces(a, b, rtol=RTOL, atol=ATOL)
    assert report.agree, report.format()
    assert os.path.getsize(trace.with_name(trace.name[:-len(".trace.txt")] + ".energy.csv")) > 0
