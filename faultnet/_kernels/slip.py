"""One slip event's integration, from its first slipping blocks until every block has stopped.

Three integrations, one per treatment of the stops and joins ("crossings").  They take the
same arguments and return ``(status, duration, steps, ntouch)``; the entry kernels
(:mod:`faultnet._kernels.events`) receive one of them as an argument, so a run compiles only
the treatment it uses.  Numba inlines the integration at its one call site in the event loop
(a block class's first solo slip runs through the same call as the events).

- :func:`integrate_exact`: every crossing is reached by the scheme itself, by a partial step
  or (a DP5 join) a landing on the step's interpolant, and polished to round-off
  (:func:`faultnet._kernels.stepping.to_crossing`); RK4 or DP5;
- :func:`integrate_local`: the same, except that in events of at least
  ``ctrl[CTRL_LOCAL_FROM]`` slipping blocks the crossings of a step are handled in small local
  regions (:func:`faultnet._kernels.local.local_step`; DP5);
- :func:`integrate_interpolated`: every full DP5 step is kept and the crossings inside it are
  placed on its dense output (:func:`faultnet._kernels.interp.interpolated_crossings`).

Arguments (shared by the three): ``method`` (literal 0 RK4, 1 DP5), ``ev`` (the event's
number, for traces), ``nact`` / ``ntouch`` (lengths of the active and touched lists),
``w`` (plate position), ``ctrl`` (options, ``layout.CTRL_*``) and the bundles
(:mod:`faultnet._kernels.bundles`) ``state`` (positions, frame and failure keys), ``graph``
(topology and per-block parameters), ``work`` (work space, step context and counters) and
``records`` (only the trajectory recording, ``trace_nodes`` / ``trace_buf``, is used here).
"""

from faultnet._kernels.context import LOC_NCAND
from faultnet._kernels.crossing import STATUS_EVENT_TOO_LONG, STATUS_OK
from faultnet._kernels.dopri import dopri_step
from faultnet._kernels.integrate import D, V
from faultnet._kernels.interp import interpolated_crossings
from faultnet._kernels.jit import inline_kernel, kernel
from faultnet._kernels.layout import (
    CNT_BLOCK_STEPS,
    CNT_TRACE_FULL,
    CNT_TRACE_ROWS,
    CTRL_DT,
    CTRL_LOCAL_FROM,
    CTRL_MAX_DURATION,
    CTRL_MAX_VELOCITY,
    SCAL_OFFSET,
    TRACE_EVENT,
    TRACE_TIME,
    TRACE_X,
)
from faultnet._kernels.local import local_step
from faultnet._kernels.stepping import (
    apply_crossing,
    commit,
    restore_positions,
    step_scan,
    to_crossing,
)

__all__ = ["integrate_exact", "integrate_interpolated", "integrate_local", "record_trace"]

#: with local regions, the outer step is halved while a step holds more crossings than this
#: (down to MIN_STEP * dt) and doubled while it holds fewer than half as many
LOCAL_CROSSINGS = 12
#: the shortest step any treatment takes, as a fraction of dt (sets the stall guard)
MIN_STEP = 1.0 / 16.0


@kernel
def record_trace(ev, t, state, work, records):
    """Append (event, time, positions, velocities) of the traced blocks to ``trace_buf``.

    ``state``, ``work``, ``records``: the bundles of :mod:`faultnet._kernels.bundles`.
    """
    z, scal, W, cnt = state.z, state.scal, work.W, work.cnt
    trace_nodes, trace_buf = records.trace_nodes, records.trace_buf
    row = cnt[CNT_TRACE_ROWS]
    if row >= trace_buf.shape[0]:
        cnt[CNT_TRACE_FULL] = 1
        return
    m = trace_nodes.shape[0]
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


@kernel
def no_regions(h, nact, ntouch, w, keys, ctrl, graph, work):
    """Stands in for :func:`~faultnet._kernels.local.local_step` where regions are off.

    Never called (``ctrl[CTRL_LOCAL_FROM]`` is inf), only typed.
    """
    n = nact - nact
    return STATUS_OK, nact, ntouch, n, n, False


