"""Interpolated crossings: stops and joins placed on a step's dense output, no step redone.

The exact treatment (:mod:`.stepping`)
reaches every crossing with the whole scheme, so an event keeps the fifth order of its DP5
steps; on 2-D lattices that costs more than the steps themselves.  With this treatment
(:func:`.slip.integrate_interpolated`) the event loop takes every full step
as it is and applies all the crossings found inside it at its end, from what the step has
already computed.  First every listed crossing is located on the step's own values
(:func:`_locate`), then applied, joins in the order of their fractions of the step, then
stops:

- a *join* of block j at ``th``: j starts from rest and its path over the rest of the step
  is integrated alone (:func:`.response.place_join`), its slipping and
  stopping neighbours on the step's dense output and its neighbours that joined earlier in
  the step on their paths.  The dense output moved j's neighbours as if none of them crossed
  inside the step; a neighbour that started (or stopped) before ``th`` pushes (holds back)
  j, whose join comes earlier (later): the root of its force on their paths (:func:`_chained`;
  at a rupture front one block often joins behind another within the same step);
- a *stop* of block b at fraction ``th``: b is held, until the commit, at the position of
  its path integrated alone from the start of the step
  (:func:`.response.stop_position`; the step itself carried it on past the
  stop), shifted by its answer to the neighbours that joined or stopped before ``th``
  (:func:`~.response.stop_shift`);
- the slipping neighbours of b (or j) moved over ``[th, 1]`` with b on its continuation past
  the stop (or j at rest), and so did j's neighbours that joined before it and b's joining
  neighbours: their velocities and positions get the force they missed and their own answer
  to it, through their friction and springs (:func:`.response.respond`,
  :func:`~.response.stop_answer`).

Then, still before the commit, every stuck block next to a crossing block, or next to one of
its slipping (corrected) neighbours, whose force at the end of the step has reached 1 is a
join the crossings revealed (nothing else has moved since the step's scan listed the joins):
it is placed after them as a join that its neighbours' crossings push, and its own
neighbours are scanned in turn (:mod:`.late_joins`).  Each crossing costs a few passes over
a handful of blocks instead of a partial step.  The neglected terms are the second-order
answer of the neighbours (and of theirs) and the dense output's error: the S error of an
event grows like ``dt^4`` per crossing, against ``dt^5`` for the exact treatment
(``faultnet.solver.accuracy`` calibrates which to use for a given rtol).  Placing the
chained and revealed joins on the neighbours' paths is what keeps large events accurate:
with one Newton step from the dense output's root for chained joins, revealed joins started
back from the step's end on a Taylor expansion of the force and stops placed in the order
of the list, the worst of 150 events on the triangular critical cluster was off by 9e-2 at
coefficient 0.6 (now 7e-5), and the 90th percentile over all of them was twice as large
(2.2e-5 against 1.1e-5; on the periodic 150^2 lattice 2.9e-5 against 7.0e-6).

Arguments: ``h`` the step's length, ``th`` a fraction of it, ``b``, ``j`` blocks, ``nact``,
``ntouch`` the lengths of the active and touched lists, ``ncand`` the crossings listed in
``IW[CAND]``, ``e`` an entry of that list (a join's block, ``-2 - b`` for a stop of b, -1
dropped), ``w`` the plate position, ``keys`` the failure keys (for the blocks a join touches),
``W`` the work array, ``graph`` and ``work`` the bundles (:mod:`~faultnet.solver._kernels.bundles`).
"""

import numpy as np

from faultnet.solver._kernels.carlson_langer.crossing import join_theta, stick_theta
from faultnet.solver._kernels.carlson_langer.late_joins import (
    late_join,
    late_joins,
    refresh,
    rejoin,
    take_again,
)
from faultnet.solver._kernels.carlson_langer.physics import (
    accel,
    force,
    friction_slope,
    jerk_snap,
    start_accel,
)
from faultnet.solver._kernels.carlson_langer.response import (
    neighbour_poly,
    path_moments,
    place_join,
    respond,
    stop_answer,
    stop_position,
    stop_shift,
)
from faultnet.solver._kernels.carlson_langer.roots import poly_root
from faultnet.solver._kernels.carlson_langer.stepping import activate, deactivate, stick_scan
from faultnet.solver._kernels.carlson_langer.tableau import path_dense, stage_rows
from faultnet.solver._kernels.carlson_langer.work import (
    ACT,
    ACTIVE,
    AN,
    APOS,
    CAND,
    FLAG,
    JOINING,
    LOC_MOVED,
    LOC_NCAND,
    LOC_THETA,
    P2,
    SA,
    STOPPING,
    SV,
    THETA_CACHE,
    VN,
    VS,
    A,
    D,
    P,
    V,
)
from faultnet.solver._kernels.jit import forced_kernel, inline_kernel, kernel
from faultnet.solver._kernels.layout import CNT_INTERPOLATED_CROSSINGS

