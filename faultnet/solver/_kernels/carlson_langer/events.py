"""The event loop: load the plate to the next failure, run one slip event.

The entry kernels below are the only ones the Python layer calls for a run, one per crossing
treatment, so that a run compiles only the code it uses.  Each passes its event integration
(:mod:`.slip`) to the shared event loop: ``run_events_dopri5`` (DP5 steps, exact crossings) and
``run_events_dopri5_interpolated`` (DP5 steps, crossings on each step's dense output).

They advance the model by up to ``n_req`` events and fill preallocated catalog arrays.  The
return value is a status code (``STATUS_*``); the counters in ``work.cnt`` are named in
:mod:`faultnet.solver._kernels.layout` (``CNT_*``).

Arguments of the kernels here: ``ev`` (an event's number), ``hyp`` (its hypocentre), ``w`` (the
plate position), ``nact`` and ``ntouch`` (the lengths of the active and the touched lists),
``integrate`` (the event's
integration, :mod:`.slip`); of the entry kernels: ``n_req`` (events requested), ``ev0`` (the first
one's number), the bundles (:mod:`~faultnet.solver._kernels.bundles`)
``state`` (z, frame, failure keys and
their tree), ``graph`` (topology and per-block parameters), ``work`` (work space, step context,
counters) and ``records`` (catalog, slips, traces, profiles, the last event's row), and ``ctrl``
(options, ``layout.CTRL_*``), ``cls`` (int64[N]: each block's parameter class) and ``solo``
(float64[n_classes, SOLO_SIZE]: the classes' cached solo slips, ``layout.SOLO_*``, NaN until
computed).
"""

import math

import numpy as np

from faultnet.solver._kernels.carlson_langer.crossing import (
    STATUS_EVENT_TOO_LONG,
    STATUS_INTERRUPTED,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_RUNAWAY,
    STATUS_SLIPS_FULL,
)
from faultnet.solver._kernels.carlson_langer.physics import block_key
from faultnet.solver._kernels.carlson_langer.slip import (
    integrate_exact,
    integrate_interpolated,
    record_trace,
)
from faultnet.solver._kernels.carlson_langer.solo import solo_apply, solo_end, solo_free, solo_start
from faultnet.solver._kernels.carlson_langer.stepping import activate, join_scan, touch
from faultnet.solver._kernels.carlson_langer.tree import build_keys_and_tree, tree_update
from faultnet.solver._kernels.carlson_langer.work import (
    ACTIVE,
    FLAG,
    FSEEN,
    P2,
    PLATE,
    Q2,
    STUCK,
    TOUCH,
    UNTOUCHED,
    VN,
    D,
    P,
    Q,
    V,
)
from faultnet.solver._kernels.jit import entry, inline_kernel, kelvin_kernel, kernel
from faultnet.solver._kernels.layout import (
    CAT_BLOCKS,
    CAT_DURATION,
    CAT_FAULTS,
    CAT_HYPOCENTER,
    CAT_S,
    CAT_STEPS,
    CAT_T,
    CNT_EVENTS,
    CNT_SLIP_ROWS,
    CNT_STEPS,
    CNT_TRACE_ROWS,
    CTRL_REBUILD,
    CTRL_SOLO_CACHE,
    OUT_BLOCKS,
    OUT_DURATION,
    OUT_FAULTS,
    OUT_HYPOCENTER,
    OUT_SLIP,
    OUT_STEPS,
    OUT_T,
    SCAL_OFFSET,
    SCAL_W,
    SOLO_DURATION,
    SOLO_SLIP,
    SOLO_SPEED,
    SOLO_STEPS,
)

__all__ = [
    "STATUS_OK",
    "STATUS_SLIPS_FULL",
    "STATUS_NONFINITE",
    "STATUS_RUNAWAY",
    "STATUS_EVENT_TOO_LONG",
    "RECENTRE_AT",
    "run_events_dopri5",
    "run_events_dopri5_interpolated",
]

#: the re-centred plate coordinate ``w`` is shifted back by an integer once it
#: exceeds this, so coordinates stay O(1) however long the run
RECENTRE_AT = 4.0


@kernel
def _finish_event(ntouch, ev, state, graph, work, records):
    """Apply the slips, refresh keys of touched blocks, reset the work rows.

    Returns the total slip, the blocks that slipped and the faults they are on.
    """
    z, keys, tree = state.z, state.keys, state.tree
    W, IW, cnt = work.W, work.IW, work.cnt
    slip_event, slip_node, slip_val = records.slip_event, records.slip_node, records.slip_val
    total = 0.0
    nblk = nflt = 0
    rec = len(slip_val) > 0
    row = cnt[CNT_SLIP_ROWS]
    for q in range(ntouch):
        j = IW[TOUCH, q]
        if IW[FLAG, j] == STUCK:
            s = W[j, D]
            total += s
            nblk += 1
            f = graph.fault[j]
            if IW[FSEEN, f] != ev + 1:  # the fault's first block in this event
                IW[FSEEN, f] = ev + 1
                nflt += 1
            z[j] += s
            if rec:
                slip_event[row] = ev
                slip_node[row] = j
                slip_val[row] = s
                row += 1
    cnt[CNT_SLIP_ROWS] = row
    off = state.scal[SCAL_OFFSET]
    for q in range(ntouch):
        j = IW[TOUCH, q]
        keys[j] = block_key(j, z, off, graph)
        tree_update(j, keys, tree)
        W[j, D] = 0.0
        W[j, P] = 0.0
        W[j, P2] = 0.0
        IW[FLAG, j] = UNTOUCHED
    return total, nblk, nflt


