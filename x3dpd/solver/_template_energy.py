"""Step-loop template, part: the energies of a state and the ledger row (x3dpd.solver.variants).

Generated per variant beside the loop, with the variant's constants (``_template_variant``).
Inlined into the step loop at its one output site; Python reaches them through the loop's
SNAPSHOT mode (x3dpd.solver.simulation), so each variant compiles them once.
"""

from x3dpd._jit import step_kernel
from x3dpd.solver._template_contact import (CONTACT_TAIL, L_DDAMP, L_DFRIC, L_DROLL, L_WEXT,
                                            L_WN)
from x3dpd.solver._template_variant import (FILLED_ENERGY, HAS_PAIRS, HAS_ROLLING, HAS_SHAPES,
                                            HAS_VISCOELASTIC, HAS_WALLS,
                                            NORMAL_DAMPED, NORMAL_STORED_ENERGY, SLOT_ENERGY,
                                            TANGENTIAL_STORED_ENERGY, TANGENTIAL_STORES)
from x3dpd.solver.contact_lists import S_A, S_FN, S_FT


@step_kernel
def _energies(nodes, particles, walls, pairs, shapes, units, dt, out):
    """out[0:6] = KE_trans, KE_rot, U_grav, U_spring, U_contact, S (Verlet correction).

    The effect units add theirs in the slot ``energy`` (x3dpd.physics.effect_unit): gravity's
    potential in U_grav (x3dpd.physics.gravity), a modal
    structure's kinetic energy counts in KE_trans, its strain energy in U_spring and its forces
    in S (modal mass 1): x3dpd.physics.modal."""
    x, vel, force = nodes.x, nodes.vel, nodes.force
    kin_mass, kin_inertia, inv_m = nodes.kin_mass, nodes.kin_inertia, nodes.inv_m
    ke_t = 0.0
    ke_r = 0.0
    shadow = 0.0
    for i in range(x.shape[0]):
        m = kin_mass[i]
        if m != 0.0:
            ke_t += 0.5 * m * (vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
        for d in range(3):
            ke_r += 0.5 * kin_inertia[i, d] * vel[i, 3 + d] ** 2
        for d in range(6):
            shadow += force[i, d] ** 2 * inv_m[i, d]
    out[0] = ke_t
    out[1] = ke_r
    out[2] = 0.0
    out[3] = 0.0
    if FILLED_ENERGY:
        shadow += SLOT_ENERGY(units, nodes, out)
    out[4] = (_contact_energy(particles, walls, pairs, shapes)
              if (HAS_WALLS or HAS_PAIRS or HAS_SHAPES) else 0.0)
    out[5] = dt * dt / 8.0 * shadow


@step_kernel
def _contact_energy(particles, walls, pairs, shapes):
    """Elastic energy stored in the open contacts, by the normal law's ``stored_energy`` and
    the tangential law's (a spring's: x3dpd.physics.tangential_laws)."""
    u = 0.0
    ws = walls.state
    for s in range(walls.count[0]):
        if ws[s, S_A] > 0.0:
            k = particles.law_wall[walls.first[s], 0]
            u += NORMAL_STORED_ENERGY(ws[s, S_FN], ws[s, S_A], k)
            if TANGENTIAL_STORES:
                u += _tangential_energy(ws, s)
    ps = pairs.state
    kind = particles.kind
    for s in range(pairs.count[0]):
        if ps[s, S_A] > 0.0:
            k = particles.law_pair[kind[pairs.first[s]], kind[pairs.second[s]], 0]
            u += NORMAL_STORED_ENERGY(ps[s, S_FN], ps[s, S_A], k)
            if TANGENTIAL_STORES:
                u += _tangential_energy(ps, s)
    if HAS_SHAPES:
        cs = shapes.state
        for s in range(cs.shape[0]):
            if cs[s, S_A] > 0.0:
                k = particles.law_wall[shapes.row_particle[s], 0]
                u += NORMAL_STORED_ENERGY(cs[s, S_FN], cs[s, S_A], k)
                if TANGENTIAL_STORES:
                    u += _tangential_energy(cs, s)
    return u


@step_kernel
def _tangential_energy(states, s):
    """The tangential law's stored energy in state row ``s`` (force in S_FT, history in the
    row's last N_TANGENTIAL columns)."""
    return TANGENTIAL_STORED_ENERGY(states[s, S_FT], states[s, S_FT + 1], states[s, S_FT + 2],
                                    states, s, states.shape[1] - CONTACT_TAIL)


@step_kernel
def _ledger_row(t, en, ledger, e_ref, row):
    """row = t, KE_t, KE_r, U_g, U_s, U_c, D_visc, D_fric, D_damp, W_ext, E_total, residual
    (and D_roll, the rolling resistance's dissipation, in a scene with a rolling law: its row
    has that 13th column, x3dpd.solver.simulation.energy_columns).

    D_visc = W_N - U_c when contacts are viscoelastic or damped (absorbed minus still stored);
    elastic
    contacts dissipate nothing by definition, so their integration error shows in the residual.
    """
    row[0] = t
    for k in range(5):
        row[1 + k] = en[k]
    if HAS_VISCOELASTIC or NORMAL_DAMPED:
        row[6] = ledger[L_WN] - en[4]
    else:
        row[6] = 0.0
    row[7] = ledger[L_DFRIC]
    row[8] = ledger[L_DDAMP]
    row[9] = ledger[L_WEXT]
    e_total = en[0] + en[1] + en[2] + en[3] + en[4]
    row[10] = e_total
    row[11] = (e_total - en[5]) - e_ref + row[6] + row[7] + row[8] - row[9]
    if HAS_ROLLING:
        row[12] = ledger[L_DROLL]
        row[11] += row[12]
