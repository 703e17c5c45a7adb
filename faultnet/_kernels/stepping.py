"""Inside an event: the active list, steps, and reaching a crossing.

Kernels shared by the event loop (:mod:`faultnet._kernels.events`) and the
local regions (:mod:`faultnet._kernels.local`).  Every kernel works on the
active blocks ``IW[ACT, q0:nact]``: ``q0 = 0`` for the whole event, ``q0 > 0``
for a local region, whose list lives above the event's (see ``local.py``).

``graph`` and ``work`` are the bundles :class:`~faultnet._kernels.bundles.Graph` (topology
and per-block parameters) and :class:`~faultnet._kernels.bundles.Work` (``W``, ``IW``,
``loc``, ``cnt``); ``w`` is the plate position and ``keys`` the failure keys.
"""

import numba as nb
import numpy as np
from numba.core import types
from numba.extending import overload

from faultnet._kernels.context import LOC_BND_END, LOC_BND_START, LOC_OUTER_H, LOC_REGION_T
from faultnet._kernels.crossing import (
    JOIN,
    LANDED,
    STATUS_OK,
    STICK,
    earliest_crossing,
)
from faultnet._kernels.dopri import boundary_at, dopri_step
from faultnet._kernels.integrate import (
    ACT,
    ACTIVE,
    AN,
    APOS,
    DN,
    F0,
    FLAG,
    FRONTIER,
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
    force,
    rk4_step,
)
from faultnet._kernels.jit import INNER, inline_kernel, kernel
from faultnet._kernels.landing import land
from faultnet._kernels.layout import (
    CNT_BLOCK_STEPS,
    CNT_LANDED_JOINS,
    CNT_PARTIAL_BLOCK_STEPS,
    CNT_RELOCATIONS,
)
from faultnet._kernels.tableau import stage_rows

__all__ = [
    "activate",
    "apply_crossing",
    "commit",
    "deactivate",
    "join_scan",
    "restore_positions",
    "step",
    "step_scan",
    "stick_scan",
    "to_crossing",
    "touch",
]


@kernel
def touch(j, w, keys, W, IW, ntouch):
    """Mark block j touched and store its force at the start of the event.

    The force is ``1 + (w - key)``: exactly 1 at the hypocentre, whose key is ``w``, so that
    its slip equals the cached free single-block slip bit for bit (:mod:`faultnet._kernels.
    solo`); ``(1 + w) - key`` rounds to 1 +- 2.2e-16 for some keys.
    """
    IW[FLAG, j] = FRONTIER
    W[j, F0] = 1.0 + (w - keys[j])
    IW[TOUCH, ntouch] = j
    return ntouch + 1


@kernel
def activate(j, nact, ntouch, w, keys, graph, work):
    """Block j starts to slip from rest; its neighbours become touched."""
    W, IW, indptr = work.W, work.IW, graph.indptr
    IW[FLAG, j] = ACTIVE
    IW[ACT, nact] = j
    IW[APOS, j] = nact
    W[j, V] = 0.0
    W[j, VN] = 0.0
    for p in range(indptr[j], indptr[j + 1]):
        nb_ = graph.indices[p]
        if IW[FLAG, nb_] == UNTOUCHED:
            ntouch = touch(nb_, w, keys, W, IW, ntouch)
    W[j, A] = accel(j, P, V, W, graph)
    return nact + 1, ntouch


@kernel
def deactivate(i, nact, W, IW):
    """Block i sticks (v = 0); swap-remove it from the active list."""
    q = IW[APOS, i]
    last = IW[ACT, nact - 1]
    IW[ACT, q] = last
    IW[APOS, last] = q
    IW[FLAG, i] = STUCK
    W[i, V] = 0.0
    W[i, VN] = 0.0
    return nact - 1


@kernel
def join_scan(q0, nact, ntouch, w, keys, graph, work):
    """Activate every stuck neighbour of a slipping block whose force is >= 1."""
    W, IW, indptr, indices = work.W, work.IW, graph.indptr, graph.indices
    q = q0
    while q < nact:
        i = IW[ACT, q]
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if IW[FLAG, j] != ACTIVE:
                if force(j, D, W, graph) >= 1.0:
                    nact, ntouch = activate(j, nact, ntouch, w, keys, graph, work)
        q += 1
    return nact, ntouch


