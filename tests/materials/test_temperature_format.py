"""The ``[material.NAME.temperature]`` format in a user's own library file: an instantaneous
(tangent) expansion table integrated exactly, a mean table's tangent, a room-temperature entry
that keeps working, and every malformed block refused with the file and material named."""

from __future__ import annotations

import pytest

from x3dpd.materials import MaterialError, properties_at, read_library, thermal_strain

ROOM = """
[material.x]
E = { value = 200.0, unit = "GPa", source = "a" }
nu = { value = 0.3, source = "a" }
rho = { value = 8.0, unit = "g/cm^3", source = "a" }
mu = { value = 0.4, source = "a" }
"""
HOT = """
[material.x.temperature]
E = { T_unit = "K", T = [300, 500, 700], values = [200, 190, 170], unit = "GPa", source = "b" }
nu = { value = 0.3, source = "c" }
rho = { from = "expansion", T_unit = "K", at = 300, source = "d" }
"""
TANGENT = (
    'alpha = { T_unit = "K", T = [300, 400, 600], values = [10, 12, 16], unit = "1e-6/K", '
    'reference = 300, source = "e" }\n'
)
MEAN = (
    'alpha_mean = { T_unit = "degC", T = [26.85, 226.85, 426.85], values = [10, 12, 13], '
    'unit = "1e-6/K", reference = 26.85, source = "f" }\n'
)


def library(tmp_path, text: str):
    path = tmp_path / "lib.toml"
    path.write_text(text)
    return read_library(path)[0], path


def test_room_temperature_entries_read_as_before(tmp_path):
    mat, _ = library(tmp_path, ROOM)
    assert mat.temperature is None and mat.E == 200e9


def test_an_instantaneous_table_is_integrated_exactly(tmp_path):
    """alpha linear between points: eps(T) = the trapezoids from T0 = 300 K, written out."""
    mat, _ = library(tmp_path, ROOM + HOT + TANGENT)
    eps_500 = ((10 + 12) / 2 * 100 + (12 + 14) / 2 * 100) * 1e-6  # alpha(500) = 14
    hot = properties_at(mat, 500.0)
    assert hot.strain == pytest.approx(eps_500, rel=1e-12)
    assert hot.alpha == pytest.approx(14e-6, rel=1e-12)
    assert hot.alpha_mean == pytest.approx(eps_500 / 200, rel=1e-12)
    assert properties_at(mat, 300.0).alpha_mean == pytest.approx(10e-6, rel=1e-12)  # alpha(T0)
    assert hot.E == pytest.approx(190e9, rel=1e-12)
    assert hot.rho == pytest.approx(8000.0 / (1 + eps_500) ** 3, rel=1e-12)
    # the material's range is where all tables overlap: 300 to 600 K (E goes to 700)
    with pytest.raises(MaterialError, match="outside its temperature table, 300 K to 600 K"):
        properties_at(mat, 650.0, unit="K")


def test_a_mean_tables_tangent_is_the_derivative_of_its_strain(tmp_path):
    """eps = alpha_mean (T - T0): d eps/dT = alpha_mean + slope (T - T0); at a table point the
    average of the two one-sided slopes."""
    mat, _ = library(tmp_path, ROOM + HOT + MEAN)
    slope_low, slope_high = 2e-6 / 200, 1e-6 / 200
    assert properties_at(mat, 400.0).alpha == pytest.approx(11e-6 + slope_low * 100, rel=1e-12)
    tangent_at_500 = 12e-6 + (slope_low + slope_high) / 2 * 200
    assert properties_at(mat, 500.0).alpha == pytest.approx(tangent_at_500, rel=1e-12)
    assert properties_at(mat, 500.0).strain == pytest.approx(12e-6 * 200, rel=1e-12)
    assert thermal_strain(mat, "300K", "300K") == 0.0


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (ROOM + HOT, "give exactly one of alpha_mean .* or alpha"),
        (ROOM + HOT + TANGENT + MEAN, "give exactly one of alpha_mean"),
        (ROOM + HOT.replace(', source = "b"', "") + TANGENT, "temperature: E has no source"),
        (ROOM + HOT.replace("[300, 500, 700]", "[300, 700, 500]") + TANGENT, "T must increase"),
        (ROOM + HOT.replace("[200, 190, 170]", "[200, 190]") + TANGENT, "the same length"),
        (
            ROOM + HOT.replace('T_unit = "K", T = [300', 'T_unit = "R", T = [300') + TANGENT,
            "E T_unit 'R': expected one of degF, degC, K",
        ),
        (
            ROOM + HOT + TANGENT.replace("reference = 300", "reference = 200"),
            "the reference must lie within the table",
        ),
        (ROOM + HOT + TANGENT.replace("reference = 300, ", ""), "needs its reference"),
        (ROOM + HOT + TANGENT.replace('"1e-6/K"', '"ppm"'), "alpha unit 'ppm': expected one of"),
        (
            ROOM
            + HOT.replace('{ value = 0.3, source = "c" }', '{ value = 0.5, source = "c" }')
            + TANGENT,
            "nu has a value no solid has",
        ),
        (
            ROOM
            + HOT.replace(
                '{ from = "expansion", T_unit = "K", at = 300, source = "d" }',
                '{ value = 8.0, unit = "g/cm^3", source = "d" }',
            )
            + TANGENT,
            "rho cannot be a constant",
        ),
        (ROOM + HOT.replace("[300, 500, 700]", "[800, 900, 1000]") + TANGENT, "do not overlap"),
        (
            ROOM + HOT + TANGENT + 'G = { value = 80.0, unit = "GPa", source = "g" }\n',
            "unknown key.s. G",
        ),
        (ROOM + HOT + TANGENT.replace("T = [300", "T = [-300"), "below absolute zero"),
        (
            ROOM.replace(
                'mu = { value = 0.4, source = "a" }',
                'mu = { value = 0.4, source = "a" }\nmaxwell = [{ E = 5.0, unit = "GPa",'
                ' tau = 2e-6, source = "m" }]',
            )
            + HOT
            + TANGENT,
            "a viscoelastic material cannot have a temperature table",
        ),
    ],
)
def test_malformed_blocks_are_refused_naming_file_and_material(tmp_path, text, message):
    with pytest.raises(MaterialError, match=message) as info:
        library(tmp_path, text)
    assert "lib.toml: material 'x'" in str(info.value)
    assert "\n" not in str(info.value)
