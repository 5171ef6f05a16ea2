"""A design of multiple individual particle (MIP) dampers (``[mip]`` and the plate keys,
x3dpd.design.config_mip) and a structure whose mode depends on the drive level (``[levels]``,
x3dpd.design.levels; report Section 11.3, Table 6): the plates each configuration makes, the
structure at each level against its closed form, a dwell's baselines at the level, the errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from x3dpd.api.decks import read_deck
from x3dpd.api.structures import linear_sdof
from x3dpd.api import build
from x3dpd.design.configs import make_configurations
from x3dpd.design.design_file import read_design
from x3dpd.design.explore import run_design
from x3dpd.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "decks" / "mip_apparatus_05.inp"
M = 350.0 / 386.1  # the apparatus's mass (decks/mip_apparatus_05.inp)
RHO = read_deck(DECK).pdmp[0].prho  # SS-302 [lbf s^2/in^4]
TABLE6 = """[levels]
force = [150, 300, 400, 500, 600, 800, 1000, 1200]
frequency = [132, 131, 130, 130, 129, 128, 127, 127]
zeta = [0.047, 0.057, 0.060, 0.065, 0.071, 0.071, 0.071, 0.070]
"""
PLATES_05 = """name = "d0.5"
radius = 0.25
holes = 221
pitch = 0.6
hole = 0.505
thickness = [0.501, 0.5015, 0.502, 0.503]
"""


def design(
    tmp_path,
    *,
    mip="plate_size = 10.0\nend_plate = 0.05\nlumped = true\n",
    vary="shim = [0.006, 0.009]\n",
    configs=(PLATES_05,),
    levels=TABLE6,
    evaluate='kind = "dwell"\nfrequency = 128.0\ndrives = [800.0]\n',
) -> Path:
    text = f'structure = "{DECK}"\n[mip]\n{mip}[vary]\n{vary}'
    text += "".join(f"[[configuration]]\n{c}" for c in configs)
    text += f"{levels}[evaluate]\n{evaluate}"
    path = tmp_path / "mip.toml"
    path.write_text(text)
    return path


def test_each_configuration_is_its_plates(tmp_path):
    made = make_configurations(read_design(design(tmp_path)))
    assert [m.config.name for m in made] == ["d0.5_shim0.006", "d0.5_shim0.009"]
    for m, shim in zip(made, (0.006, 0.009)):
        text = m.text[m.text.index("\nPLATES\n") :]
        assert text.count(f"shim={shim!r}") == 4 and text.count("lumped=yes") == 4
        v = m.values
        # the first plate's hole: 0.501 + shim long, its free length that less the diameter
        assert v["cavity_length"] == pytest.approx(0.501 + shim)
        assert v["clearance"] == pytest.approx(0.501 + shim - 0.5)
        assert v["count"] == 884 and v["cavities"] == 4
        assert v["added_mass"] == pytest.approx(884 * RHO * 4 / 3 * math.pi * 0.25**3, rel=1e-12)
        # lumped: one sphere per plate, of 221 spheres' mass
        assert m.deck.pdmp[0].prho == pytest.approx(221 * RHO)
        assert len(m.deck.contacts[0].slaves[0].nodes) == 1


@pytest.mark.parametrize(
    "drive,f,zeta",
    [(800.0, 128.0, 0.071), (700.0, 128.5, 0.071), (250.0, 131 + 1 / 3, 0.047 + 0.010 * 2 / 3)],
)
def test_the_structure_takes_its_levels_mode(tmp_path, drive, f, zeta):
    """k = m (2 pi f)^2, c = 2 zeta sqrt(k m) at the level, interpolated linearly in the drive
    between Table 6's rows: the particle-free structure's own frequency and damping ratio."""
    ev = f'kind = "dwell"\nfrequency = 128.0\ndrives = [{drive}]\n'
    (made,) = make_configurations(
        read_design(design(tmp_path, vary="shim = [0.009]\n", evaluate=ev))
    )
    sdof = linear_sdof(build(made.deck), 1, 2, ignore_particles=True)
    assert sdof.m == pytest.approx(M, rel=1e-12)
    assert math.sqrt(sdof.k / sdof.m) / (2 * math.pi) == pytest.approx(f, rel=1e-12)
    assert sdof.c / (2 * math.sqrt(sdof.k * sdof.m)) == pytest.approx(zeta, rel=1e-12)
    assert made.values["level"] == drive


def test_several_drives_make_a_configuration_per_level(tmp_path):
    ev = 'kind = "dwell"\nfrequency = 128.0\ndrives = [300.0, 800.0]\n'
    made = make_configurations(read_design(design(tmp_path, vary="shim = [0.009]\n", evaluate=ev)))
    assert [m.config.name for m in made] == ["d0.5_shim0.009_F300", "d0.5_shim0.009_F800"]
    ks = [linear_sdof(build(m.deck), 1, 2, ignore_particles=True).k for m in made]
    assert ks == pytest.approx([M * (2 * math.pi * 131) ** 2, M * (2 * math.pi * 128) ** 2])


def test_a_dwell_credits_the_damper_with_what_it_adds_at_the_level(tmp_path):
    """design.csv's undamped baseline is the level's mode in closed form: at 128 Hz, the
    level's frequency, X = F / (c w) with the level's c (the deck's own 132 Hz, zeta 0.047
    mode would give another)."""
    ev = (
        'kind = "dwell"\nfrequency = 128.0\ndrives = [800.0]\ntol = 0.2\nwindow = 3\n'
        "max_cycles = 30\n"
    )
    rows = run_design(
        design(tmp_path, vary="shim = [0.009]\n", evaluate=ev),
        tmp_path / "out",
        workers=1,
        echo=lambda s: None,
    )
    (row,) = rows
    k = M * (2 * math.pi * 128.0) ** 2
    c = 2 * 0.071 * math.sqrt(k * M)
    assert row["baseline_undamped"] == pytest.approx(800.0 / (c * 2 * math.pi * 128.0), rel=1e-9)
    assert row["amplitude"] < row["baseline_undamped"]  # the damper takes energy out


@pytest.mark.parametrize(
    "change,message",
    [
        (
            dict(evaluate='kind = "dwell"\nfrequency = 128.0\ndrives = [1500.0]\n'),
            r"mip.toml:\d+: evaluate.drives: a drive of 1500 is outside the levels' table",
        ),
        (dict(mip="plate_size = 10.0\ncolour = 1\n"), r"mip.colour: unknown key 'colour'"),
        (dict(configs=(PLATES_05.replace("holes = 221\n", ""),)), r"a MIP damper needs holes"),
        (dict(configs=(PLATES_05 + "count = 3\n",)), r"count does not apply to a MIP damper"),
        (
            dict(configs=(PLATES_05.replace("pitch = 0.6", "pitch = 0.5"),)),
            r"the plates: pitch 0.5 must exceed the hole diameter 0.505",
        ),
        (dict(vary="shim = [-0.003]\n"), r"free length = thickness \+ shim - sphere diameter"),
        (dict(levels=TABLE6.replace("zeta = [0.047,", "zeta = [1.2,")), r"levels.zeta: "),
    ],
)
def test_bad_mip_or_levels_is_one_line_at_its_place(tmp_path, change, message):
    with pytest.raises(InputError, match=message) as exc:
        make_configurations(read_design(design(tmp_path, **change)))
    assert "\n" not in str(exc.value)
    assert np.char.startswith(str(exc.value), str(tmp_path / "mip.toml"))