@kernel
def stick_scan(q0, nact, W, IW):
    """Deactivate every slipping block that has stopped (v <= 0, a <= 0).

    A block that has just joined has v = 0 but a > 0 and keeps slipping.
    """
    for q in range(nact - 1, q0 - 1, -1):
        i = IW[ACT, q]
        if W[i, V] <= 0.0 and W[i, A] <= 0.0:
            nact = deactivate(i, nact, W, IW)
    return nact


def step(method, h, q0, nact, graph, work):
    """A step without locating crossings (polish re-steps, solo slips).

    Chosen while typing (``method`` must be a literal: 0 RK4, 1 DP5), so a
    run compiles only its own scheme's code.
    """
    raise NotImplementedError("a kernel: called from compiled code only")


def step_scan(method, h, q0, nact, vmax, scan, graph, work):
    """A step and the earliest crossing inside it: (theta, block, kind, status).

    Chosen while typing, like :func:`step`.  ``scan``: 1, or 2 to list every
    crossing for the local regions as well (DP5, see
    :func:`faultnet._kernels.dopri.dopri_step`).
    """
    raise NotImplementedError("a kernel: called from compiled code only")


def _literal_method(method):
    """0 (RK4) or 1 (DP5) from a literal integer type; else a typing error."""
    if not isinstance(method, types.IntegerLiteral) or method.literal_value not in (0, 1):
        raise nb.errors.TypingError(f"method must be the literal 0 or 1, got {method}")
    return method.literal_value


@overload(step, prefer_literal=True, inline="always", jit_options=INNER)
def _step(method, h, q0, nact, graph, work):
    if _literal_method(method) == 0:

        def rk4(method, h, q0, nact, graph, work):
            rk4_step(h, nact, graph, work)

        return rk4

    def dp5(method, h, q0, nact, graph, work):
        dopri_step(h, q0, nact, np.int64(0), 0.0, graph, work)

    return dp5


@overload(step_scan, prefer_literal=True, inline="always", jit_options=INNER)
def _step_scan(method, h, q0, nact, vmax, scan, graph, work):
    if _literal_method(method) == 0:

        def rk4(method, h, q0, nact, vmax, scan, graph, work):
            rk4_step(h, nact, graph, work)
            # the literal method prunes the dense-output branch of the scan
            return earliest_crossing(0, h, nact, vmax, graph, work)

        return rk4

    def dp5(method, h, q0, nact, vmax, scan, graph, work):
        return dopri_step(h, q0, nact, scan, vmax, graph, work)

    return dp5


@kernel
def _residual(who, kind, W, graph):
    """Crossing function and its time derivative at the end of the last step."""
    if kind == STICK:
        return W[who, VN], W[who, AN]
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    dg = 0.0
    for r in range(indptr[who], indptr[who + 1]):
        dg += kval[r] * W[indices[r], VN]
    return force(who, P, W, graph) - 1.0, dg


@kernel
def _taylor_shift(dh, q0, nact, graph, work):
    """Move the end of the step by a tiny ``dh``: x += v dh + a dh^2 / 2, v += a dh.

    Used only for |dh| <= ``_TAYLOR_MAX`` times the step, where the neglected
    third-order term is below round-off; costs one force pass instead of a step.
    """
    W, IW = work.W, work.IW
    half = 0.5 * dh * dh
    for q in range(q0, nact):
        i = IW[ACT, q]
        x = W[i, DN] + dh * W[i, VN] + half * W[i, AN]
        W[i, DN] = x
        W[i, P] = x
        W[i, P2] = x
        W[i, VN] += dh * W[i, AN]
    for q in range(q0, nact):
        i = IW[ACT, q]
        W[i, AN] = accel(i, P, VN, W, graph)


#: largest Newton correction, as a fraction of the step, done by a Taylor shift
_TAYLOR_MAX = 1e-4


@kernel
def _polish(h, hmax, who, kind, method, q0, nact, graph, work):
    """Newton on the true crossing residual at the end of a step of length h.

    A small correction shifts the end by a Taylor step; a large one (a poor
    first estimate) redoes the step from the committed state.  The crossing
    ends located to round-off whatever the order of the scheme.  Returns the
    step length and the number of full step evaluations it took.
    """
    W, IW, loc = work.W, work.IW, work.loc
    K = stage_rows(work)
    n = 0
    for _ in range(6):
        g, dg = _residual(who, kind, W, graph)
        if dg == 0.0:
            break
        dh = -g / dg
        hn = h + dh
        if not (0.0 < hn <= hmax) or abs(dh) <= 1e-13 * hmax:
            break
        if abs(dh) <= _TAYLOR_MAX * hmax:
            if loc[LOC_BND_END] > loc[LOC_BND_START]:
                th = loc[LOC_REGION_T] + hn / loc[LOC_OUTER_H]
                boundary_at(th, W, K, IW, loc)
            _taylor_shift(dh, q0, nact, graph, work)
        else:
            step(method, hn, q0, nact, graph, work)
            n += 1
        h = hn
    return h, n


