"""Joins that a step's crossings reveal: blocks they push over the threshold inside the step.

After :func:`.interp.interpolated_crossings` has applied a step's listed
stops and joins, the blocks they moved (a stopping or joining block b, and b's slipping
neighbours, whose ends were corrected) may have pushed a stuck neighbour's force to 1 at the
end of the step: such a block is a neighbour of b or of one of b's slipping neighbours
(:func:`late_joins`, before the commit, on the end positions in ``P2``).  Its force passed 1
inside the step, where the step's scan, which saw no crossing, did not list it.  Such blocks
are appended to the step's crossings (:func:`_reveal`) and placed after them, in rounds: as
any join that its neighbours' crossings push, each starts where its force on their paths
reaches 1 (:func:`.interp._chained`), and its path is answered by its slipping and joining
neighbours and answers its stopping ones (:func:`late_join`); its own neighbours are scanned
in the next round.  On the ring of 2000, the periodic 64^2 lattice and the 150^2
percolation cluster (alpha 0.9), 0.4-1.7% of the events have such a join.  (Taking the step
again with them listed among its crossings gave the same errors, and 6.5% more block-steps
on the 150^2 lattice at rtol 2e-5.)

A block that stopped in the step and is over the threshold at its end slips again: the
step is taken again at half its length (:func:`.interp.interpolated_crossings`) until the
stop and the new start fall in different steps, where the new start is a listed join; at
the shortest step (1/16 of dt) it starts from rest at the end of the step
(:func:`rejoin`).  On the three graphs above, 8-19 in 100,000 events have one; starting
it from rest at the end of a full step put such an event on the ring 2e-3 off at step
coefficient 0.5.

Arguments: ``h`` the step's length, ``b``, ``j``, ``n`` blocks, ``nact``, ``ntouch``,
``ncand`` the lengths of the active, touched and crossing lists, ``joining`` whether j is next
to a joining block, ``w`` the plate position and ``keys`` the failure keys (for the blocks a
join touches), ``graph`` and ``work`` the ``Graph`` and ``Work`` bundles
(:mod:`~faultnet.solver._kernels.bundles`).
"""

import numpy as np

from faultnet.solver._kernels.bundles import DIAG
from faultnet.solver._kernels.carlson_langer.physics import accel, force
from faultnet.solver._kernels.carlson_langer.response import place_join, stop_answer
from faultnet.solver._kernels.carlson_langer.stepping import activate, touch
from faultnet.solver._kernels.carlson_langer.tableau import path_dense
from faultnet.solver._kernels.carlson_langer.work import (
    ACTIVE,
    AN,
    CAND,
    FLAG,
    FRONTIER,
    JOINING,
    LOC_MOVED,
    P2,
    SA,
    STOPPING,
    STUCK,
    SV,
    UNTOUCHED,
    VS,
    A,
    D,
    P,
    V,
)
from faultnet.solver._kernels.jit import forced_kernel, inline_kernel, kernel
from faultnet.solver._kernels.layout import CNT_REVEALED_JOINS

__all__ = ["late_join", "late_joins", "refresh", "rejoin", "take_again"]


@kernel
def refresh(b, graph, work):
    """Accelerations of b's slipping neighbours (b has moved)."""
    W, IW = work.W, work.IW
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        n = graph.indices[p]
        if IW[FLAG, n] == ACTIVE:
            W[n, A] = accel(n, P, V, W, graph)


@inline_kernel
def rejoin(b, nact, ntouch, w, keys, graph, work):
    """Block b stopped in the step, the shortest one; if its force at the step's end is >= 1
    it slips again, from rest.  Returns (nact, ntouch).
    """
    if work.IW[FLAG, b] == STUCK and force(b, D, work.W, graph) >= 1.0:
        return activate(b, nact, ntouch, w, keys, graph, work)
    return nact, ntouch


