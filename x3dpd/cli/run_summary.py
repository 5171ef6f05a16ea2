"""The summary ``x3dpd run`` prints at the end of a run (docs/running.md, "Progress and
summary")."""

from __future__ import annotations


def format_summary(deck: str, s: dict) -> str:
    """The summary ``x3dpd run`` prints (docs/running.md, "Progress and summary")."""
    from x3dpd.api.traces import ENERGY_COLUMNS

    lines = [
        f"x3dpd: {deck} -> {s['trace_file']}, {s['energy_file']} ({s['status']})",
        f"  effects        {', '.join(s['effects']) or 'none'}",
    ]
    if s.get("usrfrc_replaced"):
        lines.append(
            f"  drive          {'; '.join(s['usrfrc'])} (replaces the deck's USRFRC "
            f"{'; '.join(s['usrfrc_replaced'])}; --usrfrc-add adds instead)"
        )
    for path in s.get("code_files", ()):
        lines.append(f"  code run       {path} (a USRFRC Python file: this run executed it)")
    step = s.get("step")
    if step:
        at = (
            f"at a step chosen by accuracy ({step['min']:.4g} .. {step['max']:.4g} s, mean "
            f"{step['mean']:.4g} s since t0; bounds {step['dtmin']:.4g} .. "
            f"{step['dtmax']:.4g} s), trace every {s['itrac'] * s['dt']:.6g} s"
            if step["steps"]
            else "at a step chosen by accuracy"
        )
    else:
        at = f"at dt {s['dt']:.6g} s, trace every {s['itrac']} steps"
    lines += [
        f"  steps          {s['steps']} this run; t = {s['t_start']:.9g} .. {s['t_end']:.9g} s "
        f"{at}",
        f"  wall time      {s['wall_s']:.2f} s (setup and first-call compile/load "
        f"{s['compile_s']:.2f} s)",
    ]
    rate = s["steps_per_s"]
    if rate == rate and rate > 0:
        lines.append(f"  speed          {rate:,.0f} steps/s, {1e6 / rate:.3g} us/step")
    if s["dumps"]:
        lines.append(f"  restart dumps  {s['dumps']} written to {s['restart_file']}")
    e = s["last_energy"]
    if e is not None:
        from x3dpd.units import labels_for

        lab = labels_for(s.get("units"))
        lines.append(
            f"  energy ledger at t = {e['time']:.9g} {lab['time']} (energies in {lab['energy']})"
        )
        names = ENERGY_COLUMNS[1:11] + (
            ("dissipated_rolling",) if "dissipated_rolling" in e else ()
        )
        for name in names:
            lines.append(f"    {name:<24} {e[name]: .6e}")
        total = (
            e["dissipated_viscoelastic"]
            + e["dissipated_friction"]
            + e["dissipated_dampers"]
            + e.get("dissipated_rolling", 0.0)
        )
        lines.append(f"    {'dissipated (total)':<24} {total: .6e}")
        lines.append(
            f"    {'residual':<24} {e['residual']: .6e} ({s['residual']:+.2e} of the "
            f"energy scale {s['energy_scale']:.6g})"
        )
    return "\n".join(lines)
