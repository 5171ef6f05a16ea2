"""Every shipped deck: generated as tools/make_decks.py says, checked, and replayed against a
committed golden trace.

How a replay is compared with its golden, on this machine and on another one:
tests/golden_compare.py.

When a change is *meant* to change results, regenerate with ``python tools/regen_goldens.py``
(docs/running.md); tests/golden/PROVENANCE.json records version, commit, date and machine.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from golden_compare import ATOL, RTOL, agree_across_machines, regen, same_machine, tool

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


CASES = regen.load_cases()
SHIPPED = sorted(p.name for p in DECKS.glob("*.inp"))


def test_every_shipped_deck_has_a_case():
    assert sorted(c["deck"] for c in CASES) == SHIPPED


def test_generated_decks_are_up_to_date():
    """decks/beam_*.inp and decks/impact_wall.inp are exactly what tools/make_decks.py writes."""
    make = tool("make_decks")
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
        "mip_apparatus_05.inp",
        "mip_apparatus_025.inp",
        "mip_engine.inp",
        "capsule_wc7.inp",
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
    if same_machine(prov):
        assert report.agree, report.format()
    else:
        ok, text = agree_across_machines(a, b, prov)
        assert ok, report.format() + "\n" + text
    assert os.path.getsize(trace.with_name(trace.name[: -len(".trace.txt")] + ".energy.csv")) > 0
