"""``x3dpd materials``: the library as a table, in SI or a deck's units, and by name with
every value's source."""

from __future__ import annotations

import doctest
import re
import shlex

import pytest
from cli_helpers import ROOT, refused, run_cli

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


# ---------------------------------------------------------------- at temperature (issue 31.5)

ASME_AUSTENITIC_MSI = {800: 24.1, 900: 23.5}  # ASME B31.3 Table C-6, austenitic steels


def _value(out: str, label: str) -> float:
    line = next(line for line in out.splitlines() if line.strip().startswith(label))
    return float(line.split("=")[-1])


def test_a_material_at_a_temperature(capsys):
    """SS-302 at 850 F: E halfway between the ASME row's 800 and 900 F values, the mean
    coefficient from 32 F interpolated between ASM's 600 and 1000 F, and the strain from the
    70 F assembly temperature, each computed here from those numbers."""
    assert run_cli("materials", "SS-302", "--temperature", "850F") == 0
    out = capsys.readouterr().out
    assert out.startswith("steel-302 at 850 °F (727.59 K): ")
    assert "temperature data: 32 °F to 1200 °F" in out
    e_msi = (ASME_AUSTENITIC_MSI[800] + ASME_AUSTENITIC_MSI[900]) / 2
    assert _value(out, "E [GPa]") == pytest.approx(e_msi * 1e6 * PSI / 1e9, rel=1e-5)
    mean = lambda t: 9.9 + (10.2 - 9.9) * (t - 600) / 400  # noqa: E731  x1e-6/F from 32 F
    assert _value(out, "alpha_mean [1e-6/K] from 32 °F") == pytest.approx(mean(850) * 1.8, 1e-3)
    eps70 = 9.6e-6 * (70 - 32)  # the 32-212 F mean
    eps850 = mean(850) * 1e-6 * (850 - 32)
    strain = (eps850 - eps70) / (1 + eps70)
    assert _value(out, "thermal strain from 70 °F (assembly)") == pytest.approx(strain, 1e-5)
    assert out.count("source: ") == 5 and "ASME B31.3 Table C-6" in out
    assert "room-temperature value, used at every temperature" in out  # mu


def test_bare_numbers_follow_the_decks_convention(capsys):
    """A bare temperature is degF with the default (inch-lbf-s) units and degC with metric."""
    assert run_cli("materials", "titanium", "--temperature", "850") == 0
    bare = capsys.readouterr().out
    assert run_cli("materials", "titanium", "--temperature", "850F") == 0
    assert capsys.readouterr().out == bare
    assert run_cli("materials", "titanium", "--temperature", "455", "--units", "m", "N", "s") == 0
    out = capsys.readouterr().out
    assert out.startswith("titanium at 455 °C (728.15 K)") and "E [Pa] = " in out
    assert "alpha_mean [1e-6/°C] from 0 °C" in out
    assert (
        run_cli("materials", "titanium", "--temperature", "850F", "--units", "in", "lbf", "s") == 0
    )
    assert "alpha_mean [1e-6/°F] from 32 °F" in capsys.readouterr().out


def test_the_range_without_a_temperature(capsys):
    assert run_cli("materials", "titanium", "lead") == 0
    out = capsys.readouterr().out
    assert "temperature data: -99.67 °F to 1000 °F" in out
    assert "temperature data: room temperature only (68 °F to 77 °F)" in out
    assert run_cli("materials") == 0
    rows = {line.split()[0]: line.split()[-1] for line in capsys.readouterr().out.splitlines()}
    assert rows["steel-302"] == "32..1200" and rows["steel-report"] == "room"
    assert rows["name"] == "[°F]"


def test_every_material_at_one_temperature(capsys):
    assert run_cli("materials", "--temperature", "850F") == 0
    out = capsys.readouterr().out
    names = [line.split()[0] for line in out.splitlines()[3:-1]]
    hot = [m.name for m in materials() if m.temperature is not None]
    assert names == [n for n in hot if n != "steel-440c"]  # 440C's table stops at 212 F
    assert out.splitlines()[-1].startswith("no data at 850 °F: steel-report, ")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ("titanium", "--temperature", "1200F"),
            "material 'titanium': 1200 °F is outside its temperature table, -99.67 °F to 1000 °F",
        ),
        (
            ("steel-report", "--temperature", "850F"),
            "material 'steel-report' has room-temperature values only (68 °F to 77 °F), not 850 °F",
        ),
        (("302", "alumina", "--temperature", "1300F"), "material 'steel-302': 1300 °F is outside"),
        (("302", "--temperature", "85OF"), "temperature '85OF': expected a number with a unit"),
        (("302", "--temperature", "-500F"), "below absolute zero"),
        (("--temperature", "hot"), "temperature 'hot'"),
    ],
)
def test_bad_temperatures_are_refused(capsys, tmp_path, monkeypatch, args, message):
    """One line, exit 2, no traceback, nothing printed and nothing written."""
    monkeypatch.chdir(tmp_path)
    refused(capsys, "materials", *args, message=message, folder=tmp_path, silent=True)


def _console_blocks(text: str) -> list[tuple[str, str]]:
    """(command, expected output) of every ``$ x3dpd ...`` line in the ```console blocks."""
    out = []
    for block in re.findall(r"```console\n(.*?)```", text, flags=re.S):
        for chunk in re.split(r"^\$ ", block, flags=re.M)[1:]:
            command, _, expected = chunk.partition("\n")
            out.append((command, expected))
    return out


def test_every_number_in_the_docs_is_what_the_command_beside_it_prints(capsys):
    """docs/materials.md: each ```console block's output is the command's, to the character,
    and its Python examples run as doctests."""
    text = (ROOT / "docs" / "materials.md").read_text()
    blocks = _console_blocks(text)
    assert len(blocks) >= 6
    for command, expected in blocks:
        words = shlex.split(command)
        assert words[0] == "x3dpd", command
        status = run_cli(*words[1:])
        out, err = capsys.readouterr()
        assert out + err == expected, command
        assert status == (2 if err else 0), command
    examples = "\n".join(re.findall(r"```pycon\n(.*?)```", text, flags=re.S))
    test = doctest.DocTestParser().get_doctest(examples, {}, "materials.md", None, 0)
    assert len(test.examples) >= 8
    runner = doctest.DocTestRunner()
    runner.run(test)
    assert runner.summarize(verbose=False).failed == 0
