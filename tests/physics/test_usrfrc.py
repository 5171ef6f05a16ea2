"""Built-in external forces and user force files (x3dpd.physics.usrfrc).

Every law is checked against its closed form evaluated here with numpy on a time grid; the swept
sine's phase is also checked against a numerical integral of its frequency and by numerical
differentiation (d phi / dt = 2 pi f, continuous where the sweep ends).
"""

from __future__ import annotations

import math
import pathlib
import textwrap

import numpy as np
import pytest

from x3dpd._jit import JIT_DISABLED
from x3dpd.errors import UsrfrcError
from x3dpd.physics.user_force_file import build_external_forces, load_user_force, node_index_array
from x3dpd.physics.usrfrc import (
    KIND_SINE,
    KIND_SWEEP_LINEAR,
    KIND_SWEEP_LOG,
    _apply_forces,
    apply_forces,
    force_table,
    force_values,
    is_user_file,
    split_specs,
    sweep_frequency,
    sweep_phase,
)

IDS = np.array([3, 10, 25, 40], dtype=np.int64)  # node 25 is index 2
APPENDIX_C = pathlib.Path(__file__).resolve().parents[2] / "decks" / "appendix_c.py"
T = np.linspace(-0.05, 2.0, 4001)


def one(spec, t=T):
    return force_values(t, force_table([spec], IDS))[:, 0]


# --- parsing ---------------------------------------------------------------------------------


def test_table_layout_and_node_resolution():
    table = force_table(
        [
            "constant:node=25,dof=1,amp=2",
            "step:node=3,dof=6,amp=-1,t0=0.1,t1=0.2",
            "sine:node=40,dof=3,amp=4.84040e-3,hz=37.21,phase=90,t0=0.5",
            "SWEEP:node=10,dof=2,amp=1,f0=20,f1=10,rate=5,law=log,end=stop",
        ],
        IDS,
    )
    assert table.shape == (4, 9) and table.dtype == np.float64
    np.testing.assert_array_equal(table[0], [1, 2, 0, 2, 0, 0, 0, 0, 0])
    np.testing.assert_array_equal(table[1], [2, 0, 5, -1, 0.1, 0.2, 0, 0, 0])
    np.testing.assert_allclose(
        table[2],
        [KIND_SINE, 3, 2, 4.84040e-3, 2 * math.pi * 37.21, math.pi / 2, 0.5, 0, 0],
        rtol=1e-15,
    )
    # down-sweep: signed rate, octaves/min -> octaves/s
    np.testing.assert_allclose(table[3], [KIND_SWEEP_LOG, 1, 1, 1, 20, 10, -5 / 60, 0, 1])
    assert force_table([], IDS).shape == (0, 9)


def test_model_like_object_is_accepted():
    class FakeModel:
        node_ids = IDS

    assert force_table(["constant:node=40,dof=2,amp=1"], FakeModel())[0, 1] == 3


def test_step_without_t1_is_open_ended_and_fortran_exponent():
    row = force_table(["step:node=3,dof=1,amp=1.5d-3,t0=0"], IDS)[0]
    assert row[3] == 1.5e-3 and row[5] == math.inf


