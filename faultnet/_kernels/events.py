"""The event loop: load the plate to the next failure, run one slip event.

``run_events_dopri5`` and ``run_events_rk4`` are the only kernels the Python
layer calls (one per scheme, so that a run compiles only its own scheme's
code: the scheme reaches the steppers as a literal and is chosen while typing,
see :func:`faultnet._kernels.stepping.step_scan`).  They advance the model by up
to ``n_req`` events and fill preallocated catalog arrays.  The return value is
a status code (``STATUS_*``); counters are written to ``cnt``:

====  =========================================================
cnt   meaning
====  =========================================================
0     events completed in this call
1     rows used in the per-block slip buffer
2     rows used in the trajectory buffer
3     integration steps (full and partial) in this call
4     block-steps (slipping blocks x steps) in this call
5     1 if the trajectory buffer filled up (recording stopped)
6     block-steps spent in partial steps (stepping to crossings)
7     re-locations (an earlier crossing found inside a partial step)
8     events taken by the free single-block path (no integration)
9     steps whose crossings were handled in local regions
10    local steps that fell back to the whole-event treatment
11    id counter of local regions (never reset)
12    block-steps inside local regions
13    joins landed on a step's interpolant
14    crossings placed on a step's dense output (``ctrl[5] == 1``, ``interp.py``)
====  =========================================================
"""

import math

import numpy as np

from faultnet._kernels.context import LOC_NCAND
from faultnet._kernels.crossing import (
    STATUS_EVENT_TOO_LONG,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_RUNAWAY,
    STATUS_SLIPS_FULL,
)
from faultnet._kernels.integrate import (
    ACT,
    ACTIVE,
    APOS,
    F0,
    FLAG,
    P2,
    STUCK,
    TOUCH,
    UNTOUCHED,
    VN,
    A,
    D,
    P,
    V,
    accel,
)
from faultnet._kernels.interp import interpolated_crossings
from faultnet._kernels.jit import entry, inline_kernel, kernel
from faultnet._kernels.local import local_step
from faultnet._kernels.stepping import (
    activate,
    apply_crossing,
    commit,
    join_scan,
    step_scan,
    to_crossing,
    touch,
)
from faultnet._kernels.tree import block_key, build_keys_and_tree, tree_update

__all__ = [
    "STATUS_OK",
    "STATUS_SLIPS_FULL",
    "STATUS_NONFINITE",
    "STATUS_RUNAWAY",
    "STATUS_EVENT_TOO_LONG",
    "RECENTRE_AT",
    "run_events_dopri5",
    "run_events_rk4",
]

#: with local regions, the outer step is halved while a step holds more
#: crossings than this (down to _LOCAL_MIN_STEP * dt) and doubled while it
#: holds fewer than half as many
_LOCAL_CROSSINGS = 12
_LOCAL_MIN_STEP = 1.0 / 16.0

#: the re-centred plate coordinate ``w`` is shifted back by an integer once it
#: exceeds this, so coordinates stay O(1) however long the run
RECENTRE_AT = 4.0


@kernel
def _record_trace(ev, t, offset, z, W, trace_nodes, trace_buf, cnt):
    row = cnt[2]
    if row >= trace_buf.shape[0]:
        cnt[5] = 1
        return
    m = trace_nodes.shape[0]
    trace_buf[row, 0] = ev
    trace_buf[row, 1] = t
    for c in range(m):
        j = trace_nodes[c]
        trace_buf[row, 2 + c] = offset + (z[j] + W[j, D])
        trace_buf[row, 2 + m + c] = W[j, V]
    cnt[2] = row + 1