__all__ = ["interpolated_crossings"]


@kernel
def _stop(b, th, h, graph, work):
    """Block b stops at fraction th: its stop position, neighbours corrected.

    The position is :func:`.response.stop_position`, moved by b's answer to
    its neighbours' earlier crossings (``stop_shift``), kept in ``W[b, SV]`` (and ``P2``, the
    end positions) until the commit; b's own end values stay, for its dense output.
    """
    W, IW = work.W, work.IW
    c0, c1, c2, c3, c4 = path_dense(b, h, work)
    xs = stop_position(b, th, h, graph, work) + stop_shift(b, th, h, graph, work)
    i1, i2, i3, i4 = path_moments(xs, th, 1.0, h, 0.0, c0, c1, c2, c3, c4)
    W[b, SV] = xs
    work.loc[LOC_MOVED] += abs(xs - W[b, P2])
    W[b, P2] = xs
    respond(b, -1.0, i1, i2, i3, i4, graph, work)
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        m = graph.indices[p]
        if IW[FLAG, m] == JOINING:
            stop_answer(m, graph.kval[p], xs, th, h, c0, c1, c2, c3, c4, graph, work)


@kernel
def _start_rates(j, th, h, graph, work):
    """Acceleration, jerk and snap of stuck block j starting at fraction th of the step.

    From rest at the threshold (:func:`~.physics.start_accel`, :func:`~.physics.jerk_snap`),
    with the spring sums of its moving neighbours' velocities and accelerations at th: the
    first and second derivatives of the force of their dense output (:func:`neighbour_poly`,
    slipping neighbours, or slipping until a stop later in the step).
    """
    g1, g2, g3, g4 = neighbour_poly(j, h, -1.0, graph, work)
    r = 1.0 / h
    sv = (g1 + th * (2.0 * g2 + th * (3.0 * g3 + th * 4.0 * g4))) * r
    sa = (2.0 * g2 + th * (6.0 * g3 + th * 12.0 * g4)) * (r * r)
    a0 = start_accel(j, graph)
    jerk, snap = jerk_snap(j, 0.0, a0, sv, sa, graph)
    return a0, jerk, snap


@kernel
def _push(j, s, h, graph, work):
    """Force on stuck block j at fraction s beyond the dense output, from earlier crossings.

    The step moved j's neighbours as if none of them stopped or started inside it.  A
    neighbour m that stops (or starts) at ``W[m, VS] < s`` in fact stays behind (moves ahead,
    on the Taylor series of its start) by ``e`` at s, and j's force is higher by ``k e``.
    Returns (the summed ``k e``, the earliest such crossing or s).
    """
    W, IW = work.W, work.IW
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    dF = 0.0
    lo = s
    for p in range(indptr[j], indptr[j + 1]):
        m = indices[p]
        fl = IW[FLAG, m]
        if fl != STOPPING and fl != JOINING:
            continue
        tm = W[m, VS]
        if tm >= s:
            continue
        if fl == STOPPING:
            c0, c1, c2, c3, c4 = path_dense(m, h, work)
            t2, s2 = tm * tm, s * s
            e = c1 * (tm - s) + c2 * (t2 - s2) + c3 * (tm * t2 - s * s2)
            e += c4 * (t2 * t2 - s2 * s2)
        else:
            a0, jerk, snap = _start_rates(m, tm, h, graph, work)
            t = (s - tm) * h
            e = t * t * (0.5 * a0 + t * (jerk / 6.0 + snap * t / 24.0))
        dF += kval[p] * e
        lo = tm if tm < lo else lo
    return dF, lo