@pytest.mark.parametrize(
    "spec, words",
    [
        ("constant:node=25,dof=1", ["missing", "amp"]),
        ("constant:node=25,dof=1,amp=1,hz=3", ["unknown key", "'hz'"]),
        ("constant:node=25,dof=1,amp=1,amp=2", ["'amp'", "twice"]),
        ("constant:node=26,dof=1,amp=1", ["node=26", "not defined"]),
        ("constant:node=2.5,dof=1,amp=1", ["node=", "integer"]),
        ("constant:node=25,dof=0,amp=1", ["dof=", "1..6"]),
        ("constant:node=25,dof=7,amp=1", ["dof=", "1..6"]),
        ("constant:node=25,dof=x,amp=1", ["dof=", "1..6"]),
        ("constant:node=25,dof=1,amp=nan", ["amp=", "finite"]),
        ("constant:node=25,dof=1,amp=inf", ["amp=", "finite"]),
        ("constant:node=25,dof=1,amp=abc", ["amp=", "not a number"]),
        ("constant:node=25,dof=1,amp", ["not key=value"]),
        ("constant:node=25,,dof=1,amp=1", ["empty item"]),
        ("sine:node=25,dof=1,amp=1", ["hz=", "omega="]),
        ("sine:node=25,dof=1,amp=1,hz=3,omega=3", ["exactly one"]),
        ("sine:node=25,dof=1,amp=1,hz=0", ["hz=", "positive"]),
        ("sine:node=25,dof=1,amp=1,hz=-37.21", ["hz=", "positive"]),
        ("sine:node=25,dof=1,amp=1,hz=nan", ["hz=", "positive"]),
        ("sine:node=25,dof=1,amp=1,hz=3,phase=1xrad", ["phase="]),
        ("step:node=25,dof=1,amp=1", ["missing", "t0"]),
        ("step:node=25,dof=1,amp=1,t0=0.2,t1=0.1", ["t1=", "later"]),
        ("sweep:node=25,dof=1,amp=1,f0=10,f1=10,rate=1", ["f0 == f1"]),
        ("sweep:node=25,dof=1,amp=1,f0=10,f1=20,rate=0", ["rate=", "positive"]),
        ("sweep:node=25,dof=1,amp=1,f0=10,f1=20,rate=1,law=cubic", ["law=", "linear, log"]),
        ("sweep:node=25,dof=1,amp=1,f0=10,f1=20,rate=1,end=wrap", ["end=", "hold, stop"]),
        ("spline:node=25,dof=1,amp=1", ["unknown force kind", "'spline'"]),
        ("sine node=25,dof=1,amp=1,hz=1", ["unknown force kind"]),
    ],
)
def test_bad_specs_name_the_spec_and_the_problem(spec, words):
    with pytest.raises(UsrfrcError) as err:
        force_table([spec], IDS)
    message = str(err.value)
    assert repr(spec) in message
    for word in words:
        assert word in message


def test_user_files_are_told_apart_from_laws(tmp_path):
    existing = tmp_path / "force_without_suffix"
    existing.write_text("")
    assert is_user_file("my/force.py") and is_user_file(str(existing))
    assert not is_user_file("sine:node=25,dof=1,amp=1,hz=1") and not is_user_file("bogus")
    laws, files = split_specs(
        ["constant:node=3,dof=1,amp=1", " f.py ", "step:node=3,dof=1,amp=1,t0=0"]
    )
    assert laws == ("constant:node=3,dof=1,amp=1", "step:node=3,dof=1,amp=1,t0=0")
    assert files == ("f.py",)
    with pytest.raises(UsrfrcError, match="load_user_force"):
        force_table(["f.py"], IDS)


# --- closed forms ----------------------------------------------------------------------------


def test_constant_and_step():
    np.testing.assert_array_equal(one("constant:node=25,dof=1,amp=-2.5"), -2.5)
    step = one("step:node=25,dof=1,amp=3,t0=0.1,t1=0.7")
    np.testing.assert_array_equal(step, np.where((T >= 0.1) & (T < 0.7), 3.0, 0.0))
    np.testing.assert_array_equal(
        one("step:node=25,dof=1,amp=3,t0=0.1"), np.where(T >= 0.1, 3.0, 0.0)
    )


@pytest.mark.parametrize(
    "phase, phi",
    [
        ("", 0.0),
        (",phase=30", math.pi / 6),
        (",phase=30deg", math.pi / 6),
        (",phase=0.5rad", 0.5),
        (",phase=-90", -math.pi / 2),
    ],
)
@pytest.mark.parametrize("t0", [0.0, 0.25])
def test_sine_closed_form(phase, phi, t0):
    amp, hz = 4.84040e-3, 37.21
    got = one(f"sine:node=25,dof=1,amp={amp},hz={hz},t0={t0}{phase}")
    want = np.where(T >= t0, amp * np.sin(2 * np.pi * hz * (T - t0) + phi), 0.0)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-13 * amp)


