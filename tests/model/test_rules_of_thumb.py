"""The report's rules of thumb (x3dpd.model.rules_of_thumb) against closed forms computed here.

The structure is a spring-mounted box (x3dpd.deck.generate, node 9 free along x) or a modal one;
its steady response to F sin(w t) is X = F / sqrt((k - m w^2)^2 + (c w)^2), A = w^2 X (SDOF) or
F |sum_k phi_k^2 / (w_k^2 - w^2 + 2 i zeta_k w_k w)| (modes); over a sweep the peaks are
X_max = F / (2 zeta sqrt(1 - zeta^2) k) and A_max = F / (2 zeta sqrt(1 - zeta^2) m)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from x3dpd.deck import read_deck
from x3dpd.deck.generate import Material3, box_cavity_deck, lattice_fill
from x3dpd.deck.parser import parse_deck
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model
from x3dpd.model.rules_of_thumb import DriveEstimate, drive_estimate, rules_of_thumb

DECKS = Path(__file__).resolve().parents[2] / "decks"
G = 386.1
M, K, C = 2.04213e-4, 11.4823, 3.08293e-4  # report Table 4 [lbf s^2/in, lbf/in, lbf s/in]
F = 4.8404e-3  # [lbf]
# the generator's MATID element mass (Appendix A's 1.0e-12), lumped half on each end (the
# ground's half dropped), joins M
MASS = M + 0.5e-12
R, RHO, MU = 0.03125, 7.32971e-4, 0.30
SIZE = (0.263, 0.372, 0.372)
STEEL = Material3(27.5e6, 5.0e6, 2.0e-6, 0.33, MU, RHO)


def box(drive: str, n: int = 20, gravity=(0.0, -G, 0.0)):
    pos = lattice_fill(SIZE, R, n, gap=0.05 * R)
    deck = box_cavity_deck(
        size=SIZE,
        particles=pos,
        radius=R,
        material=STEEL,
        structure_mass=M,
        stiffness=K,
        damping=C,
        gravity=gravity,
        usrfrc=(drive,) if drive else (),
    )
    return build_model(deck), pos


def rules(model, **kw):
    return {r.code: r for r in rules_of_thumb(model, **kw)}


def sdof_response(w):
    x = F / math.hypot(K - MASS * w * w, C * w)
    return x, w * w * x


def test_sine_drive_turn_on_clearance_and_mass_ratio_closed_form():
    hz = 37.21
    model, pos = box(f"sine:node=9,dof=1,amp={F},hz={hz}")
    x, a = sdof_response(2 * math.pi * hz)
    got = rules(model)
    # drive along x, gravity along -y: they slide at mu g
    assert got["turn-on"].value == pytest.approx(a / (MU * G), rel=1e-9)
    assert "slide" in got["turn-on"].text
    bed = (pos[:, 0] + R).max() - (pos[:, 0] - R).min()
    assert got["clearance"].value == pytest.approx((SIZE[0] - bed) / (2 * x), rel=1e-9)
    mp = 20 * 4 / 3 * math.pi * R**3 * RHO
    assert got["mass-ratio"].value == pytest.approx(mp / MASS, rel=1e-12)
    f_stuck = math.sqrt(K / MASS) / (2 * math.pi) / math.sqrt(1 + mp / MASS)
    assert f"to {f_stuck:.4g} Hz" in got["mass-ratio"].text
    assert "mode-separation" not in got
    assert all(r.section.startswith("report Section") for r in got.values())


@pytest.mark.parametrize(
    "gravity, level",
    [
        ((-G, 0.0, 0.0), G),  # along the drive: lift at 1 g
        (
            (-G / math.sqrt(2), -G / math.sqrt(2), 0.0),  # 45 deg: lift at g / cos 45,
            MU * G * math.sqrt(2),
        ),  # slide at mu g / sin 45: the lower
    ],
)
def test_turn_on_level_follows_the_angle_to_gravity(gravity, level):
    hz = 30.0
    model, _ = box(f"sine:node=9,dof=1,amp={F},hz={hz}", gravity=gravity)
    _, a = sdof_response(2 * math.pi * hz)
    assert rules(model)["turn-on"].value == pytest.approx(a / level, rel=1e-9)


def test_sweep_through_resonance_gives_the_textbook_peaks():
    model, _ = box(f"sweep:node=9,dof=1,amp={F},f0=30,f1=45,rate=1")
    est = drive_estimate(model)
    zeta = C / (2 * math.sqrt(K * MASS))
    q = 2 * zeta * math.sqrt(1 - zeta**2)
    assert est.peak_displacement == pytest.approx(F / (q * K), rel=1e-7)
    assert est.peak_acceleration == pytest.approx(F / (q * MASS), rel=1e-7)
    assert est.hz == pytest.approx(
        math.sqrt(K / MASS) * math.sqrt(1 - 2 * zeta**2) / (2 * math.pi), rel=1e-5
    )


def test_weak_drive_says_the_particles_will_not_move():
    model, _ = box("sine:node=9,dof=1,amp=1e-6,hz=10")
    note = rules(model)["turn-on"]
    assert note.value < 1 and "will not move" in note.text


def test_no_drive_or_a_user_file_is_said_not_estimated(tmp_path):
    model, _ = box("")
    got = rules(model)
    assert math.isnan(got["turn-on"].value) and "no USRFRC drive" in got["turn-on"].text
    assert "clearance" not in got  # no peak displacement to compare
    assert got["mass-ratio"].text.count("total structure mass") == 1
    # a caller's own estimate (the design tools): used as given
    own = DriveEstimate(
        node=9, dof=1, peak_displacement=0.01, peak_acceleration=2 * G, hz=40, description="given"
    )
    got = rules(model, drive=own)
    assert got["turn-on"].value == pytest.approx(2 * G / (MU * G), rel=1e-12)
    assert "given" in got["clearance"].text


def test_modal_structure_closed_form():
    """beam_64_modal with its MODAL card replaced by two modes, HOUSING included (the modes as
    given): 40 Hz zeta 0.01 and 50 Hz zeta 0.02, shape 70 and 30 at node 9 x."""
    text = (DECKS / "beam_64_modal.inp").read_text()
    card = (
        "MODAL\n   MODE 1 40.0 0.01\n   MODE 2 50.0 0.02\n   SHAPE 9 1 70.0 30.0\n"
        "   HOUSING included\nEND\n"
    )
    text = re.sub(r"MODAL\n.*?END\n", card, text, flags=re.DOTALL)
    model = build_model(parse_deck(text, "modal.inp"))
    w = 2 * math.pi * 37.21
    h = sum(
        p * p / complex((2 * math.pi * f) ** 2 - w * w, 2 * z * 2 * math.pi * f * w)
        for f, z, p in ((40.0, 0.01, 70.0), (50.0, 0.02, 30.0))
    )
    est = drive_estimate(model)
    assert est.peak_displacement == pytest.approx(F * abs(h), rel=1e-9)
    assert est.mode == 0
    got = rules(model)
    mp = float(np.sum(model.mass[model.particle_start :]))
    assert mp == pytest.approx(64 * 4 / 3 * math.pi * R**3 * RHO, rel=1e-12)
    assert got["mass-ratio"].value == pytest.approx(mp * 70.0**2, rel=1e-12)
    assert got["mode-separation"].value == pytest.approx(50.0 / 40.0, rel=1e-12)
    assert "12.5 half-power bandwidths" in got["mode-separation"].text
    # without a drive: mode 1 at the cavity's master (node 9), along its largest shape value
    bare = build_model(
        parse_deck(re.sub(r"USRFRC\n.*?END\n", "", text, flags=re.DOTALL), "modal.inp")
    )
    got = rules(bare)
    assert "not estimated" in got["turn-on"].text
    assert got["mass-ratio"].value == pytest.approx(mp * 70.0**2, rel=1e-12)
    assert got["mode-separation"].value == pytest.approx(50.0 / 40.0, rel=1e-12)


def test_check_prints_the_rules_as_notes_and_keeps_its_verdict():
    model = build_model(read_deck(DECKS / "beam_64.inp"))
    report = check_model(model)
    assert [r.code for r in report.rules] == ["turn-on", "clearance", "mass-ratio"]
    assert report.exit_status == 0 and not report.warnings
    # --usrfrc replaces the deck's drive (as for x3dpd run): a sweep through resonance
    sweep = f"sweep:node=9,dof=1,amp={F},f0=30,f1=45,rate=1"
    other = check_model(model, usrfrc=(sweep,)).rules[0]
    assert "sweep" in other.text and other.value > report.rules[0].value


def test_check_command_prints_each_rule_with_its_section(capsys):
    from x3dpd.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["check", str(DECKS / "beam_64.inp")])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{DECKS / 'beam_64.inp'}: clean, 1 note\n")
    tail = out[out.index("rules of thumb") :].splitlines()[1:]
    assert [line.split()[0] for line in tail] == ["turn-on", "clearance", "mass-ratio"]
    assert all(re.search(r"\[report Sections? [0-9.]", line) for line in tail)


@pytest.mark.parametrize("start", ["bottom", "random"])
def test_a_drilled_plates_free_length_is_one_hole_less_one_sphere(start):
    """A PLATES deck: each plate's free length along its holes is thickness + shim - 2r
    (Section 11.2), wherever the spheres start along it (start=random spreads them over the
    free length, one per hole: the bed is one sphere, not the span of all)."""
    text = (DECKS / "mip_apparatus_05.inp").read_text()
    text = re.sub(r"(axis=y)\n", rf"\1 start={start} seed=3\n", text)
    deck = parse_deck(text, "mip.inp")
    plates = re.findall(r"thickness=([\d.]+) shim=([\d.]+)", text)
    free = [float(t) + float(s) - 2 * deck.pdmp[0].rzero for t, s in plates]
    notes = [r for r in rules_of_thumb(build_model(deck)) if r.code == "clearance"]
    assert len(notes) == len(free) == 4
    for note, f in zip(notes, free):
        assert note.value / notes[0].value == pytest.approx(f / free[0], rel=1e-9)
        assert f"free length along y is {f:.3g} in" in note.text