@kernel
def _finish_event(
    ntouch,
    ev,
    z,
    keys,
    tree,
    W,
    IW,
    indptr,
    indices,
    kval,
    diag,
    slip_event,
    slip_node,
    slip_val,
    cnt,
):
    """Apply the slips, refresh keys of touched blocks, reset the work rows."""
    total = 0.0
    nblk = 0
    rec = slip_val.shape[0] > 0
    row = cnt[1]
    for q in range(ntouch):
        j = IW[TOUCH, q]
        if IW[FLAG, j] == STUCK:
            s = W[j, D]
            total += s
            nblk += 1
            z[j] += s
            if rec:
                slip_event[row] = ev
                slip_node[row] = j
                slip_val[row] = s
                row += 1
    cnt[1] = row
    for q in range(ntouch):
        j = IW[TOUCH, q]
        keys[j] = block_key(j, z, indptr, indices, kval, diag)
        tree_update(j, keys, tree)
        W[j, D] = 0.0
        W[j, P] = 0.0
        W[j, P2] = 0.0
        IW[FLAG, j] = UNTOUCHED
    return total, nblk


#: a neighbour's force must stay this far below 1 for a free single-block slip
SOLO_MARGIN = 1e-12


#: the starting force that keeps a neighbour out of a solo slip
_HELD = -1e300


@inline_kernel
def _solo_slip(
    method,
    i,
    ev,
    scal,
    z,
    keys,
    W,
    IW,
    indptr,
    indices,
    kval,
    diag,
    oms,
    cfr,
    ctrl,
    loc,
    trace_nodes,
    trace_buf,
    cnt,
):
    """Slip of block i alone: from rest at the threshold, every neighbour held.

    Integrated by the event loop itself (:func:`_integrate`), with the
    neighbours' starting forces set to -1e300 so that none can join (starting
    forces are written afresh whenever a block is touched).  Such a slip
    depends only on the block's own parameters (stiffness, sigma, alpha), so
    it is computed once per parameter class and reused.  Leaves the work
    arrays as it found them.  Returns (slip, duration, steps, status).
    """
    for p in range(indptr[i], indptr[i + 1]):
        W[indices[p], F0] = _HELD
    W[i, F0] = 1.0
    IW[ACT, 0] = i
    IW[APOS, i] = 0
    IW[FLAG, i] = ACTIVE
    IW[TOUCH, 0] = i
    W[i, V] = 0.0
    W[i, VN] = 0.0
    W[i, A] = accel(i, P, V, W, indptr, indices, kval, diag, oms, cfr)
    # work counters: a cached solo slip is set-up, not part of any event (so
    # a run's counters do not depend on how it was cut into calls)
    c4, c6, c7, c13, c14 = cnt[4], cnt[6], cnt[7], cnt[13], cnt[14]
    one = np.int64(1)  # not the literal 1: _integrate keeps one compiled signature
    status, t, n, _ = _integrate(
        method,
        ev,
        one,
        one,
        0.0,
        keys,
        scal,
        z,
        W,
        IW,
        indptr,
        indices,
        kval,
        diag,
        oms,
        cfr,
        ctrl,
        loc,
        trace_nodes,
        trace_buf,
        cnt,
    )
    cnt[4], cnt[6], cnt[7], cnt[13], cnt[14] = c4, c6, c7, c13, c14
    s = W[i, D]
    W[i, D] = 0.0
    W[i, P] = 0.0
    W[i, P2] = 0.0
    W[i, V] = 0.0
    W[i, VN] = 0.0
    IW[FLAG, i] = UNTOUCHED
    return s, t, n, status


@kernel
def _solo_free(hyp, s1, w, keys, indptr, indices, kval):
    """True when slipping s1 alone leaves every neighbour of hyp below threshold.

    The slip is monotone, so a neighbour's force is largest at the end:
    F_j = 1 + w - key_j + k_ij s1.
    """
    for p in range(indptr[hyp], indptr[hyp + 1]):
        if 1.0 + w - keys[indices[p]] + kval[p] * s1 >= 1.0 - SOLO_MARGIN:
            return False
    return True


@kernel
def _solo_apply(
    hyp, s1, ev, z, keys, tree, indptr, indices, kval, diag, slip_ev, slip_nd, slip_v, cnt
):
    """Commit a free single-block slip: move the block, refresh its and its neighbours' keys."""
    z[hyp] += s1
    keys[hyp] = block_key(hyp, z, indptr, indices, kval, diag)
    tree_update(hyp, keys, tree)
    for p in range(indptr[hyp], indptr[hyp + 1]):
        j = indices[p]
        keys[j] = block_key(j, z, indptr, indices, kval, diag)
        tree_update(j, keys, tree)
    if slip_v.shape[0] > 0:
        row = cnt[1]
        slip_ev[row] = ev
        slip_nd[row] = hyp
        slip_v[row] = s1
        cnt[1] = row + 1
    cnt[8] += 1


