"""``x3dpd fit MEASURED... --modes N``: the documented example, the MODAL card it writes in a deck
that ``x3dpd check`` reads, sets measured both ways (roving response, roving hammer) and from
``x3dpd frf``'s CSV, and bad input (one line, exit 2, nothing written, nothing overwritten).

The FRF sets are tests/fixtures/frf/three_modes.uff (tools/make_frf_set.py: 3 modes, 4 points,
1 % noise) and sets written here from the same model."""

from __future__ import annotations

import re

import numpy as np
import scipy.linalg

from cli_helpers import ROOT, run_cli
from golden_compare import tool
import x3dpd
from x3dpd.deck.modes import read_modes
from x3dpd.io.frf_set import write_frf_uff

FIXTURE = ROOT / "tests" / "fixtures" / "frf" / "three_modes.uff"
DOCS = ROOT / "docs" / "testing-like-a-test-engineer.md"
COMMAND = "x3dpd fit tests/fixtures/frf/three_modes.uff --modes 3 --band 20:180 --out out/modal"
OUTPUTS = ("modes.csv", "modal_card.inp", "modal_fit.txt", "modal_fit.png")


MODEL = tool("make_frf_set")  # the fixture's generator: its model FN, ZETA, PHI, ...


def _fit(*args):
    return run_cli("fit", *args)


def _one_error_line(capsys) -> str:
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert err.startswith("x3dpd: error: ") and "\n" not in err, captured.err
    assert "Traceback" not in captured.out + captured.err
    return err


def _write_set(path, h, responses, reference=(1, 1), quantity="acceleration", f=None):
    write_frf_uff(
        path,
        MODEL.FREQUENCY if f is None else f,
        h,
        responses=responses,
        reference=reference,
        quantity=quantity,
    )
    return path


def test_the_fixture_is_what_its_script_writes(tmp_path):
    assert MODEL.main(["--out", str(tmp_path / "again.uff")]) == 0
    assert (tmp_path / "again.uff").read_bytes() == FIXTURE.read_bytes()


def test_the_documented_example_prints_what_the_docs_say(tmp_path, capsys, monkeypatch):
    """The docs' worked example, run as written (from the repository's root): its printed lines
    are the docs' block under the command, number for number."""
    monkeypatch.chdir(ROOT)
    out = tmp_path / "modal"
    args = COMMAND.split()[2:]
    args[args.index("out/modal")] = str(out)
    assert run_cli("fit", *args) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[-1].startswith(f"wrote {out / 'modes.csv'}")
    docs = DOCS.read_text()
    block = docs[docs.index(COMMAND) :].split("```")[2].strip("\n").splitlines()
    assert printed[:-1] == block[:-1]
    assert block[-1].startswith("wrote out/modal/modes.csv")


