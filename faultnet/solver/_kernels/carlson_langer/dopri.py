"""Dormand-Prince 5(4) step of the slipping blocks (fixed step, FSAL).

From the committed state (D, V, A) of the active blocks to (DN, VN, AN), leaving
``P == P2 == DN`` on active blocks and D, V, A untouched, so that the step can be redone with
another length.  Stage derivatives live in the columns ``KV + s`` (velocities) and ``KA + s``
(accelerations) of the stage rows of W (:func:`~.tableau.stage_rows`), in the row of the
block's position in the active list (``K[q, KV + s]``); ``graph`` is the ``Graph`` bundle.

For the same accuracy this fifth-order scheme takes steps about five times longer than RK4
with 6 instead of 4 force evaluations per step (the seventh, first-same-as-last evaluation is
the next step's A), see docs/guide/performance.rst.  The tableau is written out as named
constants, so each stage pass is straight-line code with constant coefficients (20% faster
than loops over a coefficient array).
"""

import numpy as np

from faultnet.solver._kernels.bundles import kelvin
from faultnet.solver._kernels.carlson_langer.crossing import STATUS_OK, block_crossings
from faultnet.solver._kernels.carlson_langer.physics import accel_hot
from faultnet.solver._kernels.carlson_langer.tableau import KA, KV, stage_rows
from faultnet.solver._kernels.carlson_langer.work import (
    ACT,
    AN,
    DN,
    P2,
    PLATE,
    Q2,
    VN,
    A,
    D,
    P,
    Q,
    V,
    new_id,
)
from faultnet.solver._kernels.jit import kelvin_kernel, kernel

__all__ = ["dopri_step"]

# Butcher tableau (Dormand & Prince 1980)
_A21 = 1 / 5
_A31, _A32 = 3 / 40, 9 / 40
_A41, _A42, _A43 = 44 / 45, -56 / 15, 32 / 9
_A51, _A52, _A53, _A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
_A61, _A62, _A63, _A64, _A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
# the stages' times, as fractions of the step (c6 = c7 = 1)
_C2, _C3, _C4, _C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
# weights of the 5th-order solution (b2 = 0)
_B1, _B3, _B4, _B5, _B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84


@kelvin_kernel
def _stage_velocity(v, i, col, W, graph):
    """With viscous coupling, block ``i``'s stage velocity ``v`` into column ``col`` (Q, Q2)."""
    if graph.viscous:
        W[i, col] = v
    return v


@kelvin_kernel
def _plate_stage(base, frac, nu_h, pos, W, graph):
    """With a moving plate, its advance ``base + frac nu_h`` (``frac`` of the step) at ``pos``."""
    if graph.nu > 0.0:
        W[PLATE, pos] = base + frac * nu_h
    return base


