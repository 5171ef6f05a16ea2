"""``x3dpd materials``: the library as a table, in SI or a deck's units, and by name with
every value's source."""

from __future__ import annotations

from cli_helpers import run_cli

from x3dpd.materials import materials

PSI = 0.45359237 * 9.80665 / 0.0254**2


def test_table_lists_every_material(capsys):
    assert run_cli("materials") == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert len(lines) == 2 + len(materials())
    for m in materials():
        assert any(line.startswith(m.name + " ") for line in lines), m.name
    assert "E [GPa]" in lines[0] and "rho [kg/m^3]" in lines[0]


def test_table_in_the_report_units(capsys):
    """The beam decks' steel (Section 8.2) comes back as its PDMP card: 2.75e7 / 5e6 psi."""
    assert run_cli("materials", "--units", "in", "lbf", "s") == 0
    out = capsys.readouterr().out
    assert "[psi]" in out and "lbf s^2/in^4" in out
    row = next(line for line in out.splitlines() if line.startswith("steel-beam "))
    assert row.split()[1:6] == ["2.75e+07", "5e+06", "/", "2e-06", "0.33"]
    wc = next(line for line in out.splitlines() if line.startswith("tungsten-carbide "))
    assert float(wc.split()[1]) == float(f"{620e9 / PSI:.6g}")


def test_one_material_shows_every_source(capsys):
    assert run_cli("materials", "Tungsten Carbide") == 0
    out = capsys.readouterr().out
    assert out.startswith("tungsten-carbide: ")
    assert out.count("source: ") == 4 and "ASM Handbook" in out


def test_unknown_name_or_unit_is_a_one_line_error(capsys):
    assert run_cli("materials", "unobtainium") == 2
    assert run_cli("materials", "--units", "in", "lbs", "s") == 2
    err = capsys.readouterr().err
    assert "unknown material 'unobtainium'" in err and "FORCE unit 'lbs'" in err
    assert "Traceback" not in err
