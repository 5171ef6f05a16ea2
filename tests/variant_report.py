"""The test suite's kernel cache, its compile report and its variant ratchet (issue 32 item 3;
docs/running.md, "The test suite's kernel cache"). A pytest plugin: tests/conftest.py imports
its hooks; ``python -m pytest -p variant_report`` loads it alone
(tests/meta/test_variant_ratchet.py).

* **The suite's own cache.** Unless ``X3DPD_CACHE_DIR`` is set, the session sets it to
  ``<rootdir>/.pytest_cache/x3dpd-kernels`` (:func:`suite_cache`), inherited by pytest-xdist's
  workers and every process a test starts: the suite never writes into the user's
  ``~/.cache/x3dpd``, and a second run of the same checkout loads what the first compiled.
  It is beside pytest's own cache, not in it (``--cache-clear`` does not empty it: a cold run
  takes minutes); ``x3dpd cache --dir .pytest_cache/x3dpd-kernels --clear --yes`` does.
* **The report.** Every compile or load of a step loop in the session, in any process and any
  cache (a test's own temporary one too), is appended to one file (``X3DPD_COMPILE_EVENTS``,
  x3dpd.solver.kernel_cache.record); at the end the controller prints the variants compiled
  with their compile seconds, and how many were loaded from the cache.
* **The ratchet.** Every variant the session ran must be listed in ``tests/meta/variants.txt``
  (:data:`VARIANT_LIST`; ``X3DPD_VARIANT_LIST`` names another): a variant the list lacks fails
  the session, named, with how to add it. It checks that the variants run are a subset of the
  list, so it holds for any subset of the suite (``-k``, one file); it applies to runs of the
  default suite's markers (not to ``-m validate``, whose long validations may run their own
  loops). A listed variant that a run did not use is reported, never a failure (a subset or
  a skipped test uses fewer).
* **rides.** ``@pytest.mark.rides(LABEL, ...)`` declares the step loops (Variant.label) a
  test's Simulations run -- a scene shaped to share a loop (a spectator sphere, a far floor:
  tests/factories.py) says which; the test fails if its setup or body runs any other in the
  test's process (a loop run by a subprocess the test starts is not seen).
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

import pytest

from x3dpd.solver.kernel_cache import EVENTS_ENV, loops_run_here, read_events
from x3dpd.solver.variants import Variant

#: The default suite's step-loop variants, one Variant.label a line (``#`` comments).
VARIANT_LIST = Path(__file__).resolve().with_name("meta") / "variants.txt"
LIST_ENV = "X3DPD_VARIANT_LIST"
_RIDES_START = pytest.StashKey[int]()


def suite_cache(config) -> Path:
    """``.pytest_cache/x3dpd-kernels`` in the rootdir (pytest's ``cache_dir`` setting)."""
    return (config.rootpath / config.getini("cache_dir") / "x3dpd-kernels").resolve()


def variant_list() -> Path:
    return Path(os.environ.get(LIST_ENV) or VARIANT_LIST)


def listed_variants(path: Path) -> list[str]:
    """The labels of a variant list: one a line, ``#`` starts a comment."""
    out = []
    for line in Path(path).read_text().splitlines():
        label = line.split("#", 1)[0].strip()
        if label:
            out.append(label)
    return out


def summarise(events: list[dict]) -> dict:
    """The session's compiles and loads: ``compiled`` {label: [events]} (each compile,
    whichever cache), ``loaded`` {label}, ``used`` {label} (both kinds) and ``first`` {label:
    the first event}."""
    compiled: dict[str, list[dict]] = {}
    loaded: set[str] = set()
    first: dict[str, dict] = {}
    for e in events:
        first.setdefault(e["label"], e)
        if e["event"] == "compiled":
            compiled.setdefault(e["label"], []).append(e)
        else:
            loaded.add(e["label"])
    return {"compiled": compiled, "loaded": loaded, "used": set(compiled) | loaded, "first": first}


def unlisted(used, listed) -> list[str]:
    """The variants used that the list lacks, sorted: what fails the ratchet."""
    return sorted(set(used) - set(listed))


def ratchet_applies(config) -> bool:
    """Whether the run selects the default suite's markers: the ``-m`` expression
    (``not validate`` in pyproject.toml) deselects the ``validate`` tests."""
    expr = config.getoption("markexpr", "") or ""
    if not expr.strip():
        return True
    from _pytest.mark.expression import Expression

    return not Expression.compile(expr).evaluate(lambda name, **kwargs: name == "validate")


def _is_worker(config) -> bool:
    return hasattr(config, "workerinput")


def pytest_configure(config):
    config.addinivalue_line(
        "markers",
        "rides(label, ...): the step-loop variants (x3dpd Variant.label) this test's "
        "Simulations run; the test fails when it runs another (tests/variant_report.py)",
    )
    if _is_worker(config):
        return  # the controller's environment, inherited
    if not os.environ.get("X3DPD_CACHE_DIR"):
        os.environ["X3DPD_CACHE_DIR"] = str(suite_cache(config))
    fd, path = tempfile.mkstemp(prefix="x3dpd-compile-events-", suffix=".jsonl")
    os.close(fd)
    os.environ[EVENTS_ENV] = path
    config._x3dpd_events = path


def pytest_sessionfinish(session, exitstatus):
    config = session.config
    path = getattr(config, "_x3dpd_events", None)
    if path is None:
        return
    summary = summarise(read_events(Path(path)))
    with contextlib.suppress(OSError):
        os.unlink(path)
    listed, missing_list = [], None
    try:
        listed = listed_variants(variant_list())
    except OSError as exc:
        missing_list = str(exc)
    summary["listed"] = listed
    summary["missing_list"] = missing_list
    summary["unlisted"] = unlisted(summary["used"], listed)
    summary["applies"] = ratchet_applies(config)
    config._x3dpd_variants = summary
    failing = summary["applies"] and (summary["unlisted"] or missing_list)
    if failing and session.exitstatus == pytest.ExitCode.OK:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    summary = getattr(config, "_x3dpd_variants", None)
    if summary is None:
        return
    tr = terminalreporter
    tr.section("x3dpd step-loop variants")
    tr.write_line(f"kernel cache: {os.environ.get('X3DPD_CACHE_DIR')}")
    compiled = summary["compiled"]
    total = sum(e["seconds"] or 0.0 for events in compiled.values() for e in events)
    n_compiles = sum(len(v) for v in compiled.values())
    tr.write_line(
        f"compiled in this run: {len(compiled)} variants ({n_compiles} compiles), "
        f"{total:.1f} s (wall time of the first calls that compiled them)"
    )
    rows = sorted(
        ((e["seconds"] or 0.0, label, e) for label, events in compiled.items() for e in events),
        key=lambda r: -r[0],
    )
    for seconds, label, e in rows:
        where = "" if e["cache"].startswith(os.environ.get("X3DPD_CACHE_DIR", "//")) else " *"
        tr.write_line(f"  {seconds:7.1f} s  {label}{where}   ({e['user']})")
    if any(not e["cache"].startswith(os.environ.get("X3DPD_CACHE_DIR", "//")) for *_, e in rows):
        tr.write_line("  * compiled into a test's own cache")
    again = sorted(label for label, events in compiled.items() if len(events) > 1)
    if again:
        tr.write_line(
            f"compiled more than once: {len(again)} variants, "
            f"{sum(e['seconds'] or 0.0 for lb in again for e in compiled[lb][1:]):.1f} s "
            "(another argument signature of the same loop, or another cache; "
            "`x3dpd cache --dir DIR` shows the compiles of each)"
        )
    tr.write_line(
        f"loaded from the cache, compiled by an earlier run: "
        f"{len(summary['loaded'] - set(compiled))} variants"
    )
    name = variant_list()
    if summary["missing_list"]:
        tr.write_line(f"variant ratchet: cannot read {name}: {summary['missing_list']}", red=True)
        return
    unused = sorted(set(summary["listed"]) - summary["used"])
    state = "" if summary["applies"] else " (not applied: -m selects other tests)"
    if not summary["unlisted"]:
        tr.write_line(
            f"variant ratchet{state}: {len(summary['used'])} variants used, all listed in "
            f"{name.name}; {len(unused)} listed variants not used by this run"
        )
        return
    tr.write_line(
        f"variant ratchet{state}: this run used {len(summary['unlisted'])} step-loop "
        f"variant(s) that {name} does not list:",
        red=summary["applies"],
    )
    for label in summary["unlisted"]:
        first = summary["first"][label]
        tr.write_line(f"  {label}   ({first['event']} by {first['user']})", red=summary["applies"])
    shown = os.path.relpath(name, config.rootpath) if name.is_absolute() else name
    tr.write_line(
        "Each variant is another compile of the whole step loop, 15-50 s in a cold suite. "
        "If the test can share a listed loop, shape its scene to ride one (tests/factories.py, "
        f"@pytest.mark.rides); if it needs this one, add the line above to {shown} "
        "in the same commit, so that review sees it.",
        red=summary["applies"],
    )


def _rides(item) -> list[str] | None:
    marker = item.get_closest_marker("rides")
    return None if marker is None else [str(a) for a in marker.args]


@pytest.hookimpl(wrapper=True)
def pytest_runtest_setup(item):
    """Count the loops from the start of the test's setup: a fixture may run its scene."""
    if _rides(item) is not None:
        item.stash[_RIDES_START] = len(loops_run_here())
    return (yield)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item):
    """A test marked ``rides`` fails when its setup or body ran a step loop it does not
    declare (a loop another test's fixture ran already is not run again: no check then)."""
    declared = _rides(item)
    if declared is None:
        return (yield)
    for label in declared:
        try:
            Variant.from_label(label)
        except ValueError as exc:
            pytest.fail(f"@pytest.mark.rides: {exc}", pytrace=False)
    result = yield
    ran = loops_run_here()[item.stash.get(_RIDES_START, 0) :]
    other = sorted(set(ran) - set(declared))
    if other:
        pytest.fail(
            f"@pytest.mark.rides({', '.join(map(repr, declared))}): the test ran "
            f"{', '.join(map(repr, other))}; its scene no longer rides the loop it declares "
            "(it compiles a variant of its own): reshape the scene, or declare the loop it "
            "needs",
            pytrace=False,
        )
    return result