@kernel
def _integrate(
    method,
    ev,
    nact,
    ntouch,
    w,
    keys,
    scal,
    z,
    W,
    IW,
    indptr,
    indices,
    kval,
    diag,
    oms,
    cfr,
    ctrl,
    loc,
    trace_nodes,
    trace_buf,
    cnt,
):
    """Integrate the active blocks until every block has stopped.

    Full steps; a crossing found inside a step is reached by a partial step
    and polished to round-off (a join, with DP5: landed on the step's
    interpolant, :mod:`faultnet._kernels.landing`), then blocks join or stop.
    With at least ``ctrl[4]`` slipping blocks (DP5 only) the crossings of a step are handled
    in local regions instead (:func:`faultnet._kernels.local.local_step`).
    Returns (status, duration, steps, ntouch).
    """
    dt, max_duration, vmax = ctrl[0], ctrl[1], ctrl[2]
    n_local = ctrl[4]
    # a stall guard: local regions may shorten the step to _LOCAL_MIN_STEP * dt
    max_steps = 4.0 * max_duration / (dt * _LOCAL_MIN_STEP) + 10000.0
    tracing = trace_nodes.shape[0] > 0
    t = 0.0
    nsteps = 0
    zero = nsteps - nsteps  # int64, not a literal: one compiled signature per kernel
    n_blocks = W.shape[0]
    h_local = dt  # outer step with local regions: shorter when crossings are dense
    # crossings placed on the step's dense output (interp.py), never a step redone
    interp = method == 1 and ctrl[5] > 0.0
    while nact > 0:
        local = method == 1 and not interp and nact >= n_local and 4 * nact < n_blocks
        h = h_local if local else dt
        scan = zero + 1
        if local or interp:
            scan += 1  # list the crossings for the local regions or the interpolated ones
            loc[LOC_NCAND] = 0.0
        th, who, kind, status = step_scan(
            method, h, zero, nact, IW, W, indptr, indices, kval, diag, oms, cfr, vmax, scan, loc
        )
        if status != STATUS_OK:
            return status, t, nsteps, ntouch
        nsteps += 1
        cnt[4] += nact
        if who < 0:
            commit(zero, nact, W, IW)
            t += h
            if local:
                h_local = min(dt, 2.0 * h_local)
        elif interp and loc[LOC_NCAND] >= 0.0:
            nact, ntouch, th_stop = interpolated_crossings(
                h, nact, ntouch, w, keys, W, IW, indptr, indices, kval, diag, oms, cfr, loc, cnt
            )
            # the event ends at its last stop, not at the end of the step
            t += h if nact > 0 or th_stop <= 0.0 else th_stop * h
        else:
            done = False
            if local:
                status, nact2, ntouch, n, ncand, done = local_step(
                    h, nact, ntouch, w, keys, W, IW, indptr, indices, kval, diag, oms, cfr,
                    ctrl, loc, cnt,
                )  # fmt: skip
                nsteps += n
                if status != STATUS_OK:
                    return status, t, nsteps, ntouch
                if done:
                    nact = nact2
                    t += h
                if ncand > _LOCAL_CROSSINGS:
                    h_local = max(dt * _LOCAL_MIN_STEP, 0.5 * h_local)
                elif ncand * 2 < _LOCAL_CROSSINGS:
                    h_local = min(dt, 2.0 * h_local)
            if not done:
                h, who, kind, n, status = to_crossing(
                    th, who, kind, h, method, zero, zero, nact, IW, W, indptr, indices, kval,
                    diag, oms, cfr, vmax, loc, cnt,
                )  # fmt: skip
                nsteps += n
                if status != STATUS_OK:
                    return status, t, nsteps, ntouch
                t += h
                nact, ntouch = apply_crossing(
                    who, kind, zero, nact, ntouch, w, keys, W, IW, indptr, indices, kval, diag,
                    oms, cfr,
                )  # fmt: skip
        if tracing:
            _record_trace(ev, t, scal[0], z, W, trace_nodes, trace_buf, cnt)
        if t > max_duration or nsteps > max_steps:
            return STATUS_EVENT_TOO_LONG, t, nsteps, ntouch
    return STATUS_OK, t, nsteps, ntouch


