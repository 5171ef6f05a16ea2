"""``x3dpd check DECK``: read a deck, build its model and report what is likely wrong before a run.

Exit status 0 when clean, 1 with warnings, 2 with errors (any deck error, printed as one
``FILE:LINE:COL: CARD: message`` line, never a traceback).
"""

from __future__ import annotations

import math

import os
import sys

import click

from x3dpd.api.checks import STEPS_PER_CONTACT, CheckReport, check_model, peak_force_error
from x3dpd.cli.temperature_option import temperature_option
from x3dpd.errors import InputError, X3dpdError
from x3dpd.units import labels_for


def _read_deck(path: str):
    """The project's deck parser (``x3dpd.api.decks.read_deck``)."""
    try:
        from x3dpd.api.decks import read_deck
    except ImportError as exc:  # the parser is being written
        raise InputError(f"cannot read {path}: the deck parser is not available ({exc})") from exc
    return read_deck(path)


@click.command("check")
@click.argument(
    "decks", nargs=-1, required=True, type=click.Path(dir_okay=False), metavar="DECK..."
)
@click.option(
    "--usrfrc",
    "usrfrc",
    multiple=True,
    metavar="SPEC",
    help="External force spec, as for `x3dpd run` (repeatable).",
)
@click.option(
    "--motion",
    "motion",
    multiple=True,
    metavar="SPEC",
    help="Prescribed motion spec, as for `x3dpd run` (repeatable).",
)
@temperature_option
@click.option(
    "--steps-per-contact",
    type=click.IntRange(min=1),
    default=STEPS_PER_CONTACT,
    show_default=True,
    help="Time steps the shortest contact should span.",
)
def check(
    decks: tuple[str, ...],
    usrfrc: tuple[str, ...],
    motion: tuple[str, ...],
    temperature: str | None,
    steps_per_contact: int,
) -> None:
    """Check each DECK: model summary, recommended time step and geometry warnings.

    Several decks are checked one after the other, each report separated by a blank line; an
    unreadable deck is reported and the others are still checked. Exit status: the worst of
    the decks' (0 clean, 1 warnings, 2 errors).
    """
    worst = 0
    for k, deck in enumerate(decks):
        if k:
            click.echo("")
        worst = max(worst, _check_one(deck, usrfrc, motion, steps_per_contact, temperature))
    # SystemExit, not ctx.exit: `x3dpd.cli.main` runs click with standalone_mode=False, where
    # click turns ctx.exit(n) into a return value that main() does not pass on.
    sys.exit(worst)


def _check_one(deck: str, usrfrc, motion, steps_per_contact: int, temperature=None) -> int:
    from x3dpd.api.decks import build_model, with_temperature

    try:
        if not os.path.isfile(deck):
            raise InputError(f"{deck}: no such deck file")
        cards = _read_deck(deck)
        if temperature is not None:
            cards = with_temperature(cards, temperature)
        model = build_model(cards, usrfrc=usrfrc, motion=motion)
    except X3dpdError as exc:
        click.echo(f"x3dpd: error: {exc}", err=True)
        return 2
    report = check_model(model, steps_per_contact=steps_per_contact, usrfrc=usrfrc)
    declared = cards.units is not None
    click.echo(format_report(report, labels_for(model.units), declared=declared))
    return report.exit_status


def format_report(report: CheckReport, units: dict | None = None, declared: bool = False) -> str:
    """Verdict line, each finding (headline, then indented details), then the summary, in the
    deck's ``units`` (labels of x3dpd.units.labels_for; default inch-lbf-s), which a UNITS
    card ``declared`` or not."""
    units = units or labels_for(None)
    return _in_units("\n".join(_report_lines(report, units, declared)), units)


def _in_units(text: str, units: dict) -> str:
    """The model's messages say "length/s" for a speed; name the deck's unit instead."""
    return text.replace("length/s", units["velocity"])


