"""Joins at the end of an interpolated step: blocks pushed over the threshold by its crossings.

After :func:`faultnet._kernels.interp.interpolated_crossings` has applied a step's stops and
joins, the blocks they moved (a stopped or started block b, and b's slipping neighbours, whose
ends were corrected) may have pushed a stuck neighbour's force to 1: such a block is a
neighbour of b or of one of b's slipping neighbours (:func:`joins_near`).  Its force passed 1
inside the step, and it starts where it did (:func:`_late_start`), not at rest at the step's
end, which would make it join up to a whole step late.

``graph`` and ``work`` are the bundles :class:`~faultnet._kernels.bundles.Graph` and
:class:`~faultnet._kernels.bundles.Work`.
"""

from faultnet._kernels.integrate import (
    ACTIVE,
    DN,
    FLAG,
    P2,
    SA,
    UNTOUCHED,
    VN,
    VS,
    A,
    D,
    P,
    V,
    accel,
    force,
)
from faultnet._kernels.jit import inline_kernel, kernel
from faultnet._kernels.response import respond
from faultnet._kernels.stepping import activate

__all__ = ["joins_near", "refresh"]


@kernel
def refresh(b, graph, work):
    """Accelerations of b's slipping neighbours (b has moved)."""
    W, IW = work.W, work.IW
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        n = graph.indices[p]
        if IW[FLAG, n] == ACTIVE:
            W[n, A] = accel(n, P, V, W, graph)


@inline_kernel
def _first_root(c0, c1, c2, lo, hi):
    """Smallest root of c0 + c1 t + c2 t^2 in (lo, hi], or -1.0."""
    best = -1.0
    if c2 == 0.0:
        if c1 != 0.0:
            r = -c0 / c1
            if lo < r <= hi:
                best = r
        return best
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return best
    sq = disc**0.5
    r1 = (-c1 - sq) / (2.0 * c2)
    r2 = (-c1 + sq) / (2.0 * c2)
    for r in (min(r1, r2), max(r1, r2)):
        if lo < r <= hi:
            return r
    return best


@kernel
def _late_start(j, over, h, b, graph, work):
    """Start block j, whose force is ``1 + over`` at the end of the step, where it crossed 1.

    Its force passed the threshold only through the crossings' corrections, so the scan did
    not place it.  Going back from the step's end by t, the force falls by
    ``d1 t - d2 t^2 / 2`` (d1, d2 from its slipping neighbours' velocities and accelerations)
    and, before the stop of neighbour b (``W[b, VS]``, ``-1``: none) by
    ``k |a_b| (t - t_b)^2 / 2`` more (b's deceleration at its stop, ``W[b, SA]``; a force
    rises monotonically in an event, so a join that the stop of b made appear happened before
    that stop).  j crossed 1 at the first root (at most h back) and starts there on the
    Taylor series of its path to the third power of the time since the join; starting it at
    rest at the step's end would make it join up to a whole step late.
    """
    W, IW, kval, indices = work.W, work.IW, graph.kval, graph.indices
    d1 = 0.0
    d2 = 0.0
    cb = 0.0
    for p in range(graph.indptr[j], graph.indptr[j + 1]):
        n = indices[p]
        if IW[FLAG, n] == ACTIVE:
            d1 += kval[p] * W[n, V]
            d2 += kval[p] * W[n, A]
        elif n == b and IW[FLAG, n] != ACTIVE:
            cb = 0.5 * kval[p] * abs(W[b, SA])
    tb = h
    if cb > 0.0:
        tb = (1.0 - W[b, VS]) * h
    t = _first_root(over, -d1, 0.5 * d2, 0.0, tb)
    if t < 0.0 and tb < h:  # before b's stop
        t = _first_root(over - cb * tb * tb, 2.0 * cb * tb - d1, 0.5 * d2 - cb, tb, h)
    if t < 0.0:
        t = h
    a0 = 1.0 - graph.oms[j]
    df = d1 - d2 * t + 2.0 * cb * max(t - tb, 0.0)  # F' at the join
    jerk = df + graph.oms[j] * graph.cfr[j] * a0
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
        t2 * t * (a0 / 6.0 + t * jerk / 24.0),
        t4 * (a0 / 24.0 + t * jerk / 120.0),
        t4 * t * (a0 / 120.0 + t * jerk / 720.0),
        t4 * t2 * (a0 / 720.0 + t * jerk / 5040.0),
        True,
        graph,
        work,
    )
    refresh(j, graph, work)


@inline_kernel
def _join_at_threshold(j, h, b, nact, ntouch, w, keys, graph, work):
    """Activate touched stuck block j if its force is >= 1 (b: its crossing neighbour or -1).

    Returns (nact, ntouch).
    """
    flag = work.IW[FLAG, j]
    if flag != ACTIVE and flag != UNTOUCHED:
        f = force(j, D, work.W, graph)
        if f >= 1.0:
            nact, ntouch = activate(j, nact, ntouch, w, keys, graph, work)
            _late_start(j, f - 1.0, h, b, graph, work)
    return nact, ntouch


@kernel
def joins_near(b, h, nact, ntouch, w, keys, graph, work):
    """Joins at the end of a step near crossing block b: b, its neighbours, and theirs.

    After the step's scan listed every join, only b (stopped or started) and its slipping
    neighbours (their ends corrected by ``interp._correct``) moved, so a stuck block that reaches
    the threshold now is a neighbour of b or of one of b's slipping neighbours: scanning
    there finds every block a scan of the whole event would (the whole event's scan cost a
    sixth of the time on a 150^2 lattice at rtol 2e-5), in the order of the crossings.
    """
    indptr, indices, IW = graph.indptr, graph.indices, work.IW
    nact, ntouch = _join_at_threshold(b, h, b - b - 1, nact, ntouch, w, keys, graph, work)
    for p in range(indptr[b], indptr[b + 1]):
        n = indices[p]
        # only a slipping neighbour was corrected; a stuck one has not moved
        corrected = IW[FLAG, n] == ACTIVE
        nact, ntouch = _join_at_threshold(n, h, b, nact, ntouch, w, keys, graph, work)
        if corrected:
            for r in range(indptr[n], indptr[n + 1]):
                if indices[r] != b:  # b is checked above
                    nact, ntouch = _join_at_threshold(
                        indices[r], h, b - b - 1, nact, ntouch, w, keys, graph, work
                    )
    return nact, ntouch
