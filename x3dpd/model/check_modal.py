"""What ``x3dpd check`` says about a modal structure (MODAL card): the mode table and warnings.

The modes never limit the step (x3dpd.physics.modal integrates each exactly), so the table
gives each mode's frequency against the step's Nyquist frequency 1/(2 DTMAX) for information.
Warnings: a cavity whose walls hang on a node without shape values (it does not move with the
structure), a rigid-body mode (zero frequency: the structure can drift), a cavity master whose
rotations are held (the cavity translates only; the moments its particles exert go to ground).
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.model.model import Model

_DOFS = ("x", "y", "z", "rx", "ry", "rz")


def modal_table(model: Model) -> list[str]:
    """Lines of the mode table: source, housing, each mode as given and as coupled with the
    deck's mass, and the modal nodes with the DOFs that move."""
    ms = model.modal
    if ms is None:
        return []
    nyquist = 0.5 / model.dt
    plural = "s" if ms.n_modes != 1 else ""
    lines = [
        f"{ms.n_modes} mode{plural} from {ms.source}; housing {ms.housing}"
        + (
            " (the deck's mass on modal nodes coupled in)"
            if ms.housing == "added"
            else " (the modes include the deck's mass on modal nodes)"
        )
    ]
    for k in range(ms.n_modes):
        f = float(ms.freq[k])
        text = (
            f"mode {int(ms.given_numbers[k])}: {float(ms.given_freq[k]):.6g} Hz, zeta "
            f"{float(ms.given_zeta[k]):.4g}"
        )
        if ms.housing == "added" and not np.allclose(ms.shape, ms.given_shape):
            text += f"; coupled mode {k + 1}: {f:.6g} Hz, zeta {float(ms.zeta[k]):.4g}"
        text += f"; {f / nyquist:.3g} x Nyquist (integrated exactly)"
        lines.append(text)
    if ms.coupling.size:
        lines.append(
            "damping couples the coupled modes (largest off-diagonal "
            f"{float(np.max(np.abs(ms.coupling))):.3g} 1/time): applied as a force"
        )
    for j, i in enumerate(ms.nodes):
        moving = [d for d in range(6) if np.any(ms.given_shape[j, d] != 0.0)]
        role = " (rigid body master)" if ms.body[j] >= 0 else ""
        lines.append(
            f"node {int(model.node_ids[i])}{role}: moves in "
            + (", ".join(_DOFS[d] for d in moving) or "no DOF")
        )
    return lines


def modal_warnings(model: Model) -> list[tuple[str, str, list[str]]]:
    """(code, headline, detail lines) of what is likely wrong with a modal structure."""
    ms = model.modal
    if ms is None:
        return []
    out = []
    modal = set(ms.nodes.tolist())
    owner = {}
    for b, m in enumerate(model.rigid_master):
        for s in model.rigid_slaves[model.rigid_ptr[b] : model.rigid_ptr[b + 1]]:
            owner[int(s)] = int(m)
    wall_nodes = set(np.unique(model.tri_nodes).tolist()) | set(
        np.unique(model.shape_nodes).tolist()
    )
    still = sorted({owner.get(n, n) for n in wall_nodes} - modal)
    if still:
        ids = [int(model.node_ids[i]) for i in still]
        out.append(
            (
                "modal-cavity-still",
                f"cavity walls hang on node{'s' if len(ids) > 1 else ''} "
                f"{', '.join(map(str, ids))}, which ha{'ve' if len(ids) > 1 else 's'} no "
                "shape values in the MODAL card: the cavity does not move with the "
                "structure",
                [],
            )
        )
    if ms.housing == "added" and ms.nodes.shape[0]:
        # the deck's mass in each given mode, against its modal mass 1
        flat = ms.given_shape.reshape(-1, ms.given_shape.shape[2])
        big = np.zeros((flat.shape[0], flat.shape[0]))
        for j in range(ms.nodes.shape[0]):
            big[6 * j : 6 * j + 6, 6 * j : 6 * j + 6] = ms.added_mass[j]
        ratio = np.diag(flat.T @ big @ flat)
        if np.any(ratio > 1.0):
            k = int(np.argmax(ratio))
            out.append(
                (
                    "modal-added-mass",
                    "the deck's mass on modal nodes outweighs the modes: in mode "
                    f"{int(ms.given_numbers[k])} it is {ratio[k]:.3g} x the mode's own "
                    f"(modal) mass, and the coupled modes fall to "
                    f"{_freqs(ms.freq)} (given: {_freqs(ms.given_freq)}). The MASS "
                    "records on modal nodes are added to the modes (HOUSING added): a "
                    "report deck's rotary inertias of 1e20 or its SDOF's equivalent mass "
                    "do not belong there",
                    [],
                )
            )
    zero = [int(n) for n, w in zip(ms.given_numbers, ms.omega) if w == 0.0]
    if zero:
        out.append(
            (
                "modal-rigid-body",
                f"mode{'s' if len(zero) > 1 else ''} {', '.join(map(str, zero))} "
                "ha{} zero frequency: the structure is free to drift (a rigid-body mode, "
                "integrated as a free mass)".format("ve" if len(zero) > 1 else "s"),
                [],
            )
        )
    for j, i in enumerate(ms.nodes):
        if ms.body[j] >= 0 and ms.held[j, 3:].all() and model.particle_cavity.shape[0]:
            out.append(
                (
                    "modal-no-rotation",
                    f"the cavity's master node {int(model.node_ids[i])} has no rotational "
                    "shape values: the cavity translates only, and the moments its "
                    "particles exert on it go to ground",
                    [],
                )
            )
    return out


def highest_mode_hz(model: Model) -> float:
    """The highest coupled mode's frequency [cycles per time unit] (0 without modes)."""
    ms = model.modal
    return 0.0 if ms is None or ms.n_modes == 0 else float(ms.omega.max() / (2.0 * math.pi))


def _freqs(f) -> str:
    return ", ".join(f"{x:.4g}" for x in list(f)[:4]) + (" ..." if len(f) > 4 else "") + " Hz"
