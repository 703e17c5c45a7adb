"""Inside an event: forces, one RK4 step of the slipping blocks, Hermite roots.

Only *active* (slipping) blocks are integrated.  Positions are displacements
``delta`` since the start of the event, so round-off does not grow with the
plate position.  Float work lives in the columns of ``W`` (shape (2 N + 1, N_WORK),
block-major so one block's values share cache lines), int work in the rows of
``IW`` (shape (N_IWORK, N); the active list ``IW[ACT, q0:nact]`` is contiguous,
``q0 = 0`` except inside a local region, see :mod:`faultnet._kernels.local`);
the column and row names are the constants below.  All kernels are compiled
without the Numba runtime (``_nrt=False``): they never allocate, and array
arguments then cost no atomic reference counting at call boundaries.

Invariants kept by every kernel:
- ``W[j, P] == W[j, P2] == W[j, D]`` for every block that is not active
  (neighbours read P and P2, the two stage-position buffers);
- ``W[j, V] == W[j, VN] == 0`` for every block that is not active;
- every neighbour of an active block is *touched* (``IW[FLAG, j] != UNTOUCHED``)
  and has its starting force in ``W[j, F0]``;
- the ghost row ``W[2 N]``, which pads the neighbour table ``graph.nbr``, is all zeros.
"""

import numpy as np

from faultnet._kernels.jit import inline_kernel, kernel
from faultnet._kernels.layout import CNT_REGION_IDS

__all__ = [
    "A",
    "AN",
    "D",
    "DN",
    "F0",
    "P",
    "P2",
    "SA",
    "SV",
    "V",
    "VN",
    "VS",
    "N_WORK",
    "FLAG",
    "ACT",
    "TOUCH",
    "APOS",
    "MARK",
    "REGION",
    "SAVE",
    "SLIST",
    "BND",
    "CAND",
    "RES",
    "QUEUE",
    "N_IWORK",
    "UNTOUCHED",
    "ACTIVE",
    "STUCK",
    "FRONTIER",
    "JOINING",
    "STOPPING",
    "accel",
    "new_id",
    "force",
    "force_hot",
    "rk4_step",
    "hermite",
    "hermite_dip",
    "hermite_fall",
    "hermite_root",
    "poly_root",
]

# float work columns of W (SV, SA, VS are the RK4 step's; with DP5 the interpolated crossings
# keep a crossing's fraction of the step in VS, a join's start in SV and SA, a stop's
# deceleration in SA: faultnet._kernels.interp)
# (NumPy integers, not Python ints: Numba types them int64, not as literals, so a kernel
# that takes a column compiles one signature for all of them)
D, P, V, A, DN, VN, AN, SV, SA, VS, P2, F0 = (np.int64(c) for c in range(12))
N_WORK = 12
# int work rows (all but the first four are used by local regions, faultnet._kernels.local;
# MARK also tags, with interpolated crossings, the stuck blocks a step's scan has evaluated:
# fresh tags from layout.CNT_REGION_IDS, which never repeat)
FLAG, ACT, TOUCH, APOS, MARK, REGION, SAVE, SLIST, BND, CAND, RES, QUEUE = range(12)
N_IWORK = 12
# block flags during an event
UNTOUCHED, ACTIVE, STUCK, FRONTIER = 0, 1, 2, 3
# interpolated crossings (faultnet._kernels.interp), within one step: a stuck block that joins
# inside it, a slipping block that stops inside it (while the crossings are located)
JOINING, STOPPING = 4, 5


@kernel
def new_id(cnt):
    """A fresh id (regions, steps, ``IW[MARK]`` tags) from the counter ``cnt[CNT_REGION_IDS]``.

    The counter is never reset, so an id never repeats for the life of the work arrays.
    """
    cnt[CNT_REGION_IDS] += 1
    return cnt[CNT_REGION_IDS]


@kernel
def force(i, pos, W, graph):
    """Force on touched block ``i`` for the displacements in column ``pos`` of W.

    ``graph``: :class:`~faultnet._kernels.bundles.Graph`.  Columns are passed by index, never
    as views: creating a view costs an atomic reference-count update, which dominated the cost
    of a step.  A kernel of its own, not inlined by Numba: typed once instead of at each of its
    call sites (about 1.5 s of a cold compile), and LLVM inlines it where it is called.
    """
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    s = 0.0
    for p in range(indptr[i], indptr[i + 1]):
        s += kval[p] * W[indices[p], pos]
    return W[i, F0] + s - graph.diag[i] * W[i, pos]