@inline_kernel
def _one_event(integrate, ev, state, graph, ctrl, cls, solo, work, records):
    """Load the plate to the next failure and run one slip event to its end.

    ``records.out`` receives the event's catalog row (``layout.OUT_*``).  Returns a status
    code.  A free single-block slip is taken from its class's cached solo slip; a class's
    first one is integrated first, by the same call of ``integrate`` as the events, so that
    Numba inlines (and compiles) the integration once.  An interrupted one is undone.
    """
    scal, keys, tree = state.scal, state.keys, state.tree
    out = records.out
    hyp = tree[1]
    # loaded to the threshold (force exactly 1), or already above it (given states)
    at_threshold = keys[hyp] >= scal[SCAL_W]
    if at_threshold:
        scal[SCAL_W] = keys[hyp]
    w = scal[SCAL_W]
    out[OUT_T] = scal[SCAL_OFFSET] + w
    out[OUT_HYPOCENTER] = hyp
    # free single-block slip: reuse the block class's solo slip when no neighbour can reach
    # the threshold during it
    solo_case = at_threshold and ctrl[CTRL_SOLO_CACHE] > 0.0 and len(records.trace_nodes) == 0
    c = cls[hyp]
    rows0 = work.cnt[CNT_TRACE_ROWS]
    computing = solo_case and not (solo[c, SOLO_SLIP] == solo[c, SOLO_SLIP])
    # at most two passes: the class's solo slip integrated (NaN in the cache), then the event
    while True:
        if computing:
            saved = solo_start(hyp, graph, work)
            nact = ntouch = hyp - hyp + 1  # int64, not a literal
            run_w = 0.0
        elif solo_case and solo_free(hyp, solo[c, SOLO_SLIP], solo[c, SOLO_SPEED], w, keys, graph):
            solo_apply(hyp, solo[c, SOLO_SLIP], ev, state, graph, work.cnt, records)
            out[OUT_DURATION] = solo[c, SOLO_DURATION]
            out[OUT_SLIP] = solo[c, SOLO_SLIP]
            out[OUT_BLOCKS] = 1
            out[OUT_FAULTS] = 1
            out[OUT_STEPS] = solo[c, SOLO_STEPS]
            return STATUS_OK
        else:
            nact, ntouch = _start(hyp, w, not at_threshold, state, graph, work)
            if len(records.trace_nodes) > 0:
                record_trace(ev, 0.0, state, work, records)
            run_w = w
        status, t, nsteps, ntouch = integrate(
            ev, nact, ntouch, run_w, state, ctrl, graph, work, records
        )
        if status == STATUS_INTERRUPTED:
            if computing:
                solo_end(hyp, saved, work)
            _undo_event(ntouch, rows0, state, graph, work)
        if status != STATUS_OK:
            return status
        if not computing:
            break
        solo[c, SOLO_SLIP] = solo_end(hyp, saved, work)
        solo[c, SOLO_DURATION] = t
        solo[c, SOLO_STEPS] = nsteps
        computing = False
    _plate_moved(w, state, work, graph)
    total, nblk, nflt = _finish_event(ntouch, ev, state, graph, work, records)
    out[OUT_DURATION] = t
    out[OUT_SLIP] = total
    out[OUT_BLOCKS] = nblk
    out[OUT_FAULTS] = nflt
    out[OUT_STEPS] = nsteps
    work.cnt[CNT_STEPS] += nsteps
    return STATUS_OK


@kelvin_kernel
def _plate_moved(w, state, work, graph):
    """Where the plate moved during the event (:mod:`.plate`), the next loading starts from
    its position at the end; the plate row of ``W`` is cleared for the next event."""
    if graph.nu > 0.0:
        W = work.W
        state.scal[SCAL_W] = w + W[PLATE, D]
        W[PLATE, :] = 0.0


