"""Step-loop template, part: the pair contacts' three passes run in order
(x3dpd.solver.variants), in one thread or -- threaded variants -- the first two on several.

``_pair_contacts`` runs the filter, the vectorized response and the apply pass of
``_template_pairs`` over the candidate list block by block (PAIR_BLOCK candidates), the
ledger's sums chained through the blocks in list order. A threaded variant
(``Variant.threaded``, the run option ``threads``) runs the first two passes over the blocks on
numba's threads (``_pair_chunks``) and the third, which adds forces and ledger sums, in this
thread in list order: the result does not depend on the thread count, bit for bit
(docs/engine.md, "Threads"). Generated per variant beside
the loop, with the variant's constants (``_template_variant``).
"""

import numba

from x3dpd._jit import step_kernel, threaded_kernel
from x3dpd.solver._template_contact import L_DFRIC, L_DROLL, L_WN, OK
from x3dpd.solver._template_pairs import (AREA, _column_rows, _columns_in, _columns_out,
                                          _pair_apply, _pair_filter, _pair_response)
from x3dpd.solver._template_variant import HAS_ROLLING, HAS_THREADED
from x3dpd.solver.contact_lists import PAIR_BLOCK

#: candidates per chunk of a threaded pair pass, the passes' blocks: a chunk's filter and
#: response run in one thread, its busy candidates in busy positions and history rows lo .. of
#: the chunk's own range (lo = its first candidate) and in a column area of its own, so chunks
#: never share a column. A threaded variant runs the threaded pass when the list has more than
#: one chunk and the last step had at least this many busy candidates (a falling or sparse
#: scene would pay the threads' start and end every step for nothing)
PAIR_CHUNK = PAIR_BLOCK


@threaded_kernel
def _pair_chunks(nchunks, npairs, x, vel, p0, radius, pl_i, pl_j, pl_on, ps, busy, c, hist,
                 counts, particles, dt, history_dt):
    """Passes 1 and 2 of the pair contacts over chunks of :data:`PAIR_CHUNK` candidates, the
    chunks spread over numba's threads: chunk k filters the candidates lo = k PAIR_CHUNK ..
    lo + PAIR_CHUNK - 1 into busy positions from lo on and into column area k
    (``_pair_filter`` with q0 = lo: a chunk has at most that many busy ones, so chunks write
    disjoint entries), writes how many into ``counts[k]`` and evaluates their response
    (``_pair_response``). Nothing a chunk writes is read by another, and no sum runs across
    chunks: the columns come out the same whichever thread ran which chunk."""
    for k in numba.prange(nchunks):
        lo = k * PAIR_CHUNK
        hi = min(npairs, lo + PAIR_CHUNK)
        area = k * AREA
        nb = _pair_filter(lo, hi, lo, area, x, vel, p0, radius, pl_i, pl_j, pl_on, ps, busy, c,
                          hist)
        counts[k] = nb
        if nb > 0:
            rows = _column_rows(c)
            _pair_response(lo, nb, busy, pl_i, pl_j, particles, hist, dt,
                           _columns_in(rows, area), _columns_out(rows, area), history_dt)


