"""Dormand-Prince 5(4) step of the slipping blocks (fixed step, FSAL).

Same contract as :func:`faultnet._kernels.integrate.rk4_step`: from the
committed state (D, V, A) of the active blocks to (DN, VN, AN), leaving
``P == P2 == DN`` on active blocks and D, V, A untouched.  Stage derivatives
live in the columns ``KV + s`` (velocities) and ``KA + s`` (accelerations) of
the stage rows of W (:func:`~faultnet._kernels.tableau.stage_rows`), in the row
of the block's position in the active list (``K[q, KV + s]``).

For the same accuracy this fifth-order scheme takes steps about five times
longer than RK4 with 6 instead of 4 force evaluations per step (the seventh,
first-same-as-last evaluation is the next step's A), see docs/guide/performance.rst.
"""

import numpy as np

from faultnet._kernels.context import (
    BOUNDARY_CACHE,
    LOC_BND_END,
    LOC_BND_START,
    LOC_CACHE,
    LOC_OUTER_H,
    LOC_REGION_T,
)
from faultnet._kernels.crossing import STATUS_OK, block_crossings
from faultnet._kernels.integrate import (
    ACT,
    AN,
    APOS,
    BND,
    DN,
    P2,
    VN,
    A,
    D,
    P,
    V,
    force_hot,
    new_id,
)
from faultnet._kernels.jit import forced_kernel, inline_kernel, kernel
from faultnet._kernels.tableau import (
    _A21,
    _A31,
    _A32,
    _A41,
    _A42,
    _A43,
    _A51,
    _A52,
    _A53,
    _A54,
    _A61,
    _A62,
    _A63,
    _A64,
    _A65,
    _B1,
    _B3,
    _B4,
    _B5,
    _B6,
    KA,
    KV,
    N_STAGE,
    dense_coeffs,
    slot_dense,
    stage_rows,
)

__all__ = [
    "KA",
    "KV",
    "N_STAGE",
    "boundary_at",
    "boundary_coeffs",
    "boundary_positions",
    "cache_boundary",
    "dense_coeffs",
    "dopri_step",
]


@inline_kernel
def _cache_slot(r, loc):
    """Offset in ``loc`` of boundary entry r's coefficients, or -1 beyond the cache."""
    o = LOC_CACHE + 5 * r
    return o if r < BOUNDARY_CACHE and o + 5 <= loc.shape[0] else -1


@kernel
def boundary_coeffs(b, W, K, IW, loc):
    """Dense-output coefficients of boundary block b over the outer step (its outer slot).

    The position at fraction th of the outer step (length ``loc[LOC_OUTER_H]``) is
    ``c0 + th (c1 + th (c2 + th (c3 + th c4)))``.
    """
    return slot_dense(W[b, D], W[b, DN], loc[LOC_OUTER_H], K, IW[APOS, b], KV, W[b, VN])


@kernel
def cache_boundary(r, b, W, K, IW, loc):
    """Keep the dense-output coefficients of boundary block b (entry r) in ``loc``.

    The boundary follows the outer step at every stage of every step of its
    region; its coefficients are computed here once, not at each stage.
    """
    o = _cache_slot(r, loc)
    if o >= 0:
        loc[o], loc[o + 1], loc[o + 2], loc[o + 3], loc[o + 4] = boundary_coeffs(b, W, K, IW, loc)


@kernel
def boundary_positions(col, th, W, K, IW, loc):
    """Write the boundary blocks' positions at fraction ``th`` of the outer step to ``col``.

    The boundary of a local region (``IW[BND, loc[LOC_BND_START]:loc[LOC_BND_END]]``) are
    slipping blocks outside it; they follow the DP5 dense output of the outer step of
    length ``loc[LOC_OUTER_H]``, whose stage derivatives are in their outer slot
    ``IW[APOS, b]`` and whose coefficients :func:`cache_boundary` keeps.
    """
    for r in range(int(loc[LOC_BND_START]), int(loc[LOC_BND_END])):
        b = IW[BND, r]
        o = _cache_slot(r, loc)
        if o >= 0:
            c0, c1, c2, c3, c4 = loc[o], loc[o + 1], loc[o + 2], loc[o + 3], loc[o + 4]
        else:
            c0, c1, c2, c3, c4 = boundary_coeffs(b, W, K, IW, loc)
        W[b, col] = c0 + th * (c1 + th * (c2 + th * (c3 + th * c4)))


