"""One slip event's integration, from its first slipping blocks until every block has stopped.

Two integrations, one per treatment of the stops and joins ("crossings"), the two that
``RunOptions(rtol=...)`` chooses between (:mod:`faultnet.solver.accuracy`).  They take the same
arguments and return ``(status, duration, steps, ntouch)``; the entry kernels (:mod:`.events`)
receive one of them as an argument, so a run compiles only the treatment it uses.  Numba
inlines the integration at its one call site in the event loop (a block class's first solo
slip runs through the same call as the events).

- :func:`integrate_exact`: every crossing is reached by the DP5 scheme itself, by a partial
  step, and polished to round-off
  (:func:`.stepping.to_crossing`): the events keep the fifth order of the steps;
- :func:`integrate_interpolated`: every full DP5 step is kept and the crossings inside it are
  placed on its dense output (:func:`.interp.interpolated_crossings`), cheaper on 2-D graphs.

Arguments (shared by the two): ``ev`` (the event's number, for traces), ``nact`` / ``ntouch``
(lengths of the active and touched lists), ``w`` (plate position), ``ctrl`` (options,
``layout.CTRL_*``) and the bundles (:mod:`faultnet.solver._kernels.bundles`) ``state`` (positions,
frame and failure keys), ``graph`` (topology and per-block parameters), ``work`` (work space,
step context and counters) and ``records`` (only the trajectory recording, ``trace_nodes`` /
``trace_buf``, is used here).
"""

from faultnet.solver._kernels.carlson_langer.crossing import (
    STATUS_EVENT_TOO_LONG,
    STATUS_INTERRUPTED,
    STATUS_OK,
)
from faultnet.solver._kernels.carlson_langer.dopri import dopri_step
from faultnet.solver._kernels.carlson_langer.interp import interpolated_crossings
from faultnet.solver._kernels.carlson_langer.plate import (
    next_plate_join,
    plate_join,
    refresh_stuck,
)
from faultnet.solver._kernels.carlson_langer.stepping import (
    apply_crossing,
    commit,
    restore_positions,
    to_crossing,
)
from faultnet.solver._kernels.carlson_langer.work import LOC_NCAND, D, V
from faultnet.solver._kernels.jit import inline_kernel, kernel
from faultnet.solver._kernels.layout import (
    CNT_BLOCK_STEPS,
    CNT_RETAKEN_STEPS,
    CNT_TRACE_FULL,
    CNT_TRACE_ROWS,
    CTRL_DT,
    CTRL_MAX_DURATION,
    CTRL_MAX_VELOCITY,
    CTRL_STOP,
    SCAL_OFFSET,
    TRACE_EVENT,
    TRACE_TIME,
    TRACE_X,
)

__all__ = ["integrate_exact", "integrate_interpolated", "record_trace"]

#: the shortest step either treatment takes, as a fraction of dt (sets the stall guard)
MIN_STEP = 1.0 / 16.0


@kernel
def record_trace(ev, t, state, work, records):
    """Append (event ``ev``, time ``t``, positions, velocities) of the traced blocks to
    ``trace_buf``.

    ``state``, ``work``, ``records``: the bundles of :mod:`faultnet.solver._kernels.bundles`.
    """
    z, scal, W, cnt = state.z, state.scal, work.W, work.cnt
    trace_nodes, trace_buf = records.trace_nodes, records.trace_buf
    row = cnt[CNT_TRACE_ROWS]
    if row >= len(trace_buf):
        cnt[CNT_TRACE_FULL] = 1
        return
    m = len(trace_nodes)
    trace_buf[row, TRACE_EVENT] = ev
    trace_buf[row, TRACE_TIME] = t
    for c in range(m):
        j = trace_nodes[c]
        trace_buf[row, TRACE_X + c] = scal[SCAL_OFFSET] + (z[j] + W[j, D])
        trace_buf[row, TRACE_X + m + c] = W[j, V]
    cnt[CNT_TRACE_ROWS] = row + 1


@inline_kernel
def _max_steps(ctrl):
    """Steps after which an event counts as stalled (every step at its shortest)."""
    return 4.0 * ctrl[CTRL_MAX_DURATION] / (ctrl[CTRL_DT] * MIN_STEP) + 10000.0


