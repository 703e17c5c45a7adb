"""Joins that a step's crossings reveal: blocks they push over the threshold inside the step.

After :func:`.interp.interpolated_crossings` has applied a step's listed
stops and joins, the blocks they moved (a stopping or joining block b, and b's slipping
neighbours, whose ends were corrected) may have pushed a stuck neighbour's force to 1 at the
end of the step: such a block is a neighbour of b or of one of b's slipping neighbours
(:func:`late_joins`, before the commit, on the end positions in ``P2``).  Its force passed 1
inside the step, and it starts where it did: at the root of its force on its neighbours'
paths (:func:`_late_theta`), not at rest at the step's end, which would make it join up to a
whole step late.  A block that stopped in the step and is over the threshold at its end
slips again (:func:`rejoin`), from where the force's expansion back from the end crosses 1
(:func:`_late_start`).

Arguments: ``h`` the step's length, ``b``, ``j``, ``n`` blocks, ``s`` a fraction of the step,
``nact``, ``ntouch``, ``ncand`` the lengths of the active, touched and crossing lists, ``w`` the
plate position and ``keys`` the failure keys (for the blocks a join touches), ``W``, ``IW`` the
work arrays, ``graph`` and ``work`` the ``Graph`` and ``Work`` bundles
(:mod:`~faultnet.solver._kernels.bundles`).
"""

import numpy as np

from faultnet.solver._kernels.carlson_langer.physics import (
    accel,
    force,
    friction_slope,
    start_accel,
)
from faultnet.solver._kernels.carlson_langer.response import (
    COMMITTED,
    join_cubic,
    place_join,
    respond,
    stop_answer,
)
from faultnet.solver._kernels.carlson_langer.stepping import activate, touch
from faultnet.solver._kernels.carlson_langer.tableau import path_dense
from faultnet.solver._kernels.carlson_langer.work import (
    ACTIVE,
    AN,
    CAND,
    DN,
    FLAG,
    FRONTIER,
    JOINING,
    LOC_MOVED,
    P2,
    STOPPING,
    STUCK,
    SV,
    UNTOUCHED,
    VN,
    VS,
    A,
    D,
    P,
    V,
)
from faultnet.solver._kernels.jit import forced_kernel, inline_kernel, kernel

__all__ = ["late_joins", "refresh", "rejoin"]


@kernel
def refresh(b, graph, work):
    """Accelerations of b's slipping neighbours (b has moved)."""
    W, IW = work.W, work.IW
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        n = graph.indices[p]
        if IW[FLAG, n] == ACTIVE:
            W[n, A] = accel(n, P, V, W, graph)


@inline_kernel
def _first_root(c0, c1, c2, hi):
    """Smallest root of c0 + c1 t + c2 t^2 in (0, hi], or -1.0."""
    if c2 == 0.0:
        r = -c0 / c1 if c1 != 0.0 else -1.0
        return r if 0.0 < r <= hi else -1.0
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return -1.0
    sq = disc**0.5
    r1 = (-c1 - sq) / (2.0 * c2)
    r2 = (-c1 + sq) / (2.0 * c2)
    lo_r = r2 if r2 < r1 else r1
    hi_r = r2 if r2 > r1 else r1
    if 0.0 < lo_r <= hi:
        return lo_r
    return hi_r if 0.0 < hi_r <= hi else -1.0


@kernel
def _late_start(j, over, h, graph, work):
    """Start block j, whose force is ``1 + over`` at the end of the step, where it crossed 1.

    j stopped in the step, and its neighbours' moves after its stop brought its force back
    over the threshold.  Going back from the step's end by t, the force falls by
    ``d1 t - d2 t^2 / 2`` (d1, d2 from its slipping neighbours' velocities and accelerations
    at the end).  j crossed 1 at the first root (at most h back) and starts there on the
    Taylor series of its path to the third power of the time since the join; starting it at
    rest at the step's end would make it join up to a whole step late.
    """
    W, IW, kval, indices = work.W, work.IW, graph.kval, graph.indices
    d1 = 0.0
    d2 = 0.0
    for p in range(graph.indptr[j], graph.indptr[j + 1]):
        n = indices[p]
        if IW[FLAG, n] == ACTIVE:
            d1 += kval[p] * W[n, V]
            d2 += kval[p] * W[n, A]
    t = _first_root(over, -d1, 0.5 * d2, h)
    if t < 0.0:
        t = h
    a0 = start_accel(j, graph)
    jerk = d1 - d2 * t + friction_slope(j, 0.0, graph) * a0  # F' at the join, and friction's
    x = W[j, D] + t * t * (0.5 * a0 + t * jerk / 6.0)
    W[j, D] = x
    W[j, P] = x
    W[j, P2] = x
    W[j, DN] = x
    v = t * (a0 + 0.5 * t * jerk)
    W[j, V] = v
    W[j, VN] = v
    W[j, A] = accel(j, P, V, W, graph)
    # its slipping neighbours' answer to its path since the join (moments of the cubic start)
    t2 = t * t
    t4 = t2 * t2
    respond(
        j,
        -1.0,
        t2 * t * (a0 / 6.0 + t * jerk / 24.0),
        t4 * (a0 / 24.0 + t * jerk / 120.0),
        t4 * t * (a0 / 120.0 + t * jerk / 720.0),
        t4 * t2 * (a0 / 720.0 + t * jerk / 5040.0),
        COMMITTED,
        graph,
        work,
    )
    refresh(j, graph, work)