def test_sine_omega_equals_hz():
    a = one("sine:node=25,dof=1,amp=1,omega=100")
    b = one(f"sine:node=25,dof=1,amp=1,hz={100 / (2 * math.pi)!r}")
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)


def _freq(tau, f0, f1, k, log):
    tau1 = (math.log2(f1 / f0) if log else f1 - f0) / k
    s = np.clip(tau, 0.0, tau1)
    return f0 * 2.0 ** (k * s) if log else f0 + k * s


SWEEPS = [  # spec, f0, f1, signed rate per second, log law
    ("f0=10,f1=50,rate=40", 10, 50, 40.0, False),  # linear up, ends at 1 s
    ("f0=50,f1=10,rate=40", 50, 10, -40.0, False),  # linear down
    ("f0=10,f1=40,rate=120,law=log", 10, 40, 2.0, True),  # 2 octaves at 2 oct/s: ends at 1 s
    ("f0=40,f1=10,rate=120,law=log", 40, 10, -2.0, True),
]


@pytest.mark.parametrize("body, f0, f1, k, log", SWEEPS)
def test_sweep_frequency_and_phase(body, f0, f1, k, log):
    t0 = 0.1
    row = force_table([f"sweep:node=25,dof=1,amp=2,{body},t0={t0}"], IDS)[0]
    assert int(row[0]) == (KIND_SWEEP_LOG if log else KIND_SWEEP_LINEAR)
    t = np.linspace(0.0, 1.6, 160001)  # sweep ends at t0 + 1 = 1.1 s, then holds f1
    f = _freq(t - t0, f0, f1, k, log)
    np.testing.assert_allclose(sweep_frequency(t, row), f, rtol=1e-12)
    # phase = 2 pi int f dt: closed form vs trapezoid rule (error ~ h^2 f' / 12 per unit time)
    phi = sweep_phase(t, row)
    trap = 2 * np.pi * np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(t))])
    trap -= trap[np.searchsorted(t, t0)]
    trap[t < t0] = 0.0
    np.testing.assert_allclose(phi, trap, rtol=0, atol=1e-6)
    # numerical derivative of the phase is 2 pi f, across the end of the sweep too
    h = 1e-6
    tt = np.linspace(t0 + 0.01, 1.6, 3001)
    dphi = (sweep_phase(tt + h, row) - sweep_phase(tt - h, row)) / (2 * h)
    np.testing.assert_allclose(dphi, 2 * np.pi * _freq(tt - t0, f0, f1, k, log), rtol=2e-7)
    tau1 = t0 + 1.0
    jump = sweep_phase([tau1 + 1e-9], row)[0] - sweep_phase([tau1 - 1e-9], row)[0]
    assert abs(jump - 2 * np.pi * f1 * 2e-9) < 1e-9
    # the force is amp sin(phase), zero before t0
    np.testing.assert_allclose(
        force_values(t, row[None, :])[:, 0],
        np.where(t >= t0, 2 * np.sin(phi), 0.0),
        rtol=0,
        atol=1e-12,
    )


def test_sweep_end_stop_releases_the_force():
    table = force_table(
        [
            "sweep:node=25,dof=1,amp=1,f0=10,f1=50,rate=40,end=stop",
            "sweep:node=25,dof=1,amp=1,f0=10,f1=50,rate=40,end=hold",
        ],
        IDS,
    )
    v = force_values(T, table)
    np.testing.assert_array_equal(v[T <= 1.0, 0], v[T <= 1.0, 1])
    np.testing.assert_array_equal(v[T > 1.0, 0], 0.0)
    assert np.abs(v[T > 1.0, 1]).max() > 0.99