def test_the_modal_card_checks_with_the_fitted_and_coupled_modes_and_runs(tmp_path, capsys):
    """The written card in a deck with the four measured nodes and 0.05 kg added at node 2
    (HOUSING added): ``x3dpd check`` passes, prints the fitted frequencies as the modes given
    and, as the coupled ones, the eigenvalues of diag(w^2) psi = lambda (I + m phi_2 phi_2^T)
    psi computed here from the mode file (to the 6 digits printed). Those are the true
    structure's coupled modes (the model's phi) within four standard errors propagated from the
    report's (measured: 1.3e-4 of mode 2's frequency, 2.5 of them, from the shape at node 2,
    -1.19756 +- 0.00096 against -1.2): the shapes are mass-normalised, or the added mass would
    shift the modes otherwise (by 3-11 % here). The deck also runs, driven at node 1."""
    out = tmp_path / "fit"
    assert _fit(FIXTURE, "--modes", 3, "--band", "20:180", "--out", out, "--quiet") == 0
    assert sorted(p.name for p in out.iterdir()) == sorted(OUTPUTS)
    modes = read_modes(out / "modes.csv")
    deck = out / "structure.inp"
    deck.write_text(
        "TITLE\nmeasured structure\nEND\nUNITS\n m N s\nEND\n"
        "PARAMETERS\n 0.0 0.05 0.0 1e-5 1e-5 0 1e12 0 5 0 10\nEND\n"
        "NODE COORDINATES\n 1 0 0 0\n 2 0.1 0 0\n 3 0.2 0 0\n 4 0.3 0 0\nEND\n"
        "MASS\n 2 0.05 0 0 0\nEND\n" + (out / "modal_card.inp").read_text()
    )
    assert run_cli("check", deck) == 0
    text = capsys.readouterr().out
    # and it runs: driven at node 1 for 0.05 s, node 1 moves
    driven = out / "driven.inp"
    driven.write_text(deck.read_text() + "USRFRC\n sine:node=1,dof=1,amp=1.0,hz=40\nEND\n")
    assert run_cli(driven, "--trace", out / "driven.trace.txt", "--quiet") == 0
    x = x3dpd.read_trace(out / "driven.trace.txt").position[:, 0, 0]
    assert np.all(np.isfinite(x)) and np.max(np.abs(x)) > 0
    assert "3 modes from modes.csv; housing added" in text
    given = [float(x) for x in re.findall(r"(?m)^\s+mode \d: ([\d.]+) Hz", text)]
    coupled = [float(x) for x in re.findall(r"coupled mode \d: ([\d.]+) Hz", text)]
    assert np.allclose(given, modes.freq_hz, rtol=6e-6)

    def coupled_hz(fn, phi_2):
        w2 = (2 * np.pi * np.asarray(fn)) ** 2
        lam = scipy.linalg.eigh(np.diag(w2), np.eye(3) + 0.05 * np.outer(phi_2, phi_2))[0]
        return np.sqrt(lam) / (2 * np.pi)

    fitted = coupled_hz(modes.freq_hz, modes.shapes[:, 1, 0])
    assert np.allclose(coupled, fitted, rtol=6e-6)
    # against the truth: within four standard errors propagated from the report's standard
    # errors of fn and of the shape at node 2 (first order, correlations left out)
    report = (out / "modal_fit.txt").read_text().splitlines()
    fn_se = [float(re.findall(r"\+- (\S+)", row)[0]) for row in report[3:6]]
    row = next(r for r in report if r.startswith("2:x "))
    phi_se = [float(x) for x in re.findall(r"\+- (\S+)", row)]
    params = np.concatenate([modes.freq_hz, modes.shapes[:, 1, 0]])
    se = np.array(fn_se + phi_se)
    var = np.zeros(3)
    for k in range(6):
        step = np.zeros(6)
        step[k] = 1e-6 * abs(params[k])
        up, down = params + step, params - step
        slope = (coupled_hz(up[:3], up[3:]) - coupled_hz(down[:3], down[3:])) / (2 * step[k])
        var += (slope * se[k]) ** 2
    true = coupled_hz(MODEL.FN, MODEL.PHI[1])
    assert np.all(np.abs(fitted - true) < 4 * np.sqrt(var))
    assert np.max(np.abs(fitted / true - 1)) < 3e-4