@inline_kernel
def rejoin(b, h, nact, ntouch, w, keys, graph, work):
    """Block b stopped in the step; if its force at the step's end is >= 1 it slips again.

    Returns (nact, ntouch).
    """
    flag = work.IW[FLAG, b]
    if flag != ACTIVE and flag != UNTOUCHED:
        f = force(b, D, work.W, graph)
        if f >= 1.0:
            nact, ntouch = activate(b, nact, ntouch, w, keys, graph, work)
            _late_start(b, f - 1.0, h, graph, work)
    return nact, ntouch


@inline_kernel
def _offset(n, s, h, work):
    """Displacement of block n at fraction s of the step since the step's start, on its path.

    Slipping: the step's dense output; stopping: the same up to its stop (``W[n, VS]``), then
    its stop position ``W[n, SV]``; joining: the cubic of :func:`~.response.
    neighbour_poly` from its join on; stuck: 0.
    """
    W = work.W
    fl = work.IW[FLAG, n]
    if fl == ACTIVE or fl == STOPPING:
        if fl == STOPPING and s > W[n, VS]:
            return W[n, SV] - W[n, D]
        _, c1, c2, c3, c4 = path_dense(n, h, work)
        return s * (c1 + s * (c2 + s * (c3 + s * c4)))
    if fl == JOINING:
        return join_cubic(n, s, h, W)
    return 0.0


@inline_kernel
def _late_theta(j, h, graph, work):
    """Fraction of the step at which stuck block j's force reached 1 on its neighbours' paths.

    The force only rises during an event: bisection on ``[0, 1]`` to 2^-40.
    """
    W = work.W
    f0 = force(j, D, W, graph) - 1.0
    if f0 >= 0.0:
        return 0.0
    lo, hi = 0.0, 1.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        f = f0
        for p in range(graph.indptr[j], graph.indptr[j + 1]):
            f += graph.kval[p] * _offset(graph.indices[p], mid, h, work)
        if f >= 0.0:
            hi = mid
        else:
            lo = mid
    return hi


@kernel
def _late_join(j, h, graph, work):
    """Stuck block j, pushed over the threshold by the step's crossings, joins where it did.

    Its path (:func:`~.response.join_path`) from the fraction where its force crossed 1, its
    slipping and earlier-joining neighbours' answer to it, and its own answer to its stopping
    neighbours.  A kernel: :func:`_check` (LLVM inlines it at two sites) runs for every
    neighbour of a crossing, this rarely.
    """
    W, IW = work.W, work.IW
    th = _late_theta(j, h, graph, work)
    IW[FLAG, j] = JOINING
    W[j, VS] = th
    place_join(j, th, h, graph, work)
    for p in range(graph.indptr[j], graph.indptr[j + 1]):
        b = graph.indices[p]
        if IW[FLAG, b] == STOPPING:
            c0, c1, c2, c3, c4 = path_dense(b, h, work)
            stop_answer(j, graph.kval[p], W[b, SV], W[b, VS], h, c0, c1, c2, c3, c4, graph, work)


@forced_kernel
def _check(j, joining, h, ncand, ntouch, w, keys, graph, work):
    """Stuck block j joins if its force at the step's end (``P2``) is >= 1.

    A block next to a ``joining`` one may not be touched yet (its start force unknown): it is
    touched here (every neighbour of a slipping block is touched; an untouched neighbour of
    the block of a solo slip is held, ``solo.solo_start``).  Otherwise j is next to a block
    that slipped through the step, whose scan kept j's force at the end of the step in
    ``W[j, AN]``: since then no neighbour's end position moved by more than the step's
    summed moves ``loc[LOC_MOVED]``, so j's force cannot have reached 1 if that force plus
    their bound (times its springs' sum, ``diag - 1``) is below 1.  Returns (ncand, ntouch).
    """
    W, IW = work.W, work.IW
    fl = IW[FLAG, j]
    if fl == UNTOUCHED and joining:
        ntouch = touch(j, w, keys, W, IW, ntouch)
        fl = FRONTIER
    elif not joining:
        reach = (graph.diag[j] - 1.0) * work.loc[LOC_MOVED]
        if W[j, AN] + reach * (1.0 + 1e-9) + 1e-12 < 1.0:
            return ncand, ntouch
    if fl == STUCK or fl == FRONTIER:
        if force(j, P2, W, graph) >= 1.0:
            _late_join(j, h, graph, work)
            IW[CAND, ncand] = j
            ncand += 1
    return ncand, ntouch


@inline_kernel
def late_joins(h, ncand, ntouch, w, keys, graph, work):
    """Joins revealed by the step's crossings, before the commit; returns (ncand, ntouch).

    After the listed stops and joins are applied (``IW[CAND, :ncand]``), only they and their
    slipping neighbours have moved from where the step's scan saw them, so a stuck block
    whose force at the end of the step (``P2``) now reaches 1 is a neighbour of a crossing
    block or of one of its slipping neighbours.  Each such join is appended to the list (and
    its own neighbours scanned in turn).  The list holds at most one entry per block.
    """
    IW = work.IW
    indptr, indices = graph.indptr, graph.indices
    c = 0
    while c < ncand:
        e = IW[CAND, c]
        c += 1
        b = -2 - e if e <= -2 else e
        for p in range(indptr[b], indptr[b + 1]):
            n = indices[p]
            ncand, ntouch = _check(n, e >= 0, h, ncand, ntouch, w, keys, graph, work)
            if IW[FLAG, n] == ACTIVE:
                for r in range(indptr[n], indptr[n + 1]):
                    if indices[r] != b:
                        ncand, ntouch = _check(
                            indices[r], np.bool_(False), h, ncand, ntouch, w, keys, graph, work
                        )
    return ncand, ntouch