@inline_kernel
def _one_event(
    method,
    ev,
    z,
    scal,
    keys,
    tree,
    W,
    IW,
    indptr,
    indices,
    kval,
    diag,
    oms,
    cfr,
    ctrl,
    loc,
    cls,
    solo,
    slip_event,
    slip_node,
    slip_val,
    trace_nodes,
    trace_buf,
    cnt,
    out,
):
    """Load the plate to the next failure and run one slip event to its end.

    ``out`` receives (t_start, duration, S, n_blocks, hypocenter, n_steps).
    Returns a status code.
    """
    hyp = tree[1]
    # loaded to the threshold (force exactly 1), or already above it (given states)
    at_threshold = keys[hyp] >= scal[1]
    if at_threshold:
        scal[1] = keys[hyp]
    w = scal[1]
    out[0] = scal[0] + w
    out[4] = hyp
    if at_threshold and ctrl[3] > 0.0 and trace_nodes.shape[0] == 0:
        # free single-block slip: reuse the block class's solo slip when no
        # neighbour can reach the threshold during it
        c = cls[hyp]
        if not (solo[c, 0] == solo[c, 0]):
            s1, t1, n1, status = _solo_slip(
                method,
                hyp,
                ev,
                scal,
                z,
                keys,
                W,
                IW,
                indptr,
                indices,
                kval,
                diag,
                oms,
                cfr,
                ctrl,
                loc,
                trace_nodes,
                trace_buf,
                cnt,
            )
            if status != STATUS_OK:
                return status
            solo[c, 0] = s1
            solo[c, 1] = t1
            solo[c, 2] = n1
        s1 = solo[c, 0]
        if _solo_free(hyp, s1, w, keys, indptr, indices, kval):
            _solo_apply(
                hyp,
                s1,
                ev,
                z,
                keys,
                tree,
                indptr,
                indices,
                kval,
                diag,
                slip_event,
                slip_node,
                slip_val,
                cnt,
            )
            out[1] = solo[c, 1]
            out[2] = s1
            out[3] = 1
            out[5] = solo[c, 2]
            return STATUS_OK
    zero = np.int64(0)  # not literals: one compiled signature per kernel
    ntouch = touch(hyp, w, keys, W, IW, zero)
    nact, ntouch = activate(
        hyp, zero, ntouch, w, keys, W, IW, indptr, indices, kval, diag, oms, cfr
    )
    nact, ntouch = join_scan(
        zero, nact, ntouch, w, keys, W, IW, indptr, indices, kval, diag, oms, cfr
    )
    tracing = trace_nodes.shape[0] > 0
    if tracing:
        _record_trace(ev, 0.0, scal[0], z, W, trace_nodes, trace_buf, cnt)
    status, t, nsteps, ntouch = _integrate(
        method,
        ev,
        nact,
        ntouch,
        w,
        keys,
        scal,
        z,
        W,
        IW,
        indptr,
        indices,
        kval,
        diag,
        oms,
        cfr,
        ctrl,
        loc,
        trace_nodes,
        trace_buf,
        cnt,
    )
    if status != STATUS_OK:
        return status
    total, nblk = _finish_event(
        ntouch,
        ev,
        z,
        keys,
        tree,
        W,
        IW,
        indptr,
        indices,
        kval,
        diag,
        slip_event,
        slip_node,
        slip_val,
        cnt,
    )
    out[1] = t
    out[2] = total
    out[3] = nblk
    out[5] = nsteps
    cnt[3] += nsteps
    return STATUS_OK


