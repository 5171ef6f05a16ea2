"""Plots and the convergence table of the Chung & Ooi benchmarks (tools/chung_ooi.py).

``python tools/chung_ooi.py plots`` writes docs/img/chung_ooi_test4.png and
docs/img/chung_ooi_tests_3_5_6_8.png; ``python tools/chung_ooi.py convergence`` prints the
time-step table of docs/physics.md. Each run is a deck through x3dpd.run (a few minutes in all,
most of it compiling the step loops once).
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import chung_ooi as co  # noqa: E402


def _save(fig, path: Path) -> None:
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    print(path)


def make_plots(outdir: Path) -> int:
    outdir.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="chung_ooi_"))
    # test 4
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    refs = (co.T4_TANGENTIAL, co.T4_SPIN, co.T4_REBOUND)
    labels = (
        "tangential restitution v_t'/v_t",
        "final spin [rad/s]",
        "rebound angle of the contact point [deg]",
    )
    for material, mark in (("aluminium oxide", "o-"), ("aluminium alloy", "s--")):
        got = np.array([co.test4_point(material, a, work) for a in co.T4_ANGLES])
        for k, ax in enumerate(axes):
            ax.plot(co.T4_ANGLES, got[:, k], mark, ms=4, label=f"x3dpd mindlin, {material}")
    for k, ax in enumerate(axes):
        ax.plot(co.T4_ANGLES, refs[k], "k^", ms=6, mfc="none", label="Chung & Ooi (digitised)")
        ax.set_xlabel("incident angle [deg]")
        ax.set_ylabel(labels[k])
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Chung & Ooi test 4: oblique impact on a rigid plane, 3.9 m/s, mu 0.092")
    _save(fig, outdir / "chung_ooi_test4.png")

    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    e_in = np.array(co.TESTS[3]["e"])
    for material, mark in (("aluminium oxide", "o"), ("cast iron", "s")):
        axes[0].plot(
            e_in,
            [co.restitution(material, e, work) for e in e_in],
            mark,
            mfc="none",
            label=f"x3dpd HOOKE, {material}",
        )
    axes[0].plot([0, 1], [0, 1], "k-", lw=0.8, label="e_out = e_in")
    axes[0].set(xlabel="input restitution", ylabel="measured restitution", title="test 3")
    for material, mark in (("steel", "o-"), ("polyethylene", "s--")):
        axes[1].plot(
            co.T5_X,
            [co.test5_point(material, x, work) for x in co.T5_X],
            mark,
            ms=4,
            label=f"x3dpd mindlin, {material}",
        )
        axes[1].plot(
            co.T5_X,
            co.T5_SPIN[material],
            "^" if material == "steel" else "v",
            color="k",
            mfc="none",
            label=f"paper (digitised), {material}",
        )
    axes[1].set(
        xscale="log",
        xlabel="v_t / (mu v_n)",
        ylabel="R w' / (mu v_n)",
        title="test 5 (sliding plateau -5)",
    )
    for test, point, mark in ((6, co.test6_point, "o-"), (8, co.test8_point, "s--")):
        axes[2].plot(
            co.T8_CHI,
            [point("aluminium alloy", c, work) for c in co.T8_CHI],
            mark,
            ms=4,
            label=f"x3dpd mindlin + HOOKE e 0.5, test {test}",
        )
    chi = np.linspace(0.05, 0.95, 50)
    axes[2].plot(
        chi,
        [co.sliding_beta(c, 0.5) for c in chi],
        "k-",
        lw=0.8,
        label="gross sliding, closed form",
    )
    axes[2].plot(co.T8_CHI, co.T8_BETA, "k^", mfc="none", label="paper test 8 (digitised)")
    axes[2].set(
        xscale="log",
        xlabel="chi = 3.5 mu (1+e) v_n / v_s",
        ylabel="beta = -v_s'/v_s",
        title="tests 6 and 8",
    )
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    _save(fig, outdir / "chung_ooi_tests_3_5_6_8.png")
    return 0


def convergence_table() -> int:
    work = Path(tempfile.mkdtemp(prefix="chung_ooi_"))
    print(
        "| steps per contact | dt [s] (test 4) | test 1 glass F_max error | test 4 e_t "
        "| test 4 spin | test 4 rebound |"
    )
    print("|---|---|---|---|---|---|")
    t_c = co.hertz_wall("aluminium oxide", 0.0025, 3.9)["contact_time"]
    for n in (25, 50, 100, 200, 400):
        glass = co.normal_impact(1, "glass", work, n)
        f_err = glass["force"] / glass["reference"]["force"] - 1.0
        got = np.array([co.test4_point("aluminium oxide", a, work, n) for a in co.T4_ANGLES])
        errs = [
            co.mean_relative_error(got[:, k], r)
            for k, r in enumerate((co.T4_TANGENTIAL, co.T4_SPIN, co.T4_REBOUND))
        ]
        print(
            f"| {n} | {t_c / n:.3g} | {f_err:.2e} | "
            + " | ".join(f"{100 * e:.2f} %" for e in errs)
            + " |"
        )
    return 0