@inline_kernel
def _chained(j, th, h, graph, work):
    """The fraction at which stuck block j joins, given its neighbours' crossings before th.

    j's force on the dense output reaches 1 at th (a join the crossings revealed: th = 1, with
    their pushes).  Pushed by neighbours that joined before (:func:`_push`), it reaches 1
    earlier: at the root of the dense force plus the push between the earliest such join and
    th (regula falsi, Illinois variant; the push grows like the cube of the time since a
    neighbour's join, so one Newton step from th overshoots), or at the dense force's own
    root if that comes before the first push (a force that rose above 1 and fell back inside
    the step, which the scan, reading the step's end, did not list).  Held back by a
    neighbour's stop, it joins later by one Newton step.
    """
    dF, lo = _push(j, th, h, graph, work)
    if dF == 0.0:
        return th
    if dF < 0.0:
        a0, jerk, snap = _start_rates(j, th, h, graph, work)
        df = jerk - friction_slope(j, 0.0, graph) * a0  # F' at th
        if df <= 0.0:
            return th
        th = th - dF / (h * df)
        return 1.0 if 1.0 < th else th
    g1, g2, g3, g4 = neighbour_poly(j, h, -1.0, graph, work)
    f0 = force(j, D, work.W, graph) - 1.0
    a, fa = lo, f0 + lo * (g1 + lo * (g2 + lo * (g3 + lo * g4)))
    b, fb = th, f0 + th * (g1 + th * (g2 + th * (g3 + th * g4))) + dF
    if fa >= 0.0:  # its force reached 1 before the first push: on the dense output alone
        return poly_root(0.0, lo, f0, g1, g2, g3, g4)
    if fb <= 0.0:
        return th
    side = 0
    for _ in range(30):
        c = (a * fb - b * fa) / (fb - fa)
        push, _ = _push(j, c, h, graph, work)
        fc = f0 + c * (g1 + c * (g2 + c * (g3 + c * g4))) + push
        if fc >= 0.0:
            b, fb = c, fc
            if side == 1:
                fa *= 0.5
            side = 1
        else:
            a, fa = c, fc
            if side == -1:
                fb *= 0.5
            side = -1
        if b - a < 1e-10:
            break
    return b


@inline_kernel
def _locate(h, ncand, graph, work):
    """Each listed crossing's fraction of the step, in ``W[b, VS]``, before any is applied.

    Stops are marked ``IW[CAND, c] = -2 - b`` and flagged STOPPING, joins flagged JOINING
    (after every fraction is found: the joins' roots read their slipping neighbours);
    a slipping block that does not stop after all and a join listed twice become -1.
    """
    W, IW, loc = work.W, work.IW, work.loc
    for c in range(ncand):
        b = IW[CAND, c]
        th = loc[LOC_THETA + c] if c < THETA_CACHE else 2.0
        if IW[FLAG, b] == ACTIVE:
            if th > 1.0:  # a dip, or a block that joined at rest: its own root
                th = stick_theta(h, IW[APOS, b], b, W, stage_rows(work))
            if th > 1.0:
                IW[CAND, c] = -1  # no stop after all
                continue
            IW[CAND, c] = -2 - b
        elif IW[FLAG, b] != JOINING:
            if th > 1.0:
                f0 = force(b, D, W, graph)
                f1 = force(b, P2, W, graph)
                th = 0.0 if f0 >= 1.0 else join_theta(h, b, f0, f1, graph, work)
            IW[FLAG, b] = JOINING
        else:
            IW[CAND, c] = -1  # listed twice
            continue
        W[b, VS] = th
    for c in range(ncand):
        if IW[CAND, c] <= -2:
            IW[FLAG, -2 - IW[CAND, c]] = STOPPING


@forced_kernel
def _key(e, W):
    """Order of the applied crossings: joins by their fraction of the step, then stops."""
    if e >= 0:
        return W[e, VS]
    if e <= -2:
        return 2.0 + W[-2 - e, VS]
    return 4.0


