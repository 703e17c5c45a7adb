"""Free single-block slips: an event whose hypocentre slips alone, computed once and reused.

A block that starts from rest at the threshold while every neighbour is held follows a path
that depends only on its own stiffness, sigma and alpha.  The event loop
(:mod:`.events`) integrates it once per such parameter class
(:func:`solo_start`, :func:`solo_end`), then takes every later event of the class from the
cache when :func:`solo_free` shows that no neighbour reaches the threshold during it
(:func:`solo_apply`).

Arguments: ``i``, ``hyp`` the block slipping alone, ``s1`` its cached solo slip, ``ev`` the
event's number, ``w`` the plate position, ``keys`` the failure keys, ``saved`` the counters
:func:`solo_start` returned, ``cnt`` the counters (``layout.CNT_*``), and the bundles ``state``,
``graph``, ``work`` and ``records`` of :mod:`faultnet.solver._kernels.bundles`.
"""

from faultnet.solver._kernels.bundles import kelvin
from faultnet.solver._kernels.carlson_langer.physics import accel, block_key, load
from faultnet.solver._kernels.carlson_langer.tree import tree_update
from faultnet.solver._kernels.carlson_langer.work import (
    ACT,
    ACTIVE,
    APOS,
    F0,
    FLAG,
    P2,
    TOUCH,
    UNTOUCHED,
    VN,
    A,
    D,
    P,
    V,
)
from faultnet.solver._kernels.jit import forced_kernel, inline_kernel, kernel
from faultnet.solver._kernels.layout import (
    CNT_BLOCK_STEPS,
    CNT_INTERPOLATED_CROSSINGS,
    CNT_PARTIAL_BLOCK_STEPS,
    CNT_RELOCATIONS,
    CNT_SLIP_ROWS,
    CNT_SOLO_EVENTS,
    SCAL_OFFSET,
)

__all__ = ["SOLO_MARGIN", "solo_apply", "solo_end", "solo_free", "solo_start"]

#: a neighbour's force must stay this far below 1 for a free single-block slip
SOLO_MARGIN = 1e-12


#: the starting force that keeps a neighbour out of a solo slip
_HELD = -1e300


@inline_kernel
def solo_start(i, graph, work):
    """Set block i up to slip alone: from rest at the threshold, every neighbour held.

    The event loop then integrates it with the run's own integration
    (:mod:`.slip`); the neighbours' starting forces are set to -1e300 so that
    none can join (starting forces are written afresh whenever a block is touched).  Such a
    slip depends only on the block's own parameters (stiffness, sigma, alpha), so it is
    computed once per parameter class and reused.  Returns the work counters to restore
    afterwards (:func:`solo_end`): a cached solo slip is set-up, not part of any event, so a
    run's counters do not depend on how it was cut into calls.
    """
    W, IW, cnt = work.W, work.IW, work.cnt
    for p in range(graph.indptr[i], graph.indptr[i + 1]):
        W[graph.indices[p], F0] = _HELD
    W[i, F0] = 1.0
    IW[ACT, 0] = i
    IW[APOS, i] = 0
    IW[FLAG, i] = ACTIVE
    IW[TOUCH, 0] = i
    W[i, V] = 0.0
    W[i, VN] = 0.0
    W[i, A] = accel(i, P, V, W, graph)
    return (
        cnt[CNT_BLOCK_STEPS],
        cnt[CNT_PARTIAL_BLOCK_STEPS],
        cnt[CNT_RELOCATIONS],
        cnt[CNT_INTERPOLATED_CROSSINGS],
    )


@forced_kernel
def solo_end(i, saved, work):
    """The solo slip of block i; restores the counters and leaves the work arrays as found."""
    W, IW, cnt = work.W, work.IW, work.cnt
    (
        cnt[CNT_BLOCK_STEPS],
        cnt[CNT_PARTIAL_BLOCK_STEPS],
        cnt[CNT_RELOCATIONS],
        cnt[CNT_INTERPOLATED_CROSSINGS],
    ) = saved
    s = W[i, D]
    W[i, D] = 0.0
    W[i, P] = 0.0
    W[i, P2] = 0.0
    W[i, V] = 0.0
    W[i, VN] = 0.0
    IW[FLAG, i] = UNTOUCHED
    return s


@kernel
def solo_free(hyp, s1, speed, w, keys, graph):
    """True when slipping s1 alone leaves every neighbour of hyp below threshold.

    The slip is monotone, so a neighbour's spring force is largest at the end: its load
    (:func:`~.physics.load`) plus ``k_ij s1``.  A dashpot adds at most ``eta_ij speed``, the
    bound on the slip's velocity (``layout.SOLO_SPEED``).
    """
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    for p in range(indptr[hyp], indptr[hyp + 1]):
        f = load(indices[p], w, keys) + kval[p] * s1
        if kelvin(graph):
            f += graph.eta[p] * speed
        if f >= 1.0 - SOLO_MARGIN:
            return False
    return True


@kernel
def solo_apply(hyp, s1, ev, state, graph, cnt, records):
    """Commit a free single-block slip: move the block, refresh its and its neighbours' keys."""
    z, keys, tree = state.z, state.keys, state.tree
    off = state.scal[SCAL_OFFSET]
    z[hyp] += s1
    keys[hyp] = block_key(hyp, z, off, graph)
    tree_update(hyp, keys, tree)
    for p in range(graph.indptr[hyp], graph.indptr[hyp + 1]):
        j = graph.indices[p]
        keys[j] = block_key(j, z, off, graph)
        tree_update(j, keys, tree)
    if len(records.slip_val) > 0:
        row = cnt[CNT_SLIP_ROWS]
        records.slip_event[row] = ev
        records.slip_node[row] = hyp
        records.slip_val[row] = s1
        cnt[CNT_SLIP_ROWS] = row + 1
    cnt[CNT_SOLO_EVENTS] += 1