@kernel
def commit(q0, nact, W, IW):
    for q in range(q0, nact):
        i = IW[ACT, q]
        W[i, D] = W[i, DN]
        W[i, V] = W[i, VN]
        W[i, A] = W[i, AN]


@kernel
def restore_positions(q0, nact, W, IW):
    for q in range(q0, nact):
        i = IW[ACT, q]
        W[i, P] = W[i, D]
        W[i, P2] = W[i, D]


@inline_kernel
def to_crossing(th, who, kind, h, method, q0, qb, nact, vmax, graph, work):
    """Reach the crossing found at fraction ``th`` of a step of length ``h``; commit there.

    A join (DP5) is landed on the step's interpolant
    (:func:`faultnet._kernels.landing.land`; a local region's boundary blocks,
    ``IW[APOS] < qb``, move on the outer step's dense output, ``qb = 0``: every
    block is at the step's ends).  Otherwise, or when that landing
    is not clean: a partial step to the crossing; if another crossing is found
    earlier inside it, go to that one instead; then Newton-polish the crossing
    to round-off and commit.  ``th == 0`` (a crossing at the start) discards
    the step.  Returns (time advanced, block, kind, steps taken, status); kind
    ``LANDED`` for a landed join.  Counts its work in ``work.cnt``.
    """
    W, IW, cnt = work.W, work.IW, work.cnt
    n = 0
    one = n + 1  # int64, not a literal: one typing of the scan
    if th <= 0.0:
        restore_positions(q0, nact, W, IW)
        return 0.0, who, kind, n, STATUS_OK
    if method == 1 and kind == JOIN:
        # a join (DP5): land on the step's interpolant (landing.py)
        hl = land(th, who, h, q0, qb, nact, graph, work)
        if hl >= 0.0:
            cnt[CNT_LANDED_JOINS] += 1
            return hl, who, kind - kind + LANDED, n, STATUS_OK
    hmax = h
    m = nact - q0
    for _ in range(64):
        h = th * h
        th2, who2, kind2, status = step_scan(method, h, q0, nact, vmax, one, graph, work)
        n += 1
        cnt[CNT_BLOCK_STEPS] += m
        cnt[CNT_PARTIAL_BLOCK_STEPS] += m
        if status != STATUS_OK:
            return h, who2, kind2, n, status
        if who2 < 0 or who2 == who or th2 >= 1.0 - 1e-9 or th2 <= 0.0:
            break
        th, who, kind = th2, who2, kind2
        cnt[CNT_RELOCATIONS] += 1
    h, npart = _polish(h, hmax, who, kind, method, q0, nact, graph, work)
    n += npart
    cnt[CNT_BLOCK_STEPS] += npart * m
    cnt[CNT_PARTIAL_BLOCK_STEPS] += npart * m
    commit(q0, nact, W, IW)
    return h, who, kind, n, STATUS_OK


@inline_kernel
def apply_crossing(who, kind, q0, nact, ntouch, w, keys, graph, work):
    """After committing at a crossing: joins (``who`` and any other block at threshold), then stops.

    After a landed join (kind ``LANDED``) no other block is at the threshold
    (:func:`faultnet._kernels.landing.land` checked every stuck neighbour
    there), so the scan for joins is skipped.  Returns (nact, ntouch).
    """
    W, IW = work.W, work.IW
    if kind != STICK and IW[FLAG, who] != ACTIVE:
        nact, ntouch = activate(who, nact, ntouch, w, keys, graph, work)
    if kind != LANDED:
        # joins first: the neighbours of a block that sticks now are scanned too
        nact, ntouch = join_scan(q0, nact, ntouch, w, keys, graph, work)
    if kind == STICK and IW[FLAG, who] == ACTIVE:
        nact = deactivate(who, nact, W, IW)
    nact = stick_scan(q0, nact, W, IW)
    return nact, ntouch