@inline_kernel
def _exact_loop(method, regions, ev, nact, ntouch, w, state, ctrl, graph, work, records):
    """The exact treatment; ``regions`` handles a large event's step in local regions."""
    W, IW, loc, cnt = work.W, work.IW, work.loc, work.cnt
    keys = state.keys
    dt, vmax = ctrl[CTRL_DT], ctrl[CTRL_MAX_VELOCITY]
    n_local = ctrl[CTRL_LOCAL_FROM]
    max_steps = _max_steps(ctrl)
    tracing = records.trace_nodes.shape[0] > 0
    t = 0.0
    nsteps = 0
    zero = nsteps - nsteps  # int64, not a literal: one compiled signature per kernel
    n_blocks = IW.shape[1]
    h_local = dt  # outer step with local regions: shorter when crossings are dense
    while nact > 0:
        local = method == 1 and nact >= n_local and 4 * nact < n_blocks
        h = h_local if local else dt
        scan = zero + 1
        if local:
            scan += 1  # list the crossings for the local regions
            loc[LOC_NCAND] = 0.0
        th, who, kind, status = step_scan(method, h, zero, nact, vmax, scan, graph, work)
        if status != STATUS_OK:
            return status, t, nsteps, ntouch
        nsteps += 1
        cnt[CNT_BLOCK_STEPS] += nact
        if who < 0:
            commit(zero, nact, W, IW)
            t += h
            if local:
                h_local = min(dt, 2.0 * h_local)
        else:
            done = False
            if local:
                status, nact2, ntouch, n, ncand, done = regions(
                    h, nact, ntouch, w, keys, ctrl, graph, work
                )
                nsteps += n
                if status != STATUS_OK:
                    return status, t, nsteps, ntouch
                if done:
                    nact = nact2
                    t += h
                if ncand > LOCAL_CROSSINGS:
                    h_local = max(dt * MIN_STEP, 0.5 * h_local)
                elif ncand * 2 < LOCAL_CROSSINGS:
                    h_local = min(dt, 2.0 * h_local)
            if not done:
                h, who, kind, n, status = to_crossing(
                    th, who, kind, h, method, zero, zero, nact, vmax, graph, work
                )
                nsteps += n
                if status != STATUS_OK:
                    return status, t, nsteps, ntouch
                t += h
                nact, ntouch = apply_crossing(who, kind, zero, nact, ntouch, w, keys, graph, work)
        if tracing:
            record_trace(ev, t, state, work, records)
        if t > ctrl[CTRL_MAX_DURATION] or nsteps > max_steps:
            return STATUS_EVENT_TOO_LONG, t, nsteps, ntouch
    return STATUS_OK, t, nsteps, ntouch


@inline_kernel
def integrate_exact(method, ev, nact, ntouch, w, state, ctrl, graph, work, records):
    """Integrate the active blocks until every block has stopped, each crossing reached exactly."""
    return _exact_loop(method, no_regions, ev, nact, ntouch, w, state, ctrl, graph, work, records)


@inline_kernel
def integrate_local(method, ev, nact, ntouch, w, state, ctrl, graph, work, records):
    """As :func:`integrate_exact`, with the crossings of large events in local regions (DP5)."""
    return _exact_loop(method, local_step, ev, nact, ntouch, w, state, ctrl, graph, work, records)


@inline_kernel
def integrate_interpolated(method, ev, nact, ntouch, w, state, ctrl, graph, work, records):
    """Integrate the active blocks until every block has stopped, crossings on the dense output.

    DP5 only (its steps call :func:`~faultnet._kernels.dopri.dopri_step` directly).  Every
    full DP5 step is kept.  A step whose crossings overflow their list (``IW[CAND]``, one
    row: only in events spanning most of a small graph) is taken again at half the length, and
    the step grows back to dt by doubling.
    """
    W, IW, loc, cnt = work.W, work.IW, work.loc, work.cnt
    keys = state.keys
    dt, vmax = ctrl[CTRL_DT], ctrl[CTRL_MAX_VELOCITY]
    max_steps = _max_steps(ctrl)
    tracing = records.trace_nodes.shape[0] > 0
    t = 0.0
    nsteps = 0
    zero = nsteps - nsteps  # int64, not a literal: one compiled signature per kernel
    scan = zero + 3  # list every crossing of the step, keep the stuck neighbours' forces
    h = dt
    while nact > 0:
        loc[LOC_NCAND] = 0.0
        th, who, kind, status = dopri_step(h, zero, nact, scan, vmax, graph, work)
        if status != STATUS_OK:
            return status, t, nsteps, ntouch
        nsteps += 1
        cnt[CNT_BLOCK_STEPS] += nact
        if who < 0:
            commit(zero, nact, W, IW)
            t += h
            h = min(dt, 2.0 * h)
        elif loc[LOC_NCAND] < 0.0:
            restore_positions(zero, nact, W, IW)
            h = max(dt * MIN_STEP, 0.5 * h)
        else:
            nact, ntouch, th_stop = interpolated_crossings(h, nact, ntouch, w, keys, graph, work)
            # the event ends at its last stop, not at the end of the step
            t += h if nact > 0 or th_stop <= 0.0 else th_stop * h
            h = min(dt, 2.0 * h)
        if tracing:
            record_trace(ev, t, state, work, records)
        if t > ctrl[CTRL_MAX_DURATION] or nsteps > max_steps:
            return STATUS_EVENT_TOO_LONG, t, nsteps, ntouch
    return STATUS_OK, t, nsteps, ntouch