@inline_kernel
def force_hot(i, pos, W, graph):
    """:func:`force` for the hot loops: the DP5 stages and the step's join scan.

    Where every spring has the same constant (``graph.k_uniform``) the neighbours' positions
    are summed and multiplied once, without reading ``kval``: 8% more block-steps per second
    on a lattice (bit-identical when k is a power of two).  The sum runs over the padded
    neighbour table ``graph.nbr`` (:func:`~faultnet._kernels.bundles.padded_neighbours`), the
    same number of terms for every block: where degrees vary (the percolation clusters) the
    loop's exit is then predicted, 12-15% more events/s, and the zeros it adds leave the sum
    bit-identical.  Only those two loops take this branch: inlined at every call site of
    :func:`force` it would cost compile time.
    """
    k = graph.k_uniform
    if k > 0.0:
        nbr = graph.nbr
        s = 0.0
        for c in range(nbr.shape[1]):
            s += W[nbr[i, c], pos]
        return W[i, F0] + k * s - graph.diag[i] * W[i, pos]
    return force(np.int64(i), pos, W, graph)  # int64: dopri_step's blocks are unsigned


@kernel
def accel(i, pos, vel, W, graph):
    """Acceleration of slipping block ``i`` (columns ``pos``, ``vel`` of W; ``graph``: Graph).

    phi(v) = (1 - sigma) / (1 + 2 alpha v / (1 - sigma)); RK stages may probe
    small negative v, where the same analytic formula is used with its
    denominator floored at 1/2 (never reached with sane steps).
    """
    den = 1.0 + graph.cfr[i] * W[i, vel]
    if den < 0.5:
        den = 0.5
    return force(i, pos, W, graph) - graph.oms[i] / den


@kernel
def rk4_step(h, nact, graph, work):
    """Classical RK4 step of length ``h`` from (D, V, A) to (DN, VN, AN).

    ``graph``, ``work``: :class:`~faultnet._kernels.bundles.Graph` and ``Work`` (only its
    ``W`` and ``IW`` are used).

    Stage positions ping-pong between the columns P and P2, so each stage is a
    single pass over the active blocks (a block's own stage velocity is only
    read by itself).  Leaves ``P == P2 == DN`` on active blocks; D, V, A are
    untouched so the step can be redone with a shorter ``h``.
    """
    W, IW = work.W, work.IW
    hh = 0.5 * h
    h6 = h / 6.0
    for q in range(nact):
        i = IW[ACT, q]
        W[i, SV] = W[i, V]
        W[i, SA] = W[i, A]
        W[i, P] = W[i, D] + hh * W[i, V]
        W[i, VS] = W[i, V] + hh * W[i, A]
    for q in range(nact):
        i = IW[ACT, q]
        k2 = accel(i, P, VS, W, graph)
        W[i, SV] += 2.0 * W[i, VS]
        W[i, SA] += 2.0 * k2
        W[i, P2] = W[i, D] + hh * W[i, VS]
        W[i, VS] = W[i, V] + hh * k2
    for q in range(nact):
        i = IW[ACT, q]
        k3 = accel(i, P2, VS, W, graph)
        W[i, SV] += 2.0 * W[i, VS]
        W[i, SA] += 2.0 * k3
        W[i, P] = W[i, D] + h * W[i, VS]
        W[i, VS] = W[i, V] + h * k3
    for q in range(nact):
        i = IW[ACT, q]
        k4 = accel(i, P, VS, W, graph)
        W[i, DN] = W[i, D] + h6 * (W[i, SV] + W[i, VS])
        W[i, VN] = W[i, V] + h6 * (W[i, SA] + k4)
        W[i, P2] = W[i, DN]
    for q in range(nact):
        i = IW[ACT, q]
        W[i, P] = W[i, DN]
        W[i, AN] = accel(i, P2, VN, W, graph)


@kernel
def hermite(th, y0, m0, y1, m1):
    """Cubic Hermite interpolant on [0, 1]; m0, m1 are slopes times h."""
    t2 = th * th
    t3 = t2 * th
    return (
        (2.0 * t3 - 3.0 * t2 + 1.0) * y0
        + (t3 - 2.0 * t2 + th) * m0
        + (3.0 * t2 - 2.0 * t3) * y1
        + (t3 - t2) * m1
    )


