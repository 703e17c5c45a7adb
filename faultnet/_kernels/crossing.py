"""Stops and joins inside a step: where a slipping block stops, where a stuck one starts.

A *stick* is a slipping block whose velocity reaches 0; a *join* is a stuck
neighbour whose force reaches the static threshold 1.  Both are located as a
fraction ``theta`` of the step just taken: on the DP5 dense output (4th order,
method 1) or on a cubic Hermite interpolant of the end values (RK4, method 0,
and the rare stops of a block that joined at rest or dips below zero).
"""

import numpy as np

from faultnet._kernels.context import LOC_NCAND, LOC_THETA, THETA_CACHE
from faultnet._kernels.integrate import (
    ACT,
    ACTIVE,
    AN,
    APOS,
    CAND,
    FLAG,
    MARK,
    VN,
    VS,
    A,
    D,
    P,
    V,
    force,
    force_hot,
    hermite_dip,
    hermite_fall,
    hermite_root,
    poly_root,
)
from faultnet._kernels.jit import inline_kernel, kernel
from faultnet._kernels.tableau import KA, KV, dense_coeffs, slot_dense, stage_rows

__all__ = [
    "JOIN",
    "LANDED",
    "STICK",
    "STATUS_EVENT_TOO_LONG",
    "STATUS_NONFINITE",
    "STATUS_OK",
    "STATUS_RUNAWAY",
    "STATUS_SLIPS_FULL",
    "block_crossings",
    "candidate",
    "earliest_crossing",
    "join_theta",
    "stick_theta",
]

STATUS_OK = 0
STATUS_SLIPS_FULL = 1
STATUS_NONFINITE = -1
STATUS_RUNAWAY = -2
STATUS_EVENT_TOO_LONG = -3

STICK = 1
JOIN = 2
#: a join reached by landing on a step's interpolant (landing.py), which has checked that no
#: other stuck neighbour is at the threshold there
LANDED = 3


@kernel
def stick_theta(method, h, q, i, W, K):
    """Where inside the step block i (active position q) stops; 2.0 if it does not.

    ``W``: the work array; ``K``: the stage derivatives
    (:func:`~faultnet._kernels.tableau.stage_rows`).
    """
    v0 = W[i, V]
    v1 = W[i, VN]
    if v1 <= 0.0:
        if v0 > 0.0:
            if method == 1:
                c0, c1, c2, c3, c4 = slot_dense(v0, v1, h, K, q, KA, W[i, AN])
                return poly_root(0.0, 1.0, c0, c1, c2, c3, c4)
            return hermite_root(0.0, 1.0, v0, h * W[i, A], v1, h * W[i, AN])
        # joined at rest and stops again within the step
        return hermite_fall(h * W[i, A], v1, h * W[i, AN])
    if W[i, A] < 0.0 and W[i, AN] > 0.0:
        return hermite_dip(v0, h * W[i, A], v1, h * W[i, AN])
    return 2.0


@kernel
def join_theta(method, h, q0, j, f0, f1, graph, work):
    """Where inside the step the force on stuck block j reaches 1 (f0 < 1 <= f1).

    Inside a local region (``q0 > 0``) a block next to a slipping block outside
    the region returns 0.0: the region must grow (its neighbour's motion is not
    integrated with the region's steps).  ``graph``, ``work``:
    :class:`~faultnet._kernels.bundles.Graph` and ``Work``.
    """
    W, IW = work.W, work.IW
    K = stage_rows(work)
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    if method == 1:
        g1 = g3 = g4 = g5 = g6 = g7 = 0.0
        for r in range(indptr[j], indptr[j + 1]):
            b = indices[r]
            if IW[FLAG, b] == ACTIVE:
                c = kval[r]
                q = IW[APOS, b]
                if q < q0:
                    return 0.0
                g1 += c * K[q, KV]
                g3 += c * K[q, KV + 2]
                g4 += c * K[q, KV + 3]
                g5 += c * K[q, KV + 4]
                g6 += c * K[q, KV + 5]
                g7 += c * W[b, VN]
        c0, c1, c2, c3, c4 = dense_coeffs(
            f0 - 1.0, f1 - 1.0, h * g1, h * g3, h * g4, h * g5, h * g6, h * g7
        )
        return poly_root(0.0, 1.0, c0, c1, c2, c3, c4)
    df0 = 0.0
    df1 = 0.0
    for r in range(indptr[j], indptr[j + 1]):
        df0 += kval[r] * W[indices[r], V]
        df1 += kval[r] * W[indices[r], VN]
    return hermite_root(0.0, 1.0, f0 - 1.0, h * df0, f1 - 1.0, h * df1)