# Over 80 lines: the check report's sections in print order, a short block each.
def _report_lines(report: CheckReport, units: dict, declared: bool = False) -> list[str]:
    n_w, n_e = len(report.warnings), len(report.errors)
    verdict = (
        "clean"
        if not (n_w or n_e)
        else ", ".join(p for p in (_plural(n_e, "error"), _plural(n_w, "warning")) if p)
    )
    note = _step_note(report)
    if note and not (n_e or n_w):
        verdict += ", 1 note"
    lines = [f"{report.path}: {verdict}"]
    for kind, findings in (("error", report.errors), ("warning", report.warnings)):
        for f in findings:
            lines.append(f"{kind}: {f.headline}")
            lines.extend(f"    {d}" for d in f.details)
    if note and not (n_e or n_w):
        lines.append(f"note: {note}")
    lines += ["", "summary"]
    n_p = report.n_particles
    lines.append(
        _row("nodes", f"{report.n_nodes} ({report.n_nodes - n_p} structural, {n_p} particles)")
    )
    for g in report.groups:
        lines.append(
            _row(
                f"particle group {g.group + 1}",
                f"{g.count} (nodes {g.nodes}), radius {g.radius:g} "
                f"{units['length']}, mass {g.mass:.6g} {units['mass']} each",
            )
        )
    lines.append(_row("particle mass", f"{report.particle_mass:.6g} {units['mass']}"))
    lines.append(
        _row(
            "structure mass", f"{report.structure_mass:.6g} {units['mass']} (rigid bodies included)"
        )
    )
    for c in report.cavities:
        box = ", ".join(f"{a} {lo:g} .. {hi:g}" for a, lo, hi in zip("xyz", c.lo, c.hi))
        box += " (extent " + " x ".join(f"{hi - lo:g}" for lo, hi in zip(c.lo, c.hi)) + ")"
        walls = f"{c.n_triangles} triangles in {c.n_faces} faces; " if c.n_triangles else ""
        lines.append(_row(f"cavity set {c.set_id}", f"{box}; {walls}{c.n_particles} particles"))
        lines += [_row("", text) for text in c.analytic_walls]
        if c.wall_material is not None:
            lines.append(_row("", _wall_text(c.wall_material, units["pressure"])))
        if c.volume is not None and c.closed:
            fill = (
                f"fill ratio {c.fill_ratio:.3g} (particle volume {c.particle_volume:.6g})"
                if c.fill_ratio is not None
                else ""
            )
            lines.append(_row("", f"closed, interior volume {c.volume:.6g}; {fill}"))
        else:
            lines.append(_row("", "open: the faces do not close, so no volume or fill ratio"))
    for k, text in enumerate(report.modes):
        lines.append(_row("modal structure" if k == 0 else "", text))
    for k, text in enumerate(report.temperature):
        lines.append(_row("temperature" if k == 0 else "", text))
    lines.append(_row("effects", ", ".join(sorted(report.effects)) or "none"))
    source = "from the UNITS card" if declared else "the default: declare others with a UNITS card"
    lines.append(
        _row(
            "units",
            f"{units['system']} ({source}; mass {units['mass']}, energy {units['energy']})",
        )
    )
    ts = report.time_step
    if ts.binding == "none":
        modes = "; the modes are integrated exactly at any step" if report.modes else ""
        lines.append(
            _row(
                "time step",
                f"DTMAX {ts.dt_deck:.3g} s; no limit (no contacts and no spring or damper on a "
                f"free structural DOF{modes})",
            )
        )
    else:
        lines.append(
            _row(
                "time step",
                f"DTMAX {ts.dt_deck:.3g} s; recommended <= "
                f"{ts.dt_recommended:.3g} s (binding: {ts.binding})",
            )
        )
    if ts.contact_kind != "none":
        lines.append(
            _row(
                "",
                f"contact: {ts.contact_law} {ts.contact_kind} impact at "
                f"{ts.impact_speed:.3g} length/s lasts {ts.t_contact:.3g} s; "
                f"/ {ts.steps_per_contact} = {ts.dt_contact:.3g} s (DTMAX gives "
                f"{ts.deck_steps_per_contact:.3g} steps per contact"
                f"{_peak_force(ts)})",
            )
        )
    if ts.omega_node:
        lines.append(
            _row(
                "",
                f"structure: omega <= {ts.omega_max:.4g} rad/s (node "
                f"{ts.omega_node} {ts.omega_dof}); 0.2 x critical step = "
                f"{ts.dt_structure:.3g} s",
            )
        )
    for path in report.code_files:
        lines.append(
            _row(
                "code run",
                f"{path}: a USRFRC Python file -- running this deck "
                "executes it with your permissions; read it first if the "
                "deck came from someone else (docs/usrfrc.md)",
            )
        )
    if report.rules:
        lines += ["", "rules of thumb (the report's design guidance; notes only)"]
        lines += [_row(rule.code, f"{rule.text} [{rule.section}]") for rule in report.rules]
    return lines


def _wall_text(w, pressure: str) -> str:
    """A cavity's WALLMAT line: its material and the contact modulus E* per particle group."""
    if math.isinf(w.e):
        return "rigid walls (no WALLMAT record)"
    mixed = ", ".join(f"group {g + 1} {e:.6g} {pressure}" for g, e in w.e_star) or "-"
    return (
        f"wall material (WALLMAT): E {w.e:.6g} {pressure}, NU {w.nu:g}, MU {w.mu:g}; "
        f"contact E* {mixed}"
    )


def _step_note(report: CheckReport) -> str | None:
    """Why a deck whose DTMAX exceeds the recommended step is still called clean (no warning:
    its contacts span enough steps to stay stable), so that the verdict and the advice agree."""
    ts = report.time_step
    if ts.binding == "none" or not ts.dt_recommended or ts.dt_deck <= 1.5 * ts.dt_recommended:
        return None
    text = (
        f"DTMAX {ts.dt_deck:.3g} s is {ts.dt_deck / ts.dt_recommended:.1f}x the recommended "
        f"{ts.dt_recommended:.3g} s"
    )
    if ts.contact_kind != "none":
        text += (
            f": it resolves the fastest contact in {ts.deck_steps_per_contact:.3g} steps "
            f"(stable{_peak_force(ts, ';')})"
        )
    return text + "; `x3dpd study DECK` measures what the step costs in accuracy and time"


def _peak_force(ts, sep: str = ",") -> str:
    """', peak force within about X %' where the measured Hertz error applies, else ''."""
    if not ts.knows_peak_force_error:
        return ""
    return f"{sep} peak force within about {peak_force_error(ts.deck_steps_per_contact):.2g} %"


def _row(label: str, text: str) -> str:
    return f"  {label:<16} {text}"


def _plural(n: int, word: str) -> str:
    return "" if n == 0 else f"{n} {word}{'s' if n != 1 else ''}"
