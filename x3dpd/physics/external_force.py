"""External forces on the nodes and their work: the USRFRC card's built-in laws
(x3dpd.physics.usrfrc), the user force files' and the Python forces (report Appendix C, X3D's
USRFRC hook; docs/usrfrc.md).

At the step's new positions every force is added to the node's force sum, and its work over
the step is booked in the ledger's external work, per DOF with the trapezoidal rule on the
half-step velocity,

.. math::  W = \\tfrac12 (f_n + f_{n+1})\\, v_{n+1/2}\\, \\Delta t,

with ``f_n`` the force of the last step (kept per built-in law, since laws may share a DOF,
and per node DOF for the user files and Python forces, which may touch any DOF). Units:
force [force], moment [force x length], work [force x length].

An effect unit (x3dpd.physics.effect_unit): its bundle :class:`AppliedForces` (the force table
of the run's specs, given to the model as ``unit_data["external_force"]["table"]``, and the
Python forces, which the solver sets between steps), its forces in the slot ``force`` after
the other units'. Whether the scene calls user files or Python forces, and the user files'
compiled ``usrfrc``, are the variant's (``variant_args``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.physics.effect_unit import L_WEXT, EffectUnit, StateArray
from x3dpd.physics.usrfrc import KIND_DATA, TABLE_COLUMNS, _force_value, law_count


class AppliedForces(NamedTuple):
    """The external forces of a run: L built-in laws, forces on n nodes."""

    table: np.ndarray        # (L + knots, 9) built-in force laws (x3dpd.physics.usrfrc)
    dofs: np.ndarray         # (L, 2) node index, DOF index of each law
    python: np.ndarray       # (n, 6) forces of Python user files (set between steps)
    row_prev: np.ndarray     # (L,) each law's force at the last step (state)
    user_prev: np.ndarray    # (n, 6) user-file and Python forces at the last step (state)
    user: np.ndarray         # (n, 6) scratch: this step's user-file and Python forces


@kernel
def no_user_force(t, x, vel, force):
    """Stand-in for the user files' ``usrfrc`` in variants without one (never called)."""
    return


@step_kernel
def _external_forces(t, nodes, u, dt, has_user, has_python, user_force):
    """Add the built-in forces, the user files' and the Python forces at time t; return their
    work over the step (trapezoidal, per DOF)."""
    x, vel, force = nodes.x, nodes.vel, nodes.force
    ext_table, frow_prev = u.table, u.row_prev
    wext = 0.0
    # built-in forces act on a few DOFs: work row by row (exact even if rows share a DOF)
    for r in range(ext_table.shape[0]):
        if ext_table[r, 0] == KIND_DATA:  # random signals' knots follow the laws
            break
        i = int(ext_table[r, 1])
        d = int(ext_table[r, 2])
        fe = _force_value(t, ext_table, r)
        force[i, d] += fe
        wext += 0.5 * (frow_prev[r] + fe) * vel[i, d] * dt
        frow_prev[r] = fe
    if has_user or has_python:
        # user forces may touch any DOF
        fext, fext_prev = u.user, u.user_prev
        fe_flat = fext.reshape(-1)
        for k in range(fe_flat.shape[0]):
            fe_flat[k] = 0.0
        if has_user:
            user_force(t, x, vel, fext)
        if has_python:
            for k in range(fe_flat.shape[0]):
                fe_flat[k] += u.python.reshape(-1)[k]
        for i in range(fext.shape[0]):
            for d in range(6):
                fe = fext[i, d]
                if fe != 0.0 or fext_prev[i, d] != 0.0:
                    wext += 0.5 * (fext_prev[i, d] + fe) * vel[i, d] * dt
                    force[i, d] += fe
                    fext_prev[i, d] = fe
    return wext


@step_kernel
def force_hook(u, nodes, rigid, stepping, t, has_user, has_python, user_force):
    """Slot ``force``: the external forces; their work to the ledger."""
    stepping.ledger[L_WEXT] += _external_forces(t, nodes, u, stepping.dt, has_user, has_python,
                                                user_force)


def _setup(model, dt, nodes) -> dict:
    """The force table of the model's ``unit_data["external_force"]`` (none without) and the
    Python forces' array, zero."""
    table = model.unit_data.get("external_force", {}).get("table")
    if table is None:
        table = np.zeros((0, len(TABLE_COLUMNS)))
    table = np.ascontiguousarray(table, np.float64)
    dofs = np.ascontiguousarray(table[:law_count(table), 1:3], np.int64).reshape(-1, 2)
    return {"table": table, "dofs": dofs, "python": np.zeros((model.n_nodes, 6))}


UNIT = EffectUnit(
    name="external_force", flag="external", effects=("external_force",),
    cards=("USRFRC", "--usrfrc"), bundle=AppliedForces, setup=_setup,
    hooks={"force": "force_hook"},
    variant_args=("HAS_USER_FORCE", "HAS_PYTHON_FORCE", "USER_FORCE"),
    state=(StateArray("row_prev", "frow_prev", "dofs"),
           StateArray("user_prev", "fext_prev", "python", (6,))),
    scratch=(("user", "user_prev"),),
    doc="USRFRC: built-in force laws, user force files and Python forces on the nodes")