@inline_kernel
def _order(ncand, work):
    """Sort ``IW[CAND, :ncand]`` by :func:`_key` in place (Shell sort, gaps 1, 4, 13, ...).

    Returns the number of crossings kept: the dropped entries (-1) sort last.
    """
    W, IW = work.W, work.IW
    gap = 1
    while 3 * gap + 1 < ncand:
        gap = 3 * gap + 1
    while gap >= 1:
        for c in range(gap, ncand):
            e = IW[CAND, c]
            k = _key(e, W)
            d = c
            while d >= gap and _key(IW[CAND, d - gap], W) > k:
                IW[CAND, d] = IW[CAND, d - gap]
                d -= gap
            IW[CAND, d] = e
        gap //= 3
    while ncand > 0 and IW[CAND, ncand - 1] == -1:
        ncand -= 1
    return ncand


@kernel
def interpolated_crossings(h, h_min, nact, ntouch, w, keys, graph, work):
    """Apply every crossing the step's scan listed (``IW[CAND]``) at the step's end; commit.

    Called after a DP5 step of length h with ``scan == 2`` (the list complete:
    ``loc[LOC_NCAND] >= 0``).  The joins that the crossings reveal (:mod:`.late_joins`) are
    placed after them, in rounds, each where its force on its neighbours' paths reaches 1.
    Returns (nact, ntouch, th_stop): ``th_stop`` is the latest stop's fraction of the step
    (0.0 if none stopped), the event's end when no block is left slipping; -1.0 if a block
    that stopped in the step is over the threshold at its end (it slips again) and the step
    is longer than ``h_min``: nothing is committed, and the step is to be taken again at half
    its length, until the stop and the new start fall in different steps.
    """
    W, IW, loc, cnt = work.W, work.IW, work.loc, work.cnt
    ncand = np.int64(loc[LOC_NCAND])
    th_stop = 0.0
    _locate(h, ncand, graph, work)
    start = ncand - ncand
    while True:  # the scan's crossings, then rounds of the joins they reveal
        for c in range(start, ncand):
            b = IW[CAND, c]
            if b >= 0:
                W[b, VS] = _chained(b, W[b, VS], h, graph, work)
        if start == 0:
            ncand = _order(ncand, work)
            loc[LOC_MOVED] = 0.0
            # on the step's own values (D, V, A -> DN, VN, AN and the stages), corrected as they go
            for c in range(ncand):
                e = IW[CAND, c]
                if e <= -2:
                    th = W[-2 - e, VS]
                    _stop(-2 - e, th, h, graph, work)
                    th_stop = th if th > th_stop else th_stop
                elif e >= 0:
                    place_join(e, W[e, VS], h, graph, work)
        else:
            for c in range(start, ncand):
                late_join(IW[CAND, c], h, graph, work)
        revealed, ntouch = late_joins(start, ncand, ntouch, w, keys, graph, work)
        if revealed == ncand:
            break
        start, ncand = ncand, revealed
    if h > h_min:
        for c in range(ncand):
            e = IW[CAND, c]
            if e <= -2 and force(-2 - e, P2, W, graph) >= 1.0:
                take_again(ncand, work)
                return nact, ntouch, -1.0
    # commit the step (P2: every block's end position), then stops, joins and the
    # accelerations they change
    for q in range(nact):
        i = IW[ACT, q]
        x = W[i, P2]
        W[i, D] = x
        W[i, P] = x
        W[i, V] = W[i, VN]
        W[i, A] = W[i, AN]
    for c in range(ncand):
        e = IW[CAND, c]
        if e <= -2:
            nact = deactivate(-2 - e, nact, W, IW)
            cnt[CNT_INTERPOLATED_CROSSINGS] += 1
        else:
            b = e
            W[b, D] += W[b, SV]
            x = W[b, D]
            W[b, P] = x
            W[b, P2] = x
            nact, ntouch = activate(b, nact, ntouch, w, keys, graph, work)
            W[b, V] = W[b, SA]
            W[b, VN] = W[b, SA]
            cnt[CNT_INTERPOLATED_CROSSINGS] += 1
    for c in range(ncand):
        e = IW[CAND, c]
        b = -2 - e if e <= -2 else e
        refresh(b, graph, work)
        if IW[FLAG, b] == ACTIVE:
            W[b, A] = accel(b, P, V, W, graph)
    for c in range(ncand):
        e = IW[CAND, c]
        if e <= -2:
            nact, ntouch = rejoin(-2 - e, nact, ntouch, w, keys, graph, work)
    nact = stick_scan(nact, W, IW)
    return nact, ntouch, th_stop