@inline_kernel
def _hermite_slope(th, y0, m0, y1, m1):
    t2 = th * th
    return (
        (6.0 * t2 - 6.0 * th) * y0
        + (3.0 * t2 - 4.0 * th + 1.0) * m0
        + (6.0 * th - 6.0 * t2) * y1
        + (3.0 * t2 - 2.0 * th) * m1
    )


@kernel
def hermite_root(lo, hi, y0, m0, y1, m1):
    """Root of the Hermite cubic in [lo, hi], where it changes sign.

    Safeguarded Newton: a Newton step that leaves the bracket is replaced by
    bisection.  Converges to round-off in a handful of iterations.
    """
    flo = hermite(lo, y0, m0, y1, m1)
    th = 0.5 * (lo + hi)
    for _ in range(60):
        f = hermite(th, y0, m0, y1, m1)
        if f == 0.0:
            return th
        if (f > 0.0) == (flo > 0.0):
            lo, flo = th, f
        else:
            hi = th
        d = _hermite_slope(th, y0, m0, y1, m1)
        nxt = th - f / d if d != 0.0 else 0.5 * (lo + hi)
        if not (lo < nxt < hi):
            nxt = 0.5 * (lo + hi)
        if abs(nxt - th) <= 1e-15:
            return nxt
        th = nxt
    return th


@kernel
def poly_root(lo, hi, c0, c1, c2, c3, c4):
    """Root in [lo, hi] of c0 + c1 t + ... + c4 t^4, which changes sign there.

    Safeguarded Newton as in :func:`hermite_root`; used with the DP5 dense output.
    """
    flo = c0 + lo * (c1 + lo * (c2 + lo * (c3 + lo * c4)))
    th = 0.5 * (lo + hi)
    for _ in range(60):
        f = c0 + th * (c1 + th * (c2 + th * (c3 + th * c4)))
        if f == 0.0:
            return th
        if (f > 0.0) == (flo > 0.0):
            lo, flo = th, f
        else:
            hi = th
        d = c1 + th * (2.0 * c2 + th * (3.0 * c3 + th * 4.0 * c4))
        nxt = th - f / d if d != 0.0 else 0.5 * (lo + hi)
        if not (lo < nxt < hi):
            nxt = 0.5 * (lo + hi)
        if abs(nxt - th) <= 1e-15:
            return nxt
        th = nxt
    return th


@inline_kernel
def _first_critical(y0, m0, y1, m1):
    """Smallest root in (0, 1) of the Hermite cubic's slope, or 2.0."""
    c2 = 6.0 * y0 + 3.0 * m0 - 6.0 * y1 + 3.0 * m1
    c1 = -6.0 * y0 - 4.0 * m0 + 6.0 * y1 - 2.0 * m1
    c0 = m0
    best = 2.0
    if c2 == 0.0:
        if c1 != 0.0:
            best = -c0 / c1
    else:
        disc = c1 * c1 - 4.0 * c2 * c0
        if disc >= 0.0:
            r = disc**0.5
            r1 = (-c1 - r) / (2.0 * c2)
            r2 = (-c1 + r) / (2.0 * c2)
            lo, hi = min(r1, r2), max(r1, r2)
            best = lo if lo > 0.0 else hi
    if not (0.0 < best < 1.0):
        return 2.0
    return best


@kernel
def hermite_fall(m0, y1, m1):
    """Root in (0, 1] of a velocity that starts at 0 rising (m0 > 0) and ends <= 0.

    Returns 0.0 when the cubic never rises above 0 (stop at once).
    """
    if m0 <= 0.0:
        return 0.0
    peak = _first_critical(0.0, m0, y1, m1)
    if peak > 1.0 or hermite(peak, 0.0, m0, y1, m1) <= 0.0:
        return 0.0
    return hermite_root(peak, 1.0, 0.0, m0, y1, m1)


@kernel
def hermite_dip(y0, m0, y1, m1):
    """First root in (0, 1] of a Hermite cubic with y0 > 0, y1 > 0, or 2.0.

    Used for a velocity that dips below zero inside a step although both
    ends are positive (the block should have stuck inside the step).
    """
    best = _first_critical(y0, m0, y1, m1)
    if best > 1.0:
        return 2.0
    if hermite(best, y0, m0, y1, m1) > 0.0:
        return 2.0
    return hermite_root(0.0, best, y0, m0, y1, m1)