@kernel
def dopri_step(h, nact, scan, vmax, graph, work):
    """One Dormand-Prince 5(4) step of length ``h`` for the active blocks ``IW[ACT, :nact]``.

    Stage s reads positions from one of the columns P, P2 and writes the inputs
    of stage s + 1 to the other, which no block reads during that pass.  With
    ``scan`` the last pass (the first-same-as-last acceleration) also locates
    the earliest stop or join inside the step, as
    (:func:`~.crossing.block_crossings`) and returns (theta, block, kind, status): theta the
    fraction of the step, block -1 when nothing crosses; otherwise (2.0, -1, 0, STATUS_OK).
    With ``scan == 2`` (interpolated crossings) it also lists every crossing
    (``IW[CAND]``, counted from ``loc[LOC_NCAND]``, which the caller zeroes) and keeps each
    stuck neighbour's force at the end of the step in ``W[j, AN]`` (unused for stuck blocks)
    for the late joins' check.

    ``h``: the step's length; ``nact``: the number of active blocks; ``vmax``: the fastest
    velocity allowed (a faster block stops the scan with ``STATUS_RUNAWAY``); ``graph``,
    ``work``: :class:`~faultnet.solver._kernels.bundles.Graph` and ``Work``, unpacked once here; the
    stage passes inline :func:`~.physics.accel_hot` and the scan.

    Where the plate moves during events (``graph.nu``), each pass first sets the plate's
    advance at its stage's time in the plate row; with viscous coupling (``graph.viscous``)
    each pass also writes its blocks' next stage velocities in the column paired with the
    positions it writes (Q with P, Q2 with P2), which their neighbours' viscous force reads;
    after the step P and P2 hold its end, VN in Q and Q2.  Both are Kelvin kernels: a plain
    model's step is compiled without them.

    The passes index with unsigned integers (active positions q, blocks i), for which Numba
    omits its negative-index wrap-around: 2-5% more events/s on W1, W4 and W5.  The scan and
    :func:`~.physics.force` take them back as int64 (one signature each).
    """
    W, IW = work.W, work.IW
    K = stage_rows(work)
    nu_h = graph.nu * h
    base = W[PLATE, D]
    for q in range(np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v = W[i, V]
        a = W[i, A]
        K[q, KV] = v
        K[q, KA] = a
        W[i, P] = W[i, D] + h * _A21 * v
        K[q, KV + 1] = v + h * _A21 * a
        _stage_velocity(K[q, KV + 1], i, Q, W, graph)
    _plate_stage(base, _C2, nu_h, P, W, graph)
    for q in range(np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v2 = K[q, KV + 1]
        a2 = accel_hot(i, P, v2, W, graph)
        K[q, KA + 1] = a2
        W[i, P2] = W[i, D] + h * (_A31 * K[q, KV] + _A32 * v2)
        K[q, KV + 2] = W[i, V] + h * (_A31 * K[q, KA] + _A32 * a2)
        _stage_velocity(K[q, KV + 2], i, Q2, W, graph)
    _plate_stage(base, _C3, nu_h, P2, W, graph)
    for q in range(np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v3 = K[q, KV + 2]
        a3 = accel_hot(i, P2, v3, W, graph)
        K[q, KA + 2] = a3
        W[i, P] = W[i, D] + h * (_A41 * K[q, KV] + _A42 * K[q, KV + 1] + _A43 * v3)
        K[q, KV + 3] = W[i, V] + h * (_A41 * K[q, KA] + _A42 * K[q, KA + 1] + _A43 * a3)
        _stage_velocity(K[q, KV + 3], i, Q, W, graph)
    _plate_stage(base, _C4, nu_h, P, W, graph)
    for q in range(np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v4 = K[q, KV + 3]
        a4 = accel_hot(i, P, v4, W, graph)
        K[q, KA + 3] = a4
        dp = _A51 * K[q, KV] + _A52 * K[q, KV + 1] + _A53 * K[q, KV + 2] + _A54 * v4
        dv = _A51 * K[q, KA] + _A52 * K[q, KA + 1] + _A53 * K[q, KA + 2] + _A54 * a4
        W[i, P2] = W[i, D] + h * dp
        K[q, KV + 4] = W[i, V] + h * dv
        _stage_velocity(K[q, KV + 4], i, Q2, W, graph)
    _plate_stage(base, _C5, nu_h, P2, W, graph)
    for q in range(np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v5 = K[q, KV + 4]
        a5 = accel_hot(i, P2, v5, W, graph)
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
        _stage_velocity(K[q, KV + 5], i, Q, W, graph)
    _plate_stage(base, 1.0, nu_h, P, W, graph)
    for q in range(np.uint64(nact)):
        i = np.uint64(IW[ACT, q])
        v6 = K[q, KV + 5]
        a6 = accel_hot(i, P, v6, W, graph)
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
        _stage_velocity(W[i, VN], i, Q2, W, graph)
    _plate_stage(base, 1.0, nu_h, P2, W, graph)
    _plate_stage(base, 1.0, nu_h, DN, W, graph)
    best = 2.0
    who = np.int64(-1)  # int64 from the start, not literals: fewer compiled signatures
    kind = np.int64(0)
    keep = scan == 2
    stamp = who - who  # int64
    if keep:
        stamp = new_id(work.cnt)  # the tag of this step's evaluations of stuck neighbours
    # a viscous join's rate reads its slipping neighbours' end accelerations: with viscous
    # coupling the scan waits until this pass has written all of them, and runs over the
    # active list a second time (one call site of the inlined scan either way)
    late = kelvin(graph) and graph.viscous and scan
    n = np.uint64(nact)
    for r in range(n + n if late else n):
        q = np.uint64(r) if r < n else np.uint64(r) - n  # (uint64 in Python too)
        i = np.uint64(IW[ACT, q])
        if r < n:
            W[i, P] = W[i, DN]
            _stage_velocity(W[i, VN], i, Q, W, graph)
            W[i, AN] = accel_hot(i, P2, W[i, VN], W, graph)
        if scan and (r >= n) == late:
            # P2 holds every active block's end position (P is being updated)
            sq, si = np.int64(q), np.int64(i)  # signed again: the scan's one signature
            best, who, kind, status = block_crossings(
                h, sq, si, P2, vmax, best, who, kind, keep, stamp, K, graph, work
            )
            if status != STATUS_OK:
                return best, who, kind, status
    return best, who, kind, STATUS_OK