@kernel
def boundary_at(th, W, K, IW, loc):
    """The boundary blocks at fraction ``th`` of the outer step, in both stage columns P and P2."""
    boundary_positions(P, th, W, K, IW, loc)
    boundary_positions(P2, th, W, K, IW, loc)


@forced_kernel
def _acc(i, pos, v, W, graph):
    """Acceleration of block i at stage positions ``pos`` and stage velocity ``v``."""
    den = 1.0 + graph.cfr[i] * v
    if den < 0.5:
        den = 0.5
    return force_hot(i, pos, W, graph) - graph.oms[i] / den


@kernel
def dopri_step(h, q0, nact, scan, vmax, graph, work):
    """One Dormand-Prince 5(4) step of length ``h`` for the active blocks ``q0 <= q < nact``.

    Stage s reads positions from one of the columns P, P2 and writes the inputs
    of stage s + 1 to the other, which no block reads during that pass.  With
    ``scan`` the last pass (the first-same-as-last acceleration) also locates
    the earliest stop or join inside the step, as
    :func:`faultnet._kernels.crossing.earliest_crossing` would, and returns
    (theta, block, kind, status); otherwise (2.0, -1, 0, STATUS_OK).  With
    ``scan >= 2`` it also lists every crossing for the local regions or the interpolated
    crossings (``IW[CAND]``, counted from ``loc[LOC_NCAND]``, which the caller zeroes); with
    ``scan == 3`` (interpolated crossings) it keeps each stuck neighbour's force at the end
    of the step in ``W[j, AN]`` (unused for stuck blocks) for the late joins' check.

    Inside a local region (``loc[LOC_BND_END] > loc[LOC_BND_START]``) the boundary blocks'
    positions are written at each stage time from the outer step's dense output; the
    step starts at fraction ``loc[LOC_REGION_T]`` of that outer step.

    ``graph``, ``work``: :class:`~faultnet._kernels.bundles.Graph` and ``Work``, unpacked
    once here; the stage passes inline :func:`_acc` and the scan.

    The passes index with unsigned integers (active positions q, blocks i), for which Numba
    omits its negative-index wrap-around: 2-5% more events/s on W1, W4 and W5.  The scan and
    :func:`~faultnet._kernels.integrate.force` take them back as int64 (one signature each).
    """
    W, IW, loc = work.W, work.IW, work.loc
    K = stage_rows(work)
    bnd = loc[LOC_BND_END] > loc[LOC_BND_START]
    th0 = loc[LOC_REGION_T]
    hr = h / loc[LOC_OUTER_H] if bnd else 0.0
    for q in range(np.uint64(q0), np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v = W[i, V]
        a = W[i, A]
        K[q, KV] = v
        K[q, KA] = a
        W[i, P] = W[i, D] + h * _A21 * v
        K[q, KV + 1] = v + h * _A21 * a
    if bnd:
        boundary_positions(P, th0 + 0.2 * hr, W, K, IW, loc)
    for q in range(np.uint64(q0), np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v2 = K[q, KV + 1]
        a2 = _acc(i, P, v2, W, graph)
        K[q, KA + 1] = a2
        W[i, P2] = W[i, D] + h * (_A31 * K[q, KV] + _A32 * v2)
        K[q, KV + 2] = W[i, V] + h * (_A31 * K[q, KA] + _A32 * a2)
    if bnd:
        boundary_positions(P2, th0 + 0.3 * hr, W, K, IW, loc)
    for q in range(np.uint64(q0), np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v3 = K[q, KV + 2]
        a3 = _acc(i, P2, v3, W, graph)
        K[q, KA + 2] = a3
        W[i, P] = W[i, D] + h * (_A41 * K[q, KV] + _A42 * K[q, KV + 1] + _A43 * v3)
        K[q, KV + 3] = W[i, V] + h * (_A41 * K[q, KA] + _A42 * K[q, KA + 1] + _A43 * a3)
    if bnd:
        boundary_positions(P, th0 + 0.8 * hr, W, K, IW, loc)
    for q in range(np.uint64(q0), np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v4 = K[q, KV + 3]
        a4 = _acc(i, P, v4, W, graph)
        K[q, KA + 3] = a4
        dp = _A51 * K[q, KV] + _A52 * K[q, KV + 1] + _A53 * K[q, KV + 2] + _A54 * v4
        dv = _A51 * K[q, KA] + _A52 * K[q, KA + 1] + _A53 * K[q, KA + 2] + _A54 * a4
        W[i, P2] = W[i, D] + h * dp
        K[q, KV + 4] = W[i, V] + h * dv
    if bnd:
        boundary_positions(P2, th0 + 8.0 / 9.0 * hr, W, K, IW, loc)
    for q in range(np.uint64(q0), np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v5 = K[q, KV + 4]
        a5 = _acc(i, P2, v5, W, graph)
        K[q, KA + 4] = a5
        dp = (
            _A61 * K[q, KV]
            + _A62 * K[q, KV + 1]
            + _A63 * K[q, KV + 2]
            + _A64 * K[q, KV + 3]
            + _A65 * v5
        )
        dv = (
            _A61 * K[q, KA]
            + _A62 * K[q, KA + 1]
            + _A63 * K[q, KA + 2]
            + _A64 * K[q, KA + 3]
            + _A65 * a5
        )
        W[i, P] = W[i, D] + h * dp
        K[q, KV + 5] = W[i, V] + h * dv
    if bnd:
        boundary_positions(P, th0 + 1.0 * hr, W, K, IW, loc)
    for q in range(np.uint64(q0), np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v6 = K[q, KV + 5]
        a6 = _acc(i, P, v6, W, graph)
        K[q, KA + 5] = a6
        dp = (
            _B1 * K[q, KV] + _B3 * K[q, KV + 2] + _B4 * K[q, KV + 3] + _B5 * K[q, KV + 4] + _B6 * v6
        )
        dv = (
            _B1 * K[q, KA] + _B3 * K[q, KA + 2] + _B4 * K[q, KA + 3] + _B5 * K[q, KA + 4] + _B6 * a6
        )
        dn = W[i, D] + h * dp
        W[i, DN] = dn
        W[i, VN] = W[i, V] + h * dv
        W[i, P2] = dn
    best = 2.0
    who = np.int64(-1)  # int64 from the start, not literals: fewer compiled signatures
    kind = np.int64(0)
    if bnd:
        boundary_positions(P2, th0 + 1.0 * hr, W, K, IW, loc)
    listing = scan >= 2
    keep = scan == 3
    stamp = who - who  # int64
    if keep:
        stamp = new_id(work.cnt)  # the tag of this step's evaluations of stuck neighbours
    for q in range(np.uint64(q0), np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        W[i, P] = W[i, DN]
        W[i, AN] = _acc(i, P2, W[i, VN], W, graph)
        if scan:
            # P2 holds every active block's end position (P is being updated)
            sq, si = np.int64(q), np.int64(i)  # signed again: the scan's one signature
            best, who, kind, status = block_crossings(
                1, h, q0, sq, si, P2, vmax, best, who, kind, listing, keep, stamp, graph, work
            )
            if status != STATUS_OK:
                return best, who, kind, status
    return best, who, kind, STATUS_OK
