"""Candidate contact lists of the step loop: state-row layout, carrying histories across list
rebuilds and open-contact flags.

A candidate list holds pairs (particle, face) or (particle, particle) that may touch before the
next rebuild; each candidate owns a row of contact state (columns below). All functions take
arrays and scalars only.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd._jit import kernel

__all__ = ["S_A", "S_FN", "S_FT", "S_H", "PAIR_COLUMNS", "PAIR_INPUT_COLUMNS",
           "PAIR_OUTPUT_COLUMNS", "PAIR_BLOCK", "COLUMN_ROW", "WALL_COLUMNS", "WALL_INPUT_COLUMNS",
           "WALL_OUTPUT_COLUMNS", "column_areas", "pair_columns", "wall_columns",
           "history_columns", "_active_flags",
           "_merge_states", "_pair_approach", "kept_histories", "restore_histories"]

# columns of a contact state row
S_A = 0         # geometric approach at the last step (may be negative)
S_FN = 1        # applied normal force (>= 0)
S_FT = 2        # friction force vector on the particle (i for pairs), 3 values
S_H = 5         # Maxwell histories

#: Rows of the pair pass's column scratch (``ContactList.columns``), one column entry per busy
#: candidate. What the pair filter gathers for the contact response (``_pair_filter`` and
#: ``_pair_response`` in the step loop), so that the response reads contiguous columns only:
PAIR_INPUT_COLUMNS = ("dx", "dy", "dz",      # x_j - x_i
                      "vix", "viy", "viz",   # velocity of particle i
                      "wix", "wiy", "wiz",   # its angular velocity
                      "vjx", "vjy", "vjz",   # velocity of particle j
                      "wjx", "wjy", "wjz",   # its angular velocity
                      "a_old", "fn_old",     # the state row's approach and normal force
                      "ftox", "ftoy", "ftoz")  # and its friction force (S_FT)
#: What the vectorized contact response hands to the scalar pass that applies it:
PAIR_OUTPUT_COLUMNS = ("fx", "fy", "fz",           # force on particle j (minus on i)
                       "tix", "tiy", "tiz",        # r_i (n x F_t): subtracted from i's moment
                       "tjx", "tjy", "tjz",        # r_j (n x F_t): subtracted from j's moment
                       "a", "fn",                  # approach and applied normal force
                       "ftx", "fty", "ftz",        # friction force (the state's S_FT columns)
                       "dw", "lost",               # normal work and friction loss of the step
                       "rolled",                   # rolling resistance's loss of the step
                       "rmin")                     # the smaller radius (penetration limit)
PAIR_COLUMNS = PAIR_OUTPUT_COLUMNS + PAIR_INPUT_COLUMNS

#: The wall pass's columns (``_template_wall_columns``), one entry per busy candidate of a
#: block: what the gather pass writes for the response ...
WALL_INPUT_COLUMNS = ("a", "a_old", "fn_old",
                      "ftox", "ftoy", "ftoz",    # the state row's friction force
                      "nx", "ny", "nz",          # the face's normal, into the particle
                      "vx", "vy", "vz",          # the particle's velocity
                      "wx", "wy", "wz",          # its spin
                      "vwx", "vwy", "vwz")       # the wall point's velocity
#: ... what the response hands to the apply pass ...
WALL_OUTPUT_COLUMNS = ("fx", "fy", "fz",         # force on the particle
                       "tx", "ty", "tz",         # moment on it (friction and rolling)
                       "fn", "ftx", "fty", "ftz",
                       "dw", "lost", "rolled")
#: ... and the wall point on its triangle, for the apply pass (the triangle, -1: the contact
#: ended or left the face, and its three barycentric weights)
WALL_COLUMNS = WALL_OUTPUT_COLUMNS + WALL_INPUT_COLUMNS + ("tri", "w0", "w1", "w2")

#: Candidates per block of the pair passes: the passes run block after block of the list (a
#: threaded loop, its blocks on several threads), each block's busy candidates in a column
#: area of their own (``pair_columns``).
PAIR_BLOCK = 1024
#: Padding of each column row: a row stride that is a multiple of 4096 bytes (a list
#: capacity of 512, 1024 ...) maps all the columns onto the same L1 cache sets, more than its
#: ways, and the pair pass ran 1.5x slower (measured on a settled bed of 512).
COLUMN_PAD = 24
#: The stride of a column in the scratch [entries], a constant of the compiled passes: a
#: column entry's address is then the area's base, the entry and a constant offset, with no
#: pointer per column to keep in a register (the filter and apply passes reloaded 21 and 14 of
#: them from the stack per contact; measured on the settled bed of 512: the pair passes 53-54
#: -> 45 us, docs/engine.md, "The pair contact passes").
COLUMN_ROW = PAIR_BLOCK + COLUMN_PAD


def column_areas(capacity: int) -> int:
    """Column areas of a pair list of ``capacity`` candidates: one per block of the list."""
    return max(1, -(-capacity // PAIR_BLOCK))


def pair_columns(capacity: int):
    """The column scratch of a pair list of ``capacity`` candidates, flat: per block of
    :data:`PAIR_BLOCK` candidates an area of one row of :data:`COLUMN_ROW` entries per name in
    :data:`PAIR_COLUMNS` (the entry of column ``C`` for the block's ``k``-th busy candidate at
    area * len(PAIR_COLUMNS) * COLUMN_ROW + C * COLUMN_ROW + k)."""
    return np.zeros(column_areas(capacity) * len(PAIR_COLUMNS) * COLUMN_ROW)


def wall_columns():
    """The wall pass's flat column scratch: one area of :data:`WALL_COLUMNS` rows of
    :data:`COLUMN_ROW` entries (the list's busy candidates, block by block of PAIR_BLOCK)."""
    return np.zeros(len(WALL_COLUMNS) * COLUMN_ROW)


def history_columns(capacity: int, n_history: int):
    """The Maxwell histories of a pair list's busy candidates while the vectorized response
    updates them: (capacity + pad, n_history) in Fortran order, so that one history of
    consecutive busy candidates is contiguous (the law writes ``h[q, k]`` for candidate q)."""
    return np.zeros((capacity + COLUMN_PAD, max(n_history, 1)), order="F")


@kernel
def _merge_states(old_a, old_b, old_s, old_n, new_a, new_b, new_s, new_n, new_approach):
    """Carry contact histories from the old candidate list to the new one (both sorted)."""
    i = 0
    for j in range(new_n):
        while i < old_n and (old_a[i] < new_a[j] or (old_a[i] == new_a[j] and old_b[i] < new_b[j])):
            i += 1
        if i < old_n and old_a[i] == new_a[j] and old_b[i] == new_b[j]:
            for c in range(new_s.shape[1]):
                new_s[j, c] = old_s[i, c]
        else:
            for c in range(new_s.shape[1]):
                new_s[j, c] = 0.0
            new_s[j, S_A] = new_approach[j] if new_approach[j] > 0.0 else 0.0


@kernel
def _active_flags(states, n, on):
    """on[s] = 1 for candidates whose contact is open (approach > 0 or a force), else 0.

    The contact loops test this byte instead of the candidate's state row: at large N that
    saves a strided 50-byte read per candidate per step.
    """
    for s in range(n):
        on[s] = 1 if (states[s, S_A] > 0.0 or states[s, S_FN] != 0.0) else 0


@kernel
def _pair_approach(x, p0, radius, pi, pj, n, out_a):
    for q in range(n):
        i = p0 + pi[q]
        j = p0 + pj[q]
        dx = x[j, 0] - x[i, 0]
        dy = x[j, 1] - x[i, 1]
        dz = x[j, 2] - x[i, 2]
        a = radius[pi[q]] + radius[pj[q]] - math.sqrt(dx * dx + dy * dy + dz * dz)
        out_a[q] = a if a > 0.0 else 0.0


def kept_histories(state, n_law: int, n_roll: int) -> list:
    """(rows, open flags, columns, a copy of those columns) of the tangential law's history
    (``n_law`` values, before the rolling law's ``n_roll`` at the end of each row) in each
    contact state table of ``state`` (walls, pairs, analytic walls), for
    :func:`restore_histories`; empty for a law without history."""
    if not n_law:
        return []
    kept = []
    for rows, on in ((state.ws, state.wl_on), (state.ps, state.pl_on), (state.cs, state.cs_on)):
        columns = slice(rows.shape[1] - n_roll - n_law, rows.shape[1] - n_roll)
        kept.append((rows, on, columns, rows[:, columns].copy()))
    return kept


def restore_histories(kept: list) -> None:
    """Put the histories :func:`kept_histories` copied back into the contacts still open (one
    that ended since keeps its cleared row: a new contact starts from zero)."""
    for rows, on, columns, history in kept:
        still_open = on != 0
        rows[still_open, columns] = history[still_open]