@kernel
def candidate(n, b, th, IW, loc):
    """Crossing candidate n of a local step is block b, at fraction ``th`` of the outer step.

    ``th`` 2.0: not located.  Thetas beyond ``THETA_CACHE`` candidates are not kept.
    """
    IW[CAND, n] = b
    if n < THETA_CACHE:
        loc[LOC_THETA + n] = th


@inline_kernel
def _list(b, th, IW, loc):
    """Append block b's crossing (at fraction th, 2.0: not located) to ``IW[CAND]``.

    The count is ``loc[LOC_NCAND]``; -1 once the row is full (the list is then
    not used).
    """
    n = int(loc[LOC_NCAND])
    if n >= IW.shape[1]:
        loc[LOC_NCAND] = -1.0
    elif n >= 0:
        candidate(n, b, th, IW, loc)
        loc[LOC_NCAND] = n + 1.0


@inline_kernel
def block_crossings(
    method, h, q0, q, i, pos, vmax, best, who, kind, listing, keep, stamp, graph, work
):
    """Fold the crossings owned by active block i into (best, who, kind).

    Block i's own stop, and the joins of its stuck neighbours, whose end-of-step
    forces are read from column ``pos`` (every active block's end position).
    With ``listing`` every crossing is also appended to ``IW[CAND]`` (a join
    once per slipping neighbour) for the local regions; a stop at a dip of v
    (a grazing crossing) is listed as not located.  With ``keep`` each stuck neighbour's
    force at the end of the step is kept in its (unused) ``AN`` column, a join's fraction of
    the step in its ``VS`` column, and the block tagged with the step's ``stamp`` in
    ``IW[MARK]``: a stuck block next to several slipping ones is evaluated (and its join
    located) once per step, and listed again from what was kept.  Returns (best, who,
    kind, status); a non-finite or runaway velocity stops the scan with its status and the
    block in ``who``.  Inlined into the step's last pass: ``graph`` and ``work``
    (:class:`~faultnet._kernels.bundles.Graph`, ``Work``) cost nothing here.
    """
    W, IW, loc = work.W, work.IW, work.loc
    indptr, indices = graph.indptr, graph.indices
    method = method + (q - q)  # int64, not the caller's literal: one signature of the roots
    v1 = W[i, VN]
    if not (v1 < vmax):
        return best, i, kind, STATUS_NONFINITE if v1 != v1 else STATUS_RUNAWAY
    if v1 <= 0.0 or W[i, A] < 0.0:
        th = stick_theta(method, h, q, i, W, stage_rows(work))
        if th < best:
            best, who, kind = th, i, STICK
        if listing and th <= 1.0:
            _list(i, th if W[i, V] > 0.0 and v1 <= 0.0 else 2.0, IW, loc)
    for p in range(np.uint64(indptr[i]), np.uint64(indptr[i + 1])):
        j = indices[p]
        u = np.uint64(j)  # unsigned: no negative-index wrap-around in the hot accesses
        if IW[FLAG, u] == ACTIVE:
            continue
        seen = keep and IW[MARK, u] == stamp  # evaluated for an earlier neighbour in this step
        f1 = W[u, AN] if seen else force_hot(u, pos, W, graph)
        if keep and not seen:
            W[u, AN] = f1
            IW[MARK, u] = stamp
        if f1 < 1.0:
            continue
        if seen:
            th = W[j, VS]
        else:
            f0 = force(j, D, W, graph)
            th = 0.0 if f0 >= 1.0 else join_theta(method, h, q0, j, f0, f1, graph, work)
            if keep:
                W[j, VS] = th
        if th < best:
            best, who, kind = th, j, JOIN
        if listing:
            _list(j, th, IW, loc)
    return best, who, kind, STATUS_OK


@kernel
def earliest_crossing(method, h, nact, vmax, graph, work):
    """Earliest stick or join inside the step just taken (D,V,A -> DN,VN,AN).

    Returns (theta, block, kind, status): theta in [0, 1] is the fraction of
    the step, block is -1 when nothing happens inside the step.  The DP5 step
    does this scan in its last pass (:func:`faultnet._kernels.dopri.dopri_step`).
    ``graph``, ``work``: :class:`~faultnet._kernels.bundles.Graph` and ``Work``.
    """
    IW = work.IW
    best = 2.0
    who = np.int64(-1)  # int64 from the start, not literals: fewer compiled signatures
    kind = np.int64(0)
    for q in range(nact):
        i = IW[ACT, q]
        best, who, kind, status = block_crossings(
            method,
            h,
            kind - kind,
            q,
            i,
            P,
            vmax,
            best,
            who,
            kind,
            False,
            False,
            kind - kind,
            graph,
            work,
        )
        if status != STATUS_OK:
            return best, who, kind, status
    return best, who, kind, STATUS_OK