@kernel
def _recentre(z, scal, keys, tree, indptr, indices, kval, diag):
    """Shift the frame by an integer so the plate coordinate stays O(1)."""
    shift = math.floor(scal[1])
    scal[0] += shift
    scal[1] -= shift
    for i in range(z.shape[0]):
        z[i] -= shift
    build_keys_and_tree(z, indptr, indices, kval, diag, keys, tree)


@inline_kernel
def _run_events(
    method,
    n_req,
    ev0,
    z,
    scal,
    keys,
    tree,
    W,
    IW,
    indptr,
    indices,
    kval,
    diag,
    oms,
    cfr,
    ctrl,
    loc,
    cls,
    solo,
    cat_f,
    cat_i,
    slip_event,
    slip_node,
    slip_val,
    trace_nodes,
    trace_buf,
    profiles,
    cnt,
    out,
):
    """Run up to ``n_req`` events; see the module docstring for ``cnt``.

    State: ``z`` (displacements minus ``scal[0]``), ``scal = [offset, w]``
    (w: plate position minus offset), ``keys`` and ``tree`` (consistent with
    z).  Catalog rows: ``cat_f[e] = (t, duration, S)``,
    ``cat_i[e] = (n_blocks, hypocenter, n_steps)``.
    """
    n = z.shape[0]
    for e in range(n_req):
        if slip_val.shape[0] > 0 and cnt[1] + n > slip_val.shape[0]:
            return STATUS_SLIPS_FULL
        status = _one_event(
            method,
            ev0 + e,
            z,
            scal,
            keys,
            tree,
            W,
            IW,
            indptr,
            indices,
            kval,
            diag,
            oms,
            cfr,
            ctrl,
            loc,
            cls,
            solo,
            slip_event,
            slip_node,
            slip_val,
            trace_nodes,
            trace_buf,
            cnt,
            out,
        )
        if status != STATUS_OK:
            return status
        cat_f[e, 0] = out[0]
        cat_f[e, 1] = out[1]
        cat_f[e, 2] = out[2]
        cat_i[e, 0] = int(out[3])
        cat_i[e, 1] = int(out[4])
        cat_i[e, 2] = int(out[5])
        if profiles.shape[0] > 0:
            for i in range(n):
                profiles[e, i] = scal[0] + z[i]
        cnt[0] = e + 1
        if scal[1] > RECENTRE_AT:
            _recentre(z, scal, keys, tree, indptr, indices, kval, diag)
    return STATUS_OK


# The two entries are written out, not made by a factory: Numba keys its on-disk cache by
# function name and line, so two closures of one factory would share (and clobber) an entry.
@entry
def run_events_dopri5(
    n_req, ev0, z, scal, keys, tree, W, IW, indptr, indices, kval, diag, oms, cfr, ctrl,
    loc, cls, solo, cat_f, cat_i, slip_event, slip_node, slip_val, trace_nodes, trace_buf,
    profiles, cnt, out,
):  # fmt: skip
    """:func:`_run_events` with Dormand-Prince 5(4) steps."""
    return _run_events(
        1,
        n_req, ev0, z, scal, keys, tree, W, IW, indptr, indices, kval, diag, oms, cfr,
        ctrl, loc, cls, solo, cat_f, cat_i, slip_event, slip_node, slip_val,
        trace_nodes, trace_buf, profiles, cnt, out,
    )  # fmt: skip


@entry
def run_events_rk4(
    n_req, ev0, z, scal, keys, tree, W, IW, indptr, indices, kval, diag, oms, cfr, ctrl,
    loc, cls, solo, cat_f, cat_i, slip_event, slip_node, slip_val, trace_nodes, trace_buf,
    profiles, cnt, out,
):  # fmt: skip
    """:func:`_run_events` with classical RK4 steps (compiled only when used)."""
    return _run_events(
        0,
        n_req, ev0, z, scal, keys, tree, W, IW, indptr, indices, kval, diag, oms, cfr,
        ctrl, loc, cls, solo, cat_f, cat_i, slip_event, slip_node, slip_val,
        trace_nodes, trace_buf, profiles, cnt, out,
    )  # fmt: skip