@inline_kernel
def integrate_exact(ev, nact, ntouch, w, state, ctrl, graph, work, records):
    """Integrate the active blocks until every block has stopped, each crossing reached exactly.

    Where the plate moves during events, a step also ends where the plate brings a stuck
    block to the threshold (:mod:`.plate`).
    """
    W, IW, cnt = work.W, work.IW, work.cnt
    keys = state.keys
    dt, vmax = ctrl[CTRL_DT], ctrl[CTRL_MAX_VELOCITY]
    max_steps = _max_steps(ctrl)
    tracing = len(records.trace_nodes) > 0
    t = 0.0
    nsteps = 0
    one = nsteps - nsteps + 1  # int64, not a literal: one compiled signature per kernel
    moving = graph.nu > 0.0
    while nact > 0:
        h = dt
        plate_j = one - 2  # the block the plate brings to 1 at the step's end (-1: none)
        if moving:
            h, plate_j = next_plate_join(dt, w, state, graph, work)
        if h > 0.0:
            th, who, kind, status = dopri_step(h, nact, one, vmax, graph, work)
            if status != STATUS_OK:
                return status, t, nsteps, ntouch
            nsteps += 1
            cnt[CNT_BLOCK_STEPS] += nact
            if who < 0:
                commit(nact, W, IW)
                t += h
            else:
                h, who, kind, n, status = to_crossing(th, who, kind, h, nact, vmax, graph, work)
                nsteps += n
                if status != STATUS_OK:
                    return status, t, nsteps, ntouch
                t += h
                nact, ntouch, hi = apply_crossing(who, kind, nact, ntouch, w, keys, graph, work)
                if moving:
                    refresh_stuck(nact, hi, w, state, graph, work)
                plate_j = one - 2  # a crossing came first: the plate's join is looked at again
        if plate_j >= 0:
            nact, ntouch = plate_join(plate_j, nact, ntouch, w, state, graph, work)
        if tracing:
            record_trace(ev, t, state, work, records)
        if t > ctrl[CTRL_MAX_DURATION] or nsteps > max_steps:
            return STATUS_EVENT_TOO_LONG, t, nsteps, ntouch
        if ctrl[CTRL_STOP] != 0.0:
            return STATUS_INTERRUPTED, t, nsteps, ntouch
    return STATUS_OK, t, nsteps, ntouch


@inline_kernel
def integrate_interpolated(ev, nact, ntouch, w, state, ctrl, graph, work, records):
    """Integrate the active blocks until every block has stopped, crossings on the dense output.

    Every full DP5 step is kept, except that a step whose crossings overflow their list
    (``IW[CAND]``, one row: only in events spanning most of a small graph), or in which a block
    stops and starts again (:mod:`.late_joins`), is taken again at half the length; the step
    grows back to dt by doubling.
    """
    W, IW, loc, cnt = work.W, work.IW, work.loc, work.cnt
    keys = state.keys
    dt, vmax = ctrl[CTRL_DT], ctrl[CTRL_MAX_VELOCITY]
    max_steps = _max_steps(ctrl)
    tracing = len(records.trace_nodes) > 0
    t = 0.0
    nsteps = 0
    zero = nsteps - nsteps  # int64, not a literal: one compiled signature per kernel
    scan = zero + 2  # list every crossing of the step, keep the stuck neighbours' forces
    h = dt
    while nact > 0:
        loc[LOC_NCAND] = 0.0
        th, who, kind, status = dopri_step(h, nact, scan, vmax, graph, work)
        if status != STATUS_OK:
            return status, t, nsteps, ntouch
        nsteps += 1
        cnt[CNT_BLOCK_STEPS] += nact
        th_stop = 0.0
        if who < 0:
            commit(nact, W, IW)
        elif loc[LOC_NCAND] < 0.0:  # more crossings than the list holds
            restore_positions(nact, W, IW)
            th_stop = -1.0
        else:  # -1.0: a stop and a new start of one block in the step
            nact, ntouch, th_stop = interpolated_crossings(
                h, dt * MIN_STEP, nact, ntouch, w, keys, graph, work
            )
        if th_stop >= 0.0:
            # the event ends at its last stop, not at the end of the step
            t += h if nact > 0 or th_stop <= 0.0 else th_stop * h
            h = 2.0 * h if 2.0 * h < dt else dt
        else:  # the step is taken again at half its length
            cnt[CNT_RETAKEN_STEPS] += 1
            h = 0.5 * h if 0.5 * h > dt * MIN_STEP else dt * MIN_STEP
        if tracing:
            record_trace(ev, t, state, work, records)
        if t > ctrl[CTRL_MAX_DURATION] or nsteps > max_steps:
            return STATUS_EVENT_TOO_LONG, t, nsteps, ntouch
        if ctrl[CTRL_STOP] != 0.0:
            return STATUS_INTERRUPTED, t, nsteps, ntouch
    return STATUS_OK, t, nsteps, ntouch