def test_a_roving_hammer_set_gives_the_same_modes(tmp_path, capsys):
    """Reciprocity: one accelerometer at node 1 and the hammer at nodes 1-4 (the same noiseless
    FRFs, H_1j = H_j1) give the shapes of the roving accelerometer; UFF directions -x (here node
    3's response) are turned to +x; and the same set as ``x3dpd frf``'s CSV reads alike. All
    three: the model's modes to 1e-6."""
    h = MODEL.accelerances()
    h[2] *= -1  # node 3's accelerometer mounted along -x
    rows = _write_set(tmp_path / "rows.uff", h, [(1, 1), (2, 1), (3, -1), (4, 1)])
    write_frf_uff(
        tmp_path / "hammer.uff",
        MODEL.FREQUENCY,
        MODEL.accelerances()[[1, 0, 3, 2]],
        responses=[(1, 1)] * 4,
        reference=(1, 1),
        quantity="acceleration",
    )
    # the roving-hammer file: one dataset per hammer point, response fixed at node 1
    _edited(tmp_path / "hammer.uff", lambda k, d: d.update(ref_node=(2, 1, 4, 3)[k]))
    csv = tmp_path / "frf.csv"
    lines = [
        "# quantity: acceleration",
        "# drive: node 1 dof 1",
        "run,response,frequency_hz,h1_re,h1_im",
    ]
    for o in range(4):
        lines += [
            f"r,{o + 1}:1,{float(f)!r},{float(v.real)!r},{float(v.imag)!r}"
            for f, v in zip(MODEL.FREQUENCY, MODEL.accelerances()[o])
        ]
    csv.write_text("\n".join(lines) + "\n")
    for name, source in (("rows", rows), ("hammer", tmp_path / "hammer.uff"), ("csv", csv)):
        out = tmp_path / name
        assert _fit(source, "--modes", 3, "--band", "20:180", "--out", out, "--quiet") == 0, name
        modes = read_modes(out / "modes.csv")
        assert np.allclose(modes.freq_hz, MODEL.FN, rtol=1e-6), name
        assert np.allclose(modes.damping, MODEL.ZETA, rtol=1e-6), name
        assert np.allclose(modes.shapes[:, :, 0].T, MODEL.PHI, rtol=0, atol=1e-6), name
        assert np.isnan(modes.shapes[:, :, 1:]).all()
    capsys.readouterr()


def test_a_set_of_reversed_sign_says_what_to_pass_and_then_fits(tmp_path, capsys):
    """Every FRF's sign reversed (accelerometers along -x, labelled +x): refused with the option
    to give, which then gives the model's shapes (1 % noise: within 0.5 %)."""
    with_noise = read_fixture()
    _write_set(tmp_path / "neg.uff", -with_noise, [(n, 1) for n in range(1, 5)])
    out = tmp_path / "fit"
    assert _fit(tmp_path / "neg.uff", "--modes", 3, "--band", "20:180", "--out", out) == 2
    err = _one_error_line(capsys)
    assert "sign is reversed" in err and "pass --force-scale -1" in err
    assert not out.exists()
    args = ("--modes", 3, "--band", "20:180", "--force-scale", -1, "--out", out, "--quiet")
    assert _fit(tmp_path / "neg.uff", *args) == 0
    modes = read_modes(out / "modes.csv")
    assert np.allclose(modes.shapes[:, :, 0].T, MODEL.PHI, rtol=0, atol=0.005 * 3.3)


def read_fixture() -> np.ndarray:
    from x3dpd.io.frf_set import read_frf_set

    return np.array([m.h for m in read_frf_set([FIXTURE])])


def _set(tmp_path, name, **kw):
    h = kw.pop("h", MODEL.accelerances())
    return _write_set(tmp_path / name, h, kw.pop("responses", [(n, 1) for n in range(1, 5)]), **kw)


def _edited(path, edit):
    """The UFF file ``path`` rewritten with ``edit(k, dataset)`` applied to each dataset."""
    import pyuff

    sets = pyuff.UFF(str(path)).read_sets()
    sets = sets if isinstance(sets, list) else [sets]
    for k, dataset in enumerate(sets):
        edit(k, dataset)
    path.unlink()
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