@step_kernel
def _pair_contacts(nodes, particles, pairs, stepping, busy):
    """Particle-particle contact forces (report Figure 41) in three passes: the candidates that
    touch (``_pair_filter``), their contact response in columns (``_pair_response``,
    vectorized), and the contact states, the forces on both particles and the ledger in list
    order (``_pair_apply``). State column S_FT holds the friction force on particle j;
    histories: N_MAXWELL terms of i, then N_MAXWELL terms of j, then the tangential law's
    N_TANGENTIAL (the row's last columns). ``busy`` is an int scratch of the list's capacity.
    A threaded variant runs a list of more than one chunk in ``_threaded_pair_contacts`` when
    the last step had at least PAIR_CHUNK busy candidates (``_busy_before``)."""
    if HAS_THREADED:
        # a constant-false branch in every other variant: they compile none of it
        if pairs.count[0] > PAIR_CHUNK and _busy_before(pairs) >= PAIR_CHUNK:
            return _threaded_pair_contacts(nodes, particles, pairs, stepping, busy)
    x, vel = nodes.x, nodes.vel
    p0, radius = particles.p0, particles.radius
    pl_i, pl_j, ps, pl_on, npairs = (pairs.first, pairs.second, pairs.state, pairs.on,
                                     pairs.count[0])
    c = pairs.columns
    hist = pairs.history
    status = OK
    w_normal = 0.0
    w_fric = 0.0
    w_roll = 0.0
    nbusy = 0
    # every block's busy candidates in busy positions and history rows 0 .., and in the
    # scratch's first column area
    for lo in range(0, npairs, PAIR_BLOCK):
        hi = min(npairs, lo + PAIR_BLOCK)
        # pass 1, tight: the candidates that touch now or touched at the last step; most
        # candidates are apart and cost about 2 ns each
        nb = _pair_filter(lo, hi, 0, 0, x, vel, p0, radius, pl_i, pl_j, pl_on, ps, busy, c, hist)
        nbusy += nb
        if nb == 0:
            # nothing touches (a falling or sparse scene): skip the calls and their arguments
            continue
        # pass 2: the contact response, from columns into columns (their views made here: a
        # falling scene, its blocks mostly idle, would pay for 38 of them every step)
        rows = _column_rows(c)
        _pair_response(0, nb, busy, pl_i, pl_j, particles, hist, stepping.dt,
                       _columns_in(rows, 0), _columns_out(rows, 0), stepping.history_dt)
        # pass 3: states, forces and the ledger, the sums chained through the blocks
        status, w_normal, w_fric, w_roll = _pair_apply(0, nb, 0, busy, p0, pl_i, pl_j, ps, pl_on,
                                                       nodes.force, stepping.pen_limit,
                                                       stepping.diag, c, hist, status, w_normal,
                                                       w_fric, w_roll)
    if HAS_THREADED:
        _note_busy(pairs, nbusy)
    _book_pair_work(stepping.ledger, w_normal, w_fric, w_roll)
    return status


@step_kernel
def _threaded_pair_contacts(nodes, particles, pairs, stepping, busy):
    """``_pair_contacts`` of a threaded variant: passes 1 and 2 in chunks on numba's threads
    (``_pair_chunks``), then pass 3 chunk after chunk in list order, its sums chained through
    them -- the same additions in the same order as in one thread."""
    npairs = pairs.count[0]
    nchunks = (npairs + PAIR_CHUNK - 1) // PAIR_CHUNK
    c = pairs.columns
    hist = pairs.history
    # the rebuild's scratch is free while forces run: the chunks' busy counts
    counts = pairs.second_new
    _pair_chunks(nchunks, npairs, nodes.x, nodes.vel, particles.p0, particles.radius,
                 pairs.first, pairs.second, pairs.on, pairs.state, busy, c, hist, counts,
                 particles, stepping.dt, stepping.history_dt)
    status = OK
    w_normal = 0.0
    w_fric = 0.0
    w_roll = 0.0
    for k in range(nchunks):
        lo = k * PAIR_CHUNK
        if counts[k] > 0:
            status, w_normal, w_fric, w_roll = _pair_apply(
                lo, counts[k], k * AREA, busy, particles.p0, pairs.first, pairs.second, pairs.state,
                pairs.on, nodes.force, stepping.pen_limit, stepping.diag, c, hist, status,
                w_normal, w_fric, w_roll)
    _book_pair_work(stepping.ledger, w_normal, w_fric, w_roll)
    return status


@step_kernel
def _busy_before(pairs):
    """How many candidates were busy at the last step: the sum of the chunks' counts the
    threaded pass keeps in the rebuild's scratch (``pairs.second_new``), or of what
    ``_note_busy`` left there. After a list rebuild the scratch holds the rebuild's numbers:
    then only which pass the step takes depends on them, never what it computes."""
    total = 0
    for k in range((pairs.count[0] + PAIR_CHUNK - 1) // PAIR_CHUNK):
        total += pairs.second_new[k]
    return total


@step_kernel
def _note_busy(pairs, nbusy):
    """The one-thread pass's busy count where ``_busy_before`` reads the chunks' counts."""
    counts = pairs.second_new
    counts[0] = nbusy
    for k in range(1, (pairs.count[0] + PAIR_CHUNK - 1) // PAIR_CHUNK):
        counts[k] = 0


@step_kernel
def _book_pair_work(ledger, w_normal, w_fric, w_roll):
    """The pair contacts' sums of the step into the ledger: normal work, friction and rolling
    losses."""
    ledger[L_WN] += w_normal
    ledger[L_DFRIC] += w_fric
    if HAS_ROLLING:
        ledger[L_DROLL] += w_roll