def test_apply_forces_adds_to_the_right_entries():
    table = force_table(
        [
            "constant:node=25,dof=1,amp=2",
            "constant:node=25,dof=1,amp=0.5",
            "sine:node=40,dof=4,amp=3,hz=1",
            "step:node=3,dof=6,amp=7,t0=1",
        ],
        IDS,
    )
    rng = np.random.default_rng(1)
    force = rng.normal(size=(4, 6))
    before = force.copy()
    t = 0.3
    apply_forces(t, table, force)
    expected = before.copy()
    expected[2, 0] += 2.5
    expected[3, 3] += 3 * math.sin(2 * math.pi * t)
    np.testing.assert_allclose(force, expected, rtol=1e-15)
    _apply_forces(1.0, table[3:], force)  # the raw kernel, as the solver calls it
    assert force[0, 5] == before[0, 5] + 7.0
    with pytest.raises(ValueError):
        apply_forces(0.0, table, np.zeros((2, 6)))


# --- user force files ------------------------------------------------------------------------


def write(tmp_path, text, name="force.py"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_node_index_array():
    index = node_index_array(IDS)
    assert index.dtype == np.int64 and index.shape == (41,)
    assert index[25] == 2 and index[3] == 0 and index[40] == 3
    assert (index[[0, 1, 2, 4, 24, 26, 39]] == -1).all()


def test_appendix_c_equals_the_builtin_sine():
    """Appendix C: 4.84040e-3 sin(233.7973253 t) on FORCE(1, node 25).

    233.7973253 / (2 pi) = 37.21000000315885 Hz, so ``hz=37.21`` gives omega smaller by
    dw = 1.98e-8 rad/s (8.5e-11 relative) and the two forces differ by up to amp*dw*t, i.e.
    2e-8 of the amplitude after 1 s: they do NOT agree to 1e-12. ``omega=233.7973253`` is the
    same arithmetic (bit-identical); ``hz=37.21000000315885`` agrees to ~1e-14 of the amplitude.
    """
    amp, w = 4.84040e-3, 233.7973253
    uf = load_user_force(APPENDIX_C, IDS)
    assert not uf.python
    t = np.linspace(0.0, 2.0, 2001)
    user = np.empty_like(t)
    for j, tj in enumerate(t):
        force = np.zeros((4, 6))
        uf(tj, np.zeros((4, 3)), np.zeros((4, 6)), force)
        assert np.count_nonzero(force[np.arange(4) != 2]) == 0
        assert np.count_nonzero(force[2, 1:]) == 0
        user[j] = force[2, 0]
    np.testing.assert_allclose(user, amp * np.sin(w * t), rtol=0, atol=1e-15 * amp)

    exact = one(f"sine:node=25,dof=1,amp={amp},omega={w}", t)
    np.testing.assert_array_equal(exact, user)
    ratio = one(f"sine:node=25,dof=1,amp={amp},hz={w / (2 * math.pi)!r}", t)
    np.testing.assert_allclose(ratio, user, rtol=0, atol=1e-12 * amp)
    rounded = one(f"sine:node=25,dof=1,amp={amp},hz=37.21", t)
    dw = w - 2 * math.pi * 37.21
    assert abs(dw - 1.9848e-8) < 1e-11
    assert np.all(np.abs(rounded - user) <= amp * abs(dw) * t + 1e-15)
    assert np.abs(rounded - user).max() > 1e-12 * amp  # the honest part: not 1e-12


def test_table_and_user_file_both_add_to_the_force_sums():
    uf = load_user_force(APPENDIX_C, IDS)
    table = force_table(["constant:node=25,dof=1,amp=1", "step:node=10,dof=2,amp=2,t0=0"], IDS)
    t = 0.01
    force = np.ones((4, 6))
    apply_forces(t, table, force)
    uf(t, np.zeros((4, 3)), np.zeros((4, 6)), force)
    expected = np.ones((4, 6))
    expected[2, 0] += 1.0 + 4.84040e-3 * math.sin(233.7973253 * t)
    expected[1, 1] += 2.0
    np.testing.assert_allclose(force, expected, rtol=1e-15)


def test_user_file_with_helpers_state_and_numba_decorator(tmp_path):
    path = write(
        tmp_path,
        """
        import numba
        import numpy as np

        K = 3.0

        def spring(dx):
            return -K * dx

        @numba.njit
        def usrfrc(time, coords, vels, force):
            i = NODE_INDEX[40]
            j = NODE_INDEX[3]
            force[i, 1] += spring(coords[i, 1] - coords[j, 1]) - 0.5 * vels[i, 1] + time
    """,
    )
    uf = load_user_force(path, IDS)
    assert not uf.python
    rng = np.random.default_rng(2)
    x, vel, force = rng.normal(size=(4, 3)), rng.normal(size=(4, 6)), np.zeros((4, 6))
    uf(2.0, x, vel, force)
    assert force[3, 1] == pytest.approx(-3.0 * (x[3, 1] - x[0, 1]) - 0.5 * vel[3, 1] + 2.0)


@pytest.mark.parametrize(
    "text, words",
    [
        ("def other(time, coords, vels, force):\n    pass\n", ["no function usrfrc"]),
        ("usrfrc = 3\n", ["no function usrfrc"]),
        (
            "def usrfrc(time, coords, force):\n    pass\n",
            ["force.py:1", "exactly", "usrfrc(time, coords, force)"],
        ),
        ("def usrfrc(*args):\n    pass\n", ["exactly"]),
        ("x = 1\ndef usrfrc(time, coords, vels, force)\n    pass\n", ["force.py:2", "SyntaxError"]),
        ("import numpy\nraise RuntimeError('boom')\n", ["force.py:2", "RuntimeError: boom"]),
        (
            "def usrfrc(time, coords, vels, force):\n    coords[0, 0] = 1.5\n",
            ["modified", "coords"],
        ),
        ("def usrfrc(time, coords, vels, force):\n    vels[:] = 0.0\n", ["modified", "vels"]),
    ],
)
def test_bad_user_files(tmp_path, text, words):
    path = write(tmp_path, text)
    with pytest.raises(UsrfrcError) as err:
        load_user_force(path, IDS)
    for word in words:
        assert word in str(err.value)


def test_missing_user_file(tmp_path):
    with pytest.raises(UsrfrcError, match="not found"):
        load_user_force(tmp_path / "nope.py", IDS)
    with pytest.raises(UsrfrcError, match="not found"):
        build_external_forces(["sine:node=25,dof=1,amp=1,hz=1", str(tmp_path / "nope.py")], IDS)


UNCOMPILABLE = """\
import numpy as np

LOG = {}


def usrfrc(time, coords, vels, force):
    i = NODE_INDEX[25]
    LOG[time] = i
    force[i, 2] += 2.0 * time + 1.0
"""


@pytest.mark.skipif(JIT_DISABLED, reason="everything 'compiles' with NUMBA_DISABLE_JIT=1")
def test_uncompilable_user_file_reports_file_line_and_falls_back(tmp_path):
    path = write(tmp_path, UNCOMPILABLE)
    with pytest.raises(UsrfrcError) as err:
        load_user_force(path, IDS)
    message = str(err.value)
    assert f"{path}:8: numba cannot compile usrfrc" in message
    assert "LOG[time] = i" in message and "--usrfrc-python" in message
    assert "\x1b[" not in message

    undefined = write(
        tmp_path,
        "def usrfrc(time, coords, vels, force):\n"
        "    force[0, 0] += time\n    force[0, 1] += GAIN * time\n",
        "undefined.py",
    )
    with pytest.raises(UsrfrcError) as err:
        load_user_force(undefined, IDS)
    assert f"{undefined}:3:" in str(err.value) and "'GAIN' is not defined" in str(err.value)

    uf = load_user_force(path, IDS, allow_python=True)
    assert uf.python
    force = np.zeros((4, 6))
    uf(0.5, np.zeros((4, 3)), np.zeros((4, 6)), force)
    assert force[2, 2] == 2.0

    forces = build_external_forces(
        [str(path), "constant:node=3,dof=1,amp=1"], IDS, allow_python=True
    )
    assert forces.table.shape == (1, 9) and forces.python_user and not forces.compiled_user
