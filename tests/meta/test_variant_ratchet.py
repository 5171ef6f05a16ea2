"""The suite's step-loop variants: the committed list (tests/meta/variants.txt), the ratchet
that holds a run to it, and ``@pytest.mark.rides`` (tests/variant_report.py; issue 32 item 3).

The list is checked here for form (every line a Variant label in canonical form, sorted, no
duplicate), the shared loops of tests/factories.py against it, and the plugin end to end: a
pytest session in a subprocess, on tests written here, whose "compiles" are lines appended to
the session's event file, must fail on an unlisted variant and name it, pass when it is
listed, and fail a test that rides another loop than it declares.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import variant_report

import factories
from x3dpd.solver.variants import Variant

TESTS = Path(__file__).resolve().parents[1]
ROOT = TESTS.parent


def test_the_variant_list_holds_canonical_labels_sorted_once_each():
    labels = variant_report.listed_variants(variant_report.VARIANT_LIST)
    assert labels, "tests/meta/variants.txt lists no variant"
    for label in labels:
        assert Variant.from_label(label).label() == label
    assert labels == sorted(labels), "keep tests/meta/variants.txt sorted (reviewable diffs)"
    assert len(set(labels)) == len(labels)


def test_the_shared_loops_of_the_factories_are_listed():
    listed = set(variant_report.listed_variants(variant_report.VARIANT_LIST))
    shared = factories.shared_loops()
    assert shared
    for label in shared:
        assert Variant.from_label(label).label() == label
    assert not set(shared) - listed, sorted(set(shared) - listed)


def test_listing_summarising_and_the_subset_rule(tmp_path):
    path = tmp_path / "variants.txt"
    path.write_text("# a comment\nwalls+pairs  # the box\n\nsprings\n")
    assert variant_report.listed_variants(path) == ["walls+pairs", "springs"]
    events = [
        {"event": "compiled", "label": "walls+pairs", "seconds": 3.0, "user": "a"},
        {"event": "loaded", "label": "springs", "seconds": None, "user": "b"},
        {"event": "compiled", "label": "modal", "seconds": 9.0, "user": "c"},
        {"event": "loaded", "label": "modal", "seconds": None, "user": "d"},
    ]
    summary = variant_report.summarise(events)
    assert set(summary["compiled"]) == {"walls+pairs", "modal"}
    assert summary["loaded"] == {"springs", "modal"}
    assert summary["used"] == {"walls+pairs", "springs", "modal"}
    assert summary["first"]["modal"]["user"] == "c"
    # a subset of the list passes whatever part of the suite ran; one more variant fails
    assert variant_report.unlisted({"springs"}, ["walls+pairs", "springs"]) == []
    assert variant_report.unlisted(summary["used"], ["walls+pairs", "springs"]) == ["modal"]


SYNTHETIC = """
import json
import os

import pytest

from x3dpd.solver import kernel_cache


def _event(label, seconds):
    line = {"event": "compiled", "name": "advance_synthetic", "label": label,
            "seconds": seconds, "cache": os.environ["X3DPD_CACHE_DIR"], "user": "synthetic",
            "pid": os.getpid(), "time": "now"}
    with open(os.environ["X3DPD_COMPILE_EVENTS"], "a") as f:
        f.write(json.dumps(line) + "\\n")


def test_compiles_a_loop():
    assert os.environ["X3DPD_CACHE_DIR"].endswith(os.path.join(".pytest_cache", "x3dpd-kernels"))
    _event("walls+modal", 12.5)


@pytest.mark.rides("walls+pairs")
def test_rides_what_it_declares():
    kernel_cache._RUN_HERE.append("walls+pairs")


@pytest.mark.rides("walls+pairs")
def test_rides_another_loop():
    kernel_cache._RUN_HERE.append("walls+modal")
"""


def _session(tmp_path: Path, listed: str, *args: str) -> subprocess.CompletedProcess:
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    (tmp_path / "test_synthetic.py").write_text(textwrap.dedent(SYNTHETIC))
    (tmp_path / "variants.txt").write_text(listed)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("X3DPD_", "PYTEST_"))}
    env["X3DPD_VARIANT_LIST"] = str(tmp_path / "variants.txt")
    env["PYTHONPATH"] = os.pathsep.join(
        filter(None, [str(TESTS), str(ROOT), env.get("PYTHONPATH")])
    )
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "variant_report", "-q", "-rf", *args],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_an_unlisted_variant_fails_the_session_and_is_named(tmp_path):
    """Two xdist workers: the controller reads what both appended, prints the compile, fails
    the session on the unlisted variant, names it and says how to add it; the test that rode
    another loop than it declared fails, naming it."""
    out = _session(tmp_path, "walls+pairs\n", "-n", "2", "-p", "xdist")
    text = out.stdout + out.stderr
    assert out.returncode == 1, text
    assert "12.5 s  walls+modal" in text
    assert "does not list" in text and "  walls+modal   (compiled by synthetic)" in text
    assert "tests/factories.py" in text and "in the same commit" in text
    assert "FAILED test_synthetic.py::test_rides_another_loop" in text
    assert "ran 'walls+modal'; its scene no longer rides" in text
    assert "test_rides_what_it_declares" not in text.split("short test summary")[-1]
    assert (tmp_path / ".pytest_cache" / "x3dpd-kernels").parent.is_dir()


def test_a_listed_variant_passes_and_the_rule_holds_for_a_subset(tmp_path):
    out = _session(tmp_path, "walls+modal\nwalls+pairs\n", "-k", "compiles or declares")
    text = out.stdout + out.stderr
    assert out.returncode == 0, text
    assert "1 variants used, all listed" in text and "1 listed variants not used" in text


def test_the_ratchet_reports_but_does_not_fail_runs_of_other_markers(tmp_path):
    out = _session(tmp_path, "walls+pairs\n", "-k", "compiles", "-m", "validate or not validate")
    text = out.stdout + out.stderr
    assert out.returncode == 0, text
    assert "not applied" in text and "walls+modal" in text


@pytest.mark.parametrize("label", ["walls+bogus", "pairs+walls"])
def test_a_rides_label_that_is_not_a_variant_is_refused(label):
    with pytest.raises(ValueError):
        Variant.from_label(label)


def test_the_event_file_is_read_line_by_line(tmp_path):
    from x3dpd.solver.kernel_cache import read_events

    path = tmp_path / "events.jsonl"
    good = {"event": "loaded", "label": "springs"}
    path.write_text(json.dumps(good) + "\n{half a line\n" + json.dumps({"event": "x"}) + "\n")
    assert read_events(path) == [good]
    assert read_events(tmp_path / "missing.jsonl") == []
