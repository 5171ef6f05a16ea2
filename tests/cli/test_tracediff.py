"""``x3dpd tracediff``: report, exit statuses 0 / 1 / 2, one-line errors."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from x3dpd.cli import _register, cli, main
from x3dpd.io.trace import TraceWriter

IDS = [25, 26, 27]


def write(path, data, ids=IDS, times=None):
    times = np.arange(data.shape[0]) * 1e-3 if times is None else times
    with TraceWriter(path, ids, {"dt": 5e-7, "itrac": 2000}) as w:
        w.write_block(times, data)
    return str(path)


@pytest.fixture
def pair(tmp_path):
    rng = np.random.default_rng(0)
    ref = rng.normal(size=(4, len(IDS), 9))
    run = ref.copy()
    run[2, 1, 4] *= 1 + 1e-6
    return (
        write(tmp_path / "ref.txt", ref),
        write(tmp_path / "same.txt", ref),
        write(tmp_path / "run.txt", run),
    )


def invoke(*args):
    _register()
    return CliRunner().invoke(cli, ["tracediff", *map(str, args)])


def run_main(capsys, *args):
    with pytest.raises(SystemExit) as exc:
        main(["tracediff", *map(str, args)])
    out, err = capsys.readouterr()
    return exc.value.code, out, err


def test_agree(pair):
    ref, same, _ = pair
    res = invoke(same, ref)
    assert res.exit_code == 0, res.output
    assert "traces agree within rtol=1e-09, atol=0 up to t=3.000000000e-03" in res.output
    assert "vy" in res.output and "max |a-b|/|b|" in res.output


def test_differ(pair):
    ref, _, run = pair
    res = invoke(run, ref)
    assert res.exit_code == 1, res.output
    assert "first difference: t=2.000000000e-03 node 26 column vy:" in res.output
    assert "1 value(s) differ" in res.output
    assert invoke(run, ref, "--rtol", "1e-5").exit_code == 0
    assert invoke(run, ref, "--atol", "1e-3").exit_code == 0
    res = invoke(run, ref, "--until", "1e-3")
    assert res.exit_code == 0 and "up to t=1.000000000e-03" in res.output


def test_node_mismatch_is_a_one_line_error(pair, tmp_path, capsys):
    ref = pair[0]
    other = write(tmp_path / "other.txt", np.zeros((4, 3, 9)), ids=[25, 27, 26])
    code, _out, err = run_main(capsys, other, ref)
    assert code == 2
    assert err.startswith("x3dpd: error: the traces follow different nodes")
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_unreadable_input_exits_2(pair, tmp_path, capsys):
    ref = pair[0]
    code, _, err = run_main(capsys, tmp_path / "missing.txt", ref)
    assert code == 2 and "does not exist" in err
    bad = tmp_path / "bad.txt"
    bad.write_text(" 0.0;1;2;3;4;5;6;7;8;9\n 0.0;1;2;x;4;5;6;7;8;9\n")
    code, _, err = run_main(capsys, ref, bad)
    assert code == 2 and "bad.txt:2: column 4 (z): 'x' is not a number" in err
    assert len(err.strip().splitlines()) == 1


def test_bad_option_exits_2(pair, capsys):
    code, _, err = run_main(capsys, pair[0], pair[1], "--rtol", "-1")
    assert code == 2 and "--rtol" in err


def test_truncated_trace_warns(pair, tmp_path):
    ref = pair[0]
    raw = Path(ref).read_bytes()
    cut = tmp_path / "cut.txt"
    cut.write_bytes(raw[:-100])
    side = json.loads(Path(ref + ".json").read_text())
    side["status"] = "interrupted"
    (tmp_path / "cut.txt.json").write_text(json.dumps(side))
    res = invoke(cut, ref, "--until", "2e-3")
    assert res.exit_code == 0
    assert "x3dpd: warning:" in res.output and "incomplete" in res.output
    res = invoke(cut, ref)
    assert res.exit_code == 1 and "time grids differ" in res.output


def test_python_m_exit_statuses(pair, tmp_path):
    ref, same, run = pair
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(
            [
                os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                os.environ.get("PYTHONPATH", ""),
            ]
        ),
    }

    def x3dpd(*args):
        return subprocess.run(
            [sys.executable, "-m", "x3dpd", "tracediff", *args],
            capture_output=True,
            text=True,
            env=env,
            timeout=120,
            check=False,
        )

    assert x3dpd(same, ref).returncode == 0
    assert x3dpd(run, ref).returncode == 1
    res = x3dpd(str(tmp_path / "missing.txt"), ref)
    assert res.returncode == 2
    assert res.stderr.startswith("x3dpd: error:") and "Traceback" not in res.stderr