def _bad_inputs(tmp_path):
    """(arguments, text the one-line error must hold) of each bad input."""
    good = _set(tmp_path, "good.uff")
    time = _edited(_set(tmp_path, "time.uff"), lambda k, d: d.update(func_type=1))
    transmissibility = _set(tmp_path, "t.uff")  # function type 5 (pyuff writes no such set)
    head = b"\n    4         0    0         0"
    data = transmissibility.read_bytes()
    assert data.count(head) == 4
    transmissibility.write_bytes(data.replace(head, head.replace(b"4", b"5", 1)))
    plain = tmp_path / "plain.csv"
    plain.write_text("frequency_hz,re,im\n" + "".join(f"{k + 1},1,0\n" for k in range(40)))
    coarse = _set(
        tmp_path,
        "coarse.uff",
        h=MODEL.accelerances(MODEL.FREQUENCY[::2])[:1],
        responses=[(5, 1)],
        f=MODEL.FREQUENCY[::2],
    )
    other = _set(
        tmp_path, "other.uff", h=MODEL.accelerances()[1:], responses=[(2, 1), (3, 1), (4, 1)]
    )
    other_ref = _set(
        tmp_path, "ref2.uff", h=MODEL.accelerances()[:1], responses=[(2, 1)], reference=(2, 1)
    )
    dead = MODEL.accelerances()
    dead[2] = 0.0  # a channel that recorded nothing
    dead = _set(tmp_path, "dead.uff", h=dead)
    velocity = _set(
        tmp_path, "vel.uff", h=MODEL.accelerances()[:1], responses=[(5, 1)], quantity="velocity"
    )
    return [
        ((time, "--modes", 3), "function type(s) 1"),
        ((transmissibility, "--modes", 3), "is a transmissibility; a modal fit needs FRFs per"),
        ((plain, "--modes", 1), "does not say its response and reference points"),
        ((good, coarse, "--modes", 3), "a modal fit needs one frequency axis"),
        (
            (good, "--modes", 3, "--band", "30:35"),
            "holds 21 lines (of 801); --modes 3 needs at least 25",
        ),
        ((good, "--modes", 4, "--band", "20:180"), "shows 3 stable mode(s)"),
        ((other, "--modes", 3), "no driving-point FRF (response and reference both at 1:x)"),
        ((good, other_ref, "--modes", 3), "2 references and 4 responses"),
        ((good, other, "--modes", 3), "7 FRFs for 4 points"),
        ((good, velocity, "--modes", 3), "of acceleration, velocity"),
        ((dead, "--modes", 3), "the FRF at 3:x is 0 over the band 0.25:200 Hz"),
        ((good, "--modes", 3, "--node", 2), "--node is an option of the single-mode fit"),
        ((good, good), "2 files given"),
        ((good, "--modes", 3, "--units", "m,N"), "--units 'm,N'"),
        ((good, "--modes", 3, "--band", "20:250"), "reaches outside the measured data"),
        ((good, "--modes", 3, "--force-scale", 0), "--force-scale 0.0"),
    ]


def test_bad_input_one_line_exit_2_nothing_written(tmp_path, capsys):
    for args, says in _bad_inputs(tmp_path):
        out = tmp_path / "out"
        assert _fit(*args, "--out", out) == 2, args
        err = _one_error_line(capsys)
        assert says in err, (args, err)
        assert not out.exists(), args


def test_bad_input_overwrites_nothing(tmp_path, capsys):
    """With --overwrite, a refused fit leaves what DIR holds as it was."""
    out = tmp_path / "out"
    out.mkdir()
    for name in OUTPUTS:
        (out / name).write_text("kept\n")
    bad = _set(
        tmp_path, "nodrive.uff", h=MODEL.accelerances()[1:], responses=[(2, 1), (3, 1), (4, 1)]
    )
    assert _fit(bad, "--modes", 3, "--out", out, "--overwrite") == 2
    _one_error_line(capsys)
    assert all((out / name).read_text() == "kept\n" for name in OUTPUTS)
    assert _fit(FIXTURE, "--modes", 3, "--band", "20:180", "--out", out) == 2
    assert "exists; give --overwrite" in _one_error_line(capsys)
    assert all((out / name).read_text() == "kept\n" for name in OUTPUTS)


def test_help_says_what_the_options_take(capsys):
    """Issue 33 item 24: the help says --force-scale may be negative and a band's minimum."""
    assert run_cli("fit", "--help") == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "negative for an FRF of reversed sign" in text
    assert "It must hold 5 lines at least (with --modes N: 5 per mode and 10)" in text
    assert "the driving-point FRF is required" in text