@kernel
def _undo_event(ntouch, rows0, state, graph, work):
    """Undo an interrupted event: touched blocks at rest where they started, their keys from
    ``z`` (a moving plate changes keys), the plate row cleared, trace rows since ``rows0``
    dropped.  The next call runs the event again."""
    W, IW, keys = work.W, work.IW, state.keys
    for q in range(ntouch):
        j = IW[TOUCH, q]
        for c in (D, P, P2, V, VN, Q, Q2):
            W[j, c] = 0.0
        IW[FLAG, j] = UNTOUCHED
        keys[j] = block_key(j, state.z, state.scal[SCAL_OFFSET], graph)
        tree_update(j, keys, state.tree)
    W[PLATE, :] = 0.0
    work.cnt[CNT_TRACE_ROWS] = rows0


@inline_kernel
def _start(hyp, w, above, state, graph, work):
    """Touch and activate the hypocentre and every block it brings over the threshold.

    With ``above`` (a given state, ``x0``: loading stops at the first block to reach the
    threshold, and only such a state holds others above it) every other block whose force is
    1 or more at plate position ``w`` is activated first, in one pass over the blocks: they
    all slip from the event's start, as the equations say, also where no spring links them
    to the hypocentre.
    """
    keys = state.keys
    W, IW = work.W, work.IW
    zero = hyp - hyp  # int64, not a literal: one compiled signature per kernel
    ntouch = touch(hyp, w, keys, W, IW, zero)
    nact, ntouch = activate(hyp, zero, ntouch, w, keys, graph, work)
    if above:
        for j in range(len(keys)):
            if keys[j] <= w and IW[FLAG, j] != ACTIVE:
                if IW[FLAG, j] == UNTOUCHED:
                    ntouch = touch(j, w, keys, W, IW, ntouch)
                nact, ntouch = activate(j, nact, ntouch, w, keys, graph, work)
    return join_scan(nact, ntouch, w, keys, graph, work)


@kernel
def _recentre(state, graph):
    """Shift the frame by an integer so the plate coordinate stays O(1)."""
    z, scal = state.z, state.scal
    shift = math.floor(scal[SCAL_W])
    scal[SCAL_OFFSET] += shift
    scal[SCAL_W] -= shift
    for i in range(len(z)):
        z[i] -= shift
    build_keys_and_tree(state, graph)


@inline_kernel
def _run_events(integrate, n_req, ev0, state, graph, ctrl, cls, solo, work, records):
    """Run up to ``n_req`` events with ``integrate`` (:mod:`.slip`).

    State: ``z`` (displacements minus the frame offset), ``scal`` (the offset and the plate
    position relative to it, ``layout.SCAL_*``), ``keys`` and ``tree`` (consistent with z,
    or rebuilt from it first where ``ctrl[CTRL_REBUILD]`` is set).
    Catalog rows: ``cat_f[e]`` and ``cat_i[e]`` (``layout.CAT_*``).
    """
    z, scal = state.z, state.scal
    cnt = work.cnt
    cat_f, cat_i, profiles, out = records.cat_f, records.cat_i, records.profiles, records.out
    n = len(z)
    if ctrl[CTRL_REBUILD] != 0.0:
        build_keys_and_tree(state, graph)
        ctrl[CTRL_REBUILD] = 0.0
    for e in range(n_req):
        if len(records.slip_val) > 0 and cnt[CNT_SLIP_ROWS] + n > len(records.slip_val):
            return STATUS_SLIPS_FULL
        status = _one_event(integrate, ev0 + e, state, graph, ctrl, cls, solo, work, records)
        if status != STATUS_OK:
            return status
        cat_f[e, CAT_T] = out[OUT_T]
        cat_f[e, CAT_DURATION] = out[OUT_DURATION]
        cat_f[e, CAT_S] = out[OUT_SLIP]
        cat_i[e, CAT_BLOCKS] = np.int64(out[OUT_BLOCKS])
        cat_i[e, CAT_HYPOCENTER] = np.int64(out[OUT_HYPOCENTER])
        cat_i[e, CAT_STEPS] = np.int64(out[OUT_STEPS])
        cat_i[e, CAT_FAULTS] = np.int64(out[OUT_FAULTS])
        if len(profiles) > 0:
            for i in range(n):
                profiles[e, i] = scal[SCAL_OFFSET] + z[i]
        cnt[CNT_EVENTS] = e + 1
        if scal[SCAL_W] > RECENTRE_AT:
            _recentre(state, graph)
    return STATUS_OK


# The entries are written out, not made by a factory: Numba keys its on-disk cache by function
# name and line, so closures of one factory would share (and clobber) an entry.
@entry
def run_events_dopri5(n_req, ev0, state, graph, ctrl, cls, solo, work, records):
    """:func:`_run_events` with DP5 steps and exact crossings."""
    return _run_events(integrate_exact, n_req, ev0, state, graph, ctrl, cls, solo, work, records)


@entry
def run_events_dopri5_interpolated(n_req, ev0, state, graph, ctrl, cls, solo, work, records):
    """:func:`_run_events` with DP5 steps and crossings on their dense output."""
    return _run_events(
        integrate_interpolated, n_req, ev0, state, graph, ctrl, cls, solo, work, records
    )
