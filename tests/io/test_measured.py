"""Measured data in (x3dpd.io.measured): FRFs and ring-downs written here from known functions,
as CSV and as UFF dataset 58 (with pyuff), read back; files of the wrong kind refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.errors import InputError
from x3dpd.io.measured import (
    read_measured_frf,
    read_measured_history,
    write_frf_csv,
)

F = 0.5 + 0.25 * np.arange(240)  # Hz


def known_frf(f=F, fn=39.37, zeta=0.03, residue=5000.0):
    """An accelerance (i w)^2 R / (wn^2 - w^2 + 2 i zeta wn w)."""
    w = 2 * np.pi * f
    wn = 2 * np.pi * fn
    return -(w**2) * residue / (wn**2 - w**2 + 2j * zeta * wn * w)


def write_uff58(path, x, data, *, binary, func_type=4, ordinate=12, denominator=13, abscissa=18):
    """One dataset 58 (pyuff needs every field to write one)."""
    import pyuff

    unit_fields = {}
    for axis in ("abscissa", "ordinate", "orddenom", "z_axis"):
        unit_fields.update(
            {
                f"{axis}_len_unit_exp": 0,
                f"{axis}_force_unit_exp": 0,
                f"{axis}_temp_unit_exp": 0,
                f"{axis}_axis_units_lab": "",
            }
        )
    dset = pyuff.prepare_58(
        binary=binary,
        id1="x3dpd test",
        id2="",
        id3="",
        id4="",
        id5="",
        func_type=func_type,
        ver_num=0,
        load_case_id=0,
        rsp_ent_name="NONE",
        rsp_node=9,
        rsp_dir=1,
        ref_ent_name="NONE",
        ref_node=9,
        ref_dir=1,
        abscissa_spacing=1,
        abscissa_min=float(x[0]),
        abscissa_inc=float(x[1] - x[0]),
        z_axis_value=0.0,
        abscissa_spec_data_type=abscissa,
        ordinate_spec_data_type=ordinate,
        orddenom_spec_data_type=denominator,
        z_axis_spec_data_type=0,
        data=data,
        x=x,
        **unit_fields,
    )
    pyuff.UFF(str(path)).write_sets(dset, mode="add")


def test_csv_frf_reads_back_exactly(tmp_path):
    h = known_frf()
    coh = np.linspace(0.5, 1.0, F.size)
    write_frf_csv(tmp_path / "m.csv", F, h, coherence=coh, quantity="acceleration", label="tip")
    (m,) = read_measured_frf(tmp_path / "m.csv")
    assert np.array_equal(m.frequency, F) and np.array_equal(m.h, h)
    assert np.array_equal(m.coherence, coh)
    assert m.quantity == "acceleration" and m.label == "tip"


def test_csv_frf_by_magnitude_and_phase(tmp_path):
    h = known_frf()
    lines = ["Frequency_Hz,Mag,Phase_deg,comment"]
    lines += [
        f"{float(f)!r},{float(abs(v))!r},{math.degrees(np.angle(v))!r},see notes"
        for f, v in zip(F, h)
    ]
    (tmp_path / "m.csv").write_text("\n".join(lines) + "\n")
    (m,) = read_measured_frf(tmp_path / "m.csv")
    assert m.quantity is None and m.coherence is None
    # mag * exp(i phase) rebuilds h to a few ulps of |h|
    np.testing.assert_allclose(m.h, h, rtol=1e-14, atol=0)


def test_uff58_binary_reads_back_exactly_and_ascii_to_its_printed_digits(tmp_path):
    h = known_frf()
    write_uff58(tmp_path / "b.uff", F, h, binary=1)
    (m,) = read_measured_frf(tmp_path / "b.uff")
    assert np.array_equal(m.frequency, F) and np.array_equal(m.h, h)
    assert m.quantity == "acceleration" and "rsp 9:1" in m.label
    write_uff58(tmp_path / "a.unv", F, h, binary=0)
    (m,) = read_measured_frf(tmp_path / "a.unv")
    assert np.array_equal(m.frequency, F)  # even spacing: min and increment are exact here
    # ASCII dataset 58 prints 12 significant digits (E20.11): 5e-12 of each component
    np.testing.assert_allclose(m.h.real, h.real, rtol=5e-12, atol=0)
    np.testing.assert_allclose(m.h.imag, h.imag, rtol=5e-12, atol=0)


def test_uff_file_with_two_frfs(tmp_path):
    write_uff58(tmp_path / "two.uff", F, known_frf(), binary=1)
    write_uff58(tmp_path / "two.uff", F, known_frf(zeta=0.1), binary=1, ordinate=8)
    a, b = read_measured_frf(tmp_path / "two.uff")
    assert np.array_equal(b.h, known_frf(zeta=0.1)) and b.quantity == "displacement"


def test_ringdowns_from_csv_and_uff(tmp_path):
    t = np.arange(2000) * 1e-3
    x = np.exp(-2.0 * t) * np.cos(2 * np.pi * 40 * t)
    lines = ["# quantity: ignored for ring-downs", "time,acceleration"]
    lines += [f"{float(a)!r},{float(b)!r}" for a, b in zip(t, x)]
    (tmp_path / "r.csv").write_text("\n".join(lines) + "\n")
    m = read_measured_history(tmp_path / "r.csv")
    assert m.kind == "acceleration" and np.array_equal(m.signal, x) and np.array_equal(m.time, t)
    write_uff58(
        tmp_path / "r.uff", t, x, binary=1, func_type=1, ordinate=8, denominator=0, abscissa=17
    )
    m = read_measured_history(tmp_path / "r.uff")
    assert m.kind == "displacement" and np.array_equal(m.signal, x)


@pytest.mark.parametrize(
    "text, where",
    [
        ("frequency,re,im\n1,2,3\n2,3,4\n3,4,5\n", "m.csv:1:1: a measured FRF needs the columns"),
        ("frequency_hz,re\n1,2\n2,3\n3,4\n", "m.csv:1:1: a measured FRF needs the columns"),
        ("# only a comment\n", "m.csv: no header row"),
        ("frequency_hz,re,im\n1,2,3\n2,x,4\n3,4,5\n", "m.csv:3:3: 'x' is not a number"),
        ("frequency_hz,re,im\n1,2,3\n2,3\n3,4,5\n", "m.csv:3:1: 2 values, the header has 3"),
        ("frequency_hz,re,im\n1,2,3\n1,3,4\n3,4,5\n", "m.csv:3:1: frequency_hz must increase"),
    ],
)
def test_bad_csv_frfs_are_named(tmp_path, text, where):
    (tmp_path / "m.csv").write_text(text)
    with pytest.raises(InputError) as err:
        read_measured_frf(tmp_path / "m.csv")
    assert where in str(err.value)


def test_a_csv_ringdown_needs_time_and_one_signal(tmp_path):
    (tmp_path / "r.csv").write_text("time,velocity\n0,1\n1,2\n2,3\n")
    with pytest.raises(InputError, match="r.csv:1:1: a measured ring-down needs the columns"):
        read_measured_history(tmp_path / "r.csv")


def test_uff_of_another_dataset_type_is_refused(tmp_path):
    import pyuff

    nodes = pyuff.prepare_15(
        node_nums=[1, 2],
        def_cs=[0, 0],
        disp_cs=[0, 0],
        color=[1, 1],
        x=[0.0, 1.0],
        y=[0.0, 0.0],
        z=[0.0, 0.0],
    )
    pyuff.UFF(str(tmp_path / "nodes.uff")).write_sets(nodes, mode="add")
    with pytest.raises(InputError, match=r"holds UFF dataset type\(s\) 15, not 58"):
        read_measured_frf(tmp_path / "nodes.uff")


def test_uff58_of_another_function_type_is_refused(tmp_path):
    t = np.arange(100) * 1e-3
    write_uff58(
        tmp_path / "time.uff", t, np.sin(t), binary=1, func_type=1, ordinate=12, abscissa=17
    )
    with pytest.raises(InputError, match=r"function type\(s\) 1; an FRF is type 4"):
        read_measured_frf(tmp_path / "time.uff")
    write_uff58(tmp_path / "frf.uff", F, known_frf(), binary=1)
    with pytest.raises(InputError, match="a ring-down is type 1"):
        read_measured_history(tmp_path / "frf.uff")


def test_not_a_uff_file(tmp_path):
    (tmp_path / "junk.uff").write_text("this is no universal file\n")
    with pytest.raises(InputError, match="junk.uff"):
        read_measured_frf(tmp_path / "junk.uff")
    with pytest.raises(InputError, match="no such file"):
        read_measured_frf(tmp_path / "missing.csv")
