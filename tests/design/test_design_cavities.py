"""Several cavities per configuration (``cavities``, ``[cavity] masters``, ``spacing``;
docs/design.md "Several cavities"): N identical cavities each with n particles against the
closed forms of their count and added mass, the copies' particles replaying the first cavity's
motion (free fall, then the same bounces), cavities on other master nodes, and the errors."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import x3dpd
from x3dpd.api.decks import Element, Node, format_deck, write_deck
from x3dpd.design.configs import make_configurations
from x3dpd.design.design_file import read_design
from x3dpd.design.explore import run_design
from x3dpd.design.sweep import read_csv
from x3dpd.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
BEAM_64 = ROOT / "decks" / "beam_64.inp"
#: beam_64's particles: steel, 0.283 lbf/in^3 over g (decks/beam_64.inp's header)
RHO = 0.000732971
G = 386.1
#: beam_64's box cavity, corner nodes at x 0..0.263, y 0..0.372, z 0..0.372 [in]
BOX = np.array([0.263, 0.372, 0.372])


def write(tmp_path: Path, text: str, name: str = "design.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _design(
    tmp_path,
    structure=BEAM_64,
    fill="count = 8\nradius = 0.0625\n",
    vary="cavities = [1, 2, 3]\n",
    cavity="",
    evaluate=None,
) -> Path:
    evaluate = evaluate or ('kind = "dwell"\nfrequency = 37.2\ndrives = [4.84040e-3]\n')
    return write(
        tmp_path,
        f'structure = "{structure}"\n{cavity}[fill]\n{fill}dt = 5e-7\n'
        f"gap_fraction = 0.05\n[vary]\n{vary}[evaluate]\n{evaluate}",
    )


def _boxes(deck) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """{CONTACT set: (low corner, high corner)} of each box cavity."""
    xyz = {n.nid: np.array([n.x, n.y, n.z]) for n in deck.nodes}
    out: dict[int, list] = {}
    for c in deck.contacts:
        for t in c.triangles:
            out.setdefault(t.set_id, []).extend(xyz[k] for k in t.nodes)
    return {s: (np.min(p, axis=0), np.max(p, axis=0)) for s, p in out.items()}


def _particles(deck) -> dict[int, np.ndarray]:
    """{CONTACT set: (n, 3) centres of its particles, in slave-list order}."""
    xyz = {n.nid: np.array([n.x, n.y, n.z]) for n in deck.nodes}
    return {s.set_id: np.array([xyz[k] for k in s.nodes]) for c in deck.contacts for s in c.slaves}


def test_n_identical_cavities_hold_n_times_the_particles_and_the_added_mass(tmp_path):
    r, n = 0.0625, 8
    made = make_configurations(read_design(_design(tmp_path)))
    one = 4.0 / 3.0 * math.pi * r**3 * RHO  # a sphere's mass, rho 4/3 pi R^3
    structure = x3dpd.check(BEAM_64).structure_mass
    first = None
    for m, cavities in zip(made, (1, 2, 3)):
        v = m.values
        assert (v["cavities"], v["count"]) == (cavities, cavities * n)
        assert v["added_mass"] == pytest.approx(cavities * n * one, rel=1e-12)
        report = x3dpd.check(m.deck)
        assert report.exit_status == 0
        assert report.structure_mass == structure  # no housing mass in beam_64
        assert v["mass_ratio"] == pytest.approx(cavities * n * one / structure, rel=1e-12)
        # a cavity's fill ratio: n spheres over the box's volume, in every configuration
        assert v["fill_ratio"] == pytest.approx(n * 4 / 3 * math.pi * r**3 / BOX.prod(), rel=1e-12)
        boxes, parts = _boxes(m.deck), _particles(m.deck)
        assert sorted(boxes) == sorted(parts) and len(boxes) == cavities
        lows = sorted(boxes.values(), key=lambda b: b[0][2])
        for (_, hi), (lo2, _) in zip(lows, lows[1:]):  # side by side along z, apart
            assert lo2[2] > hi[2]
        base = parts[min(parts)]
        first = base if first is None else first
        assert np.array_equal(base, first)  # cavity 0 as with one cavity
        for s, (lo, hi) in boxes.items():
            assert hi - lo == pytest.approx(BOX, abs=1e-15)  # identical boxes
            # the same particles, moved with their cavity, each inside it
            assert parts[s] - lo == pytest.approx(base - boxes[min(boxes)][0], abs=1e-14)
            assert np.all(parts[s] >= lo + r) and np.all(parts[s] <= hi - r)
        (rb,) = m.deck.rbels  # every wall on master 9
        assert rb.master == 9 and len(rb.slaves) == 8 * cavities


def test_the_copies_particles_replay_the_first_cavitys_free_fall_and_bounces(tmp_path):
    # one sphere per cavity, 3 cavities on the beam's master: before it reaches the floor each
    # falls freely, y = y0 - g t^2 / 2 (the central-difference scheme is exact for a constant
    # acceleration); after, every copy bounces as the first (same walls, same master, particles
    # of different cavities never touch): positions relative to their cavity agree to 1e-9 in
    # over 30 ms (rounding differences, ~1e-16 in, grow little over a few soft bounces)
    (m,) = make_configurations(
        read_design(_design(tmp_path, fill="count = 1\nradius = 0.0625\n", vary="cavities = [3]\n"))
    )
    path = tmp_path / "three.inp"
    path.write_text(m.text)
    res = x3dpd.run(path, tmax=0.03)
    tr = res.trace
    ids = tr.node_ids.tolist()
    parts = _particles(m.deck)
    lows = {s: lo for s, (lo, _) in _boxes(m.deck).items()}
    nodlim = m.deck.pdmp[0].nodlim
    pid = {s: ids.index(nodlim + 1 + k) for k, s in enumerate(sorted(parts))}
    first = min(parts)
    y0 = parts[first][0, 1]
    falling = tr.time < math.sqrt(2.0 * (y0 - 0.0625) / G) * 0.9
    assert falling.sum() >= 3
    for s, k in pid.items():
        assert tr.position[falling, k, 1] == pytest.approx(
            y0 - G * tr.time[falling] ** 2 / 2, abs=1e-12
        )
        np.testing.assert_allclose(
            tr.position[:, k, :] - (lows[s] - lows[first]),
            tr.position[:, pid[first], :],
            rtol=0,
            atol=1e-9,
        )
        np.testing.assert_allclose(
            tr.velocity[:, k, :], tr.velocity[:, pid[first], :], rtol=0, atol=1e-6
        )
    assert np.ptp(tr.position[:, pid[first], 1]) > 0.002  # it did fall and bounce


def _two_masters(tmp_path: Path) -> Path:
    """beam_64's structure without its particles plus a second master node 10 at x = 1 in on
    its own spring (the same mass, spring and boundary as node 9): a lumped 2-DOF structure."""
    deck = x3dpd.load_deck(BEAM_64)
    pd = deck.pdmp[0]
    nodes = tuple(n for n in deck.nodes if n.nid <= 9) + (Node(10, 1.0, 0.0, 0.0),)
    (mass,), (el,) = deck.masses, deck.elements
    (bc,) = deck.boundaries
    deck = replace(
        deck,
        nodes=nodes,
        pdmp=(replace(pd, nodlim=10),),
        masses=(mass, replace(mass, nid=10)),
        elements=(el, Element(2, el.mid, (10,))),
        boundaries=(bc, replace(bc, first=10, last=10)),
        contacts=tuple(replace(c, slaves=()) for c in deck.contacts),
        trace=replace(deck.trace, nodes=(9, 10)),
        initials=(),
    )
    write_deck(deck, tmp_path / "two.inp")
    return tmp_path / "two.inp"


def test_cavities_go_on_the_master_nodes_the_design_names(tmp_path):
    two = _two_masters(tmp_path)
    made = make_configurations(
        read_design(
            _design(
                tmp_path,
                structure=two,
                vary="cavities = [2, 3]\n",
                cavity="[cavity]\nmasters = [9, 10, 10]\nspacing = [0, 0, 0.5]\n",
            )
        )
    )
    for m, cavities in zip(made, (2, 3)):
        assert x3dpd.check(m.deck).exit_status == 0
        boxes = [lo for lo, _ in sorted(_boxes(m.deck).values(), key=lambda b: tuple(b[0]))]
        # cavity 0 at the origin on node 9; cavity 1 on node 10 (x = 1); cavity 2 also on
        # node 10, one spacing further
        want = [(0, 0, 0), (1, 0, 0), (1, 0, 0.5)][:cavities]
        assert [tuple(b) for b in boxes] == [pytest.approx(w, abs=1e-15) for w in want]
        bodies = {rb.master: len(rb.slaves) for rb in m.deck.rbels}
        assert bodies == {9: 8, 10: 8 * (cavities - 1)}
        assert m.values["count"] == 8 * cavities


@pytest.mark.parametrize(
    "case, text, message",
    [
        ("zero", "cavities = [0, 2]\n", r":\d+: vary.cavities: expected a value > 0"),
        ("masters", "cavities = [2]\n", r":\d+: cavity.masters: node 1 is not a structural node"),
        ("too few", "cavities = [3]\n", r"masters lists 2 master nodes; give one per cavity"),
    ],
)
def test_a_bad_cavities_setting_is_refused_at_its_line(tmp_path, case, text, message):
    cavity = {
        "masters": "[cavity]\nmasters = [9, 1]\n",
        "too few": "[cavity]\nmasters = [9, 9]\n",
    }.get(case, "")
    with pytest.raises(InputError, match=message):
        make_configurations(read_design(_design(tmp_path, vary=text, cavity=cavity)))


def test_several_cavities_need_the_cavity_on_a_master_node(tmp_path):
    # decks/impact_wall.inp: a fixed wall, no rigid body to copy the cavity onto
    spec = write(
        tmp_path,
        f'structure = "{ROOT / "decks" / "impact_wall.inp"}"\n[fill]\n'
        'cavities = 2\n[evaluate]\nkind = "ringdown"\n',
    )
    with pytest.raises(InputError, match=r"cavities: .*not all in one rigid body \(RBEL\)"):
        make_configurations(read_design(spec))


def test_design_csv_carries_the_cavities_and_the_stiffness_scale(tmp_path):
    # one configuration, 3 cavities of one sphere each, contacts 10x softer: a short dwell
    spec = _design(
        tmp_path,
        fill="count = 1\nradius = 0.0625\n",
        vary="cavities = [3]\nstiffness_scale = [0.1]\n",
        evaluate='kind = "dwell"\nfrequency = 37.2\ndrives = [9.68080e-3]\n'
        'baselines = ["added-mass"]\nwindow = 2\nmax_cycles = 6\n',
    )
    rows = run_design(spec, tmp_path / "out", workers=1, echo=lambda s: None)
    (row,) = read_csv(tmp_path / "out" / "design.csv")
    assert row["config"] == rows[0]["config"] == "cav3_Ex0.1"
    assert (row["count"], row["cavities"], row["stiffness_scale"]) == (3, 3, 0.1)
    assert row["dt"] == pytest.approx(5e-7 * 0.1**-0.4, rel=1e-12)
    one = 4.0 / 3.0 * math.pi * 0.0625**3 * RHO
    assert row["added_mass"] == pytest.approx(3 * one, rel=1e-12)
    # the added-mass baseline carries all three cavities' particles: the beam's SDOF (its MASS
    # plus half its spring element's 1e-12, its spring's KX and C) with m + 3 m_p,
    # X = F / |k - (m + 3 m_p) w^2 + i c w|
    beam = x3dpd.load_deck(BEAM_64)
    (mass,), (mat,) = beam.masses, beam.materials
    m = mass.mass + 0.5 * mat.mass + 3 * one
    w = 2 * math.pi * 37.2
    want = 9.68080e-3 / abs(complex(mat.kx - m * w * w, mat.c * w))
    assert row["baseline_added_mass"] == pytest.approx(want, rel=1e-9)
    deck = x3dpd.load_deck(tmp_path / "out" / "configs" / "cav3_Ex0.1" / "cav3_Ex0.1.inp")
    assert deck.pdmp[0].e0 == pytest.approx(27.5e6 * 0.1, rel=1e-15)
    assert len(_boxes(deck)) == 3
    assert format_deck(deck)  # the kept deck reads back and writes