@kernel
def _reveal(j, ncand, work):
    """Stuck block j, pushed over the threshold by the step's crossings, is appended to them
    as a join at the end of the step (``W[j, VS] = 1``, at rest) until :func:`late_join`
    places it.  Returns ncand.
    """
    W, IW = work.W, work.IW
    work.cnt[CNT_REVEALED_JOINS] += 1
    IW[FLAG, j] = JOINING
    W[j, VS] = 1.0
    W[j, SV] = 0.0
    W[j, SA] = 0.0
    IW[CAND, ncand] = j
    return ncand + 1


@inline_kernel
def late_join(j, h, graph, work):
    """Revealed join j at its fraction ``W[j, VS]`` of the step (:func:`.interp._chained`):
    its path, its slipping and earlier-joining neighbours' answer to it
    (:func:`~.response.place_join`), and its own answer to its stopping neighbours.
    """
    W, IW = work.W, work.IW
    place_join(j, W[j, VS], h, graph, work)
    for p in range(graph.indptr[j], graph.indptr[j + 1]):
        b = graph.indices[p]
        if IW[FLAG, b] == STOPPING:
            c0, c1, c2, c3, c4 = path_dense(b, h, work)
            stop_answer(j, graph.kval[p], W[b, SV], W[b, VS], h, c0, c1, c2, c3, c4, graph, work)


@kernel
def take_again(ncand, work):
    """Undo the step's crossings (``IW[CAND, :ncand]``) before the step is taken again.

    The stopping blocks slip again and the joining ones are stuck (``STUCK`` if they slipped
    earlier in the event, else ``FRONTIER``) at their committed positions; the step itself
    rewrites every slipping block's stage and end values.
    """
    W, IW = work.W, work.IW
    for c in range(ncand):
        e = IW[CAND, c]
        if e <= -2:
            IW[FLAG, -2 - e] = ACTIVE
        elif e >= 0:
            IW[FLAG, e] = STUCK if W[e, D] != 0.0 else FRONTIER
            W[e, P2] = W[e, D]


@forced_kernel
def _check(j, joining, ncand, ntouch, w, keys, graph, work):
    """Stuck block j is revealed (:func:`_reveal`) if its force at the step's end (``P2``) is >= 1.

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
        reach = (graph.block[j, DIAG] - 1.0) * work.loc[LOC_MOVED]
        if W[j, AN] + reach * (1.0 + 1e-9) + 1e-12 < 1.0:
            return ncand, ntouch
    if fl == STUCK or fl == FRONTIER:
        if force(j, P2, W, graph) >= 1.0:
            ncand = _reveal(j, ncand, work)
    return ncand, ntouch


@inline_kernel
def late_joins(start, ncand, ntouch, w, keys, graph, work):
    """Joins revealed by the crossings ``IW[CAND, start:ncand]``, before the commit.

    After those stops and joins are applied, only they and their slipping neighbours have
    moved from where the step's scan (or the round before) saw them, so a stuck block whose
    force at the end of the step (``P2``) now reaches 1 is a neighbour of a crossing block or
    of one of its slipping neighbours.  Each is appended to the list (:func:`_reveal`); its
    own neighbours are scanned in the next round, once it is placed.  The list holds at most
    one entry per block.  Returns (the list's new length, ntouch).
    """
    IW = work.IW
    indptr, indices = graph.indptr, graph.indices
    n = ncand
    for c in range(start, ncand):
        e = IW[CAND, c]
        b = -2 - e if e <= -2 else e
        for p in range(indptr[b], indptr[b + 1]):
            m = indices[p]
            n, ntouch = _check(m, e >= 0, n, ntouch, w, keys, graph, work)
            if IW[FLAG, m] == ACTIVE:
                for r in range(indptr[m], indptr[m + 1]):
                    if indices[r] != b:
                        n, ntouch = _check(
                            indices[r], np.bool_(False), n, ntouch, w, keys, graph, work
                        )
    return n, ntouch
