"""Joins that a step's crossings reveal: blocks they push over the threshold inside the step.

After :func:`.interp.interpolated_crossings` has applied a step's listed
stops and joins, the blocks they moved (a stopping or joining block b, and b's slipping
neighbours, whose ends were corrected) may have pushed a stuck neighbour's force to 1 at the
end of the step: such a block is a neighbour of b or of one of b's slipping neighbours
(:func:`late_joins`, before the commit, on the end positions in ``P2``).  Its force passed 1
inside the step, where the step's scan, which saw no crossing, did not list it.  The step is
then taken again from its start, with these blocks listed after the scan's crossings
(``loc[LOC_LATE:]``, :func:`_reveal`): as any join that its neighbours' crossings push, each
starts where its force on their paths reaches 1 (:func:`.interp._chained`), and the
crossings of the step answer it.  The step is taken again only when a new block is revealed,
so a cascade ends.  On the ring of 2000, the periodic 64^2 lattice and the 150^2 percolation
cluster (alpha 0.9), 0.4-2% of the events have such a join; the steps taken again are 0.4%
of the lattice's block-steps.  Where the list is full (``LATE_CAP`` blocks, or the crossing
list's cached fractions), a revealed block starts from rest at the end of the step.

A block that stopped in the step and is over the threshold at its end slips again: the
step is taken again at half its length (:func:`.interp.interpolated_crossings`) until the
stop and the new start fall in different steps, where the new start is a listed join; at
the shortest step (1/16 of dt) it starts from rest at the end of the step
(:func:`rejoin`).  About 20 in 100,000 events on the three graphs above have one; starting
it from rest at the end of a full step put such an event on the ring 2e-3 off at step
coefficient 0.5.

Arguments: ``h`` the step's length, ``b``, ``j``, ``n`` blocks, ``nact``, ``ntouch``,
``ncand`` the lengths of the active, touched and crossing lists, ``joining`` whether j is next
to a joining block, ``w`` the plate position and ``keys`` the failure keys (for the blocks a
join touches), ``graph`` and ``work`` the ``Graph`` and ``Work`` bundles
(:mod:`~faultnet.solver._kernels.bundles`).
"""

import numpy as np

from faultnet.solver._kernels.carlson_langer.physics import accel, force
from faultnet.solver._kernels.carlson_langer.stepping import activate, touch
from faultnet.solver._kernels.carlson_langer.work import (
    ACTIVE,
    AN,
    CAND,
    FLAG,
    FRONTIER,
    JOINING,
    LATE_CAP,
    LOC_LATE,
    LOC_MOVED,
    LOC_NCAND,
    LOC_NLATE,
    LOC_REVEALED,
    P2,
    SA,
    STUCK,
    SV,
    THETA_CACHE,
    UNTOUCHED,
    VS,
    A,
    D,
    P,
    V,
)
from faultnet.solver._kernels.jit import forced_kernel, inline_kernel, kernel

__all__ = ["late_joins", "refresh", "rejoin", "take_again"]


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
    """Stuck block j, pushed over the threshold by the step's crossings: listed for the step's
    next take (``loc[LOC_LATE:]``, ``loc[LOC_REVEALED]`` set), and meanwhile appended to the
    crossings as a join at rest at the end of the step, which it stays if that list is full.
    Returns ncand.
    """
    W, IW, loc = work.W, work.IW, work.loc
    IW[FLAG, j] = JOINING
    W[j, VS] = 1.0
    W[j, SV] = 0.0
    W[j, SA] = 0.0
    IW[CAND, ncand] = j
    n = np.int64(loc[LOC_NLATE])
    if n < LATE_CAP and loc[LOC_NCAND] + n < THETA_CACHE:
        loc[LOC_LATE + n] = j
        loc[LOC_NLATE] = n + 1.0
        loc[LOC_REVEALED] = 1.0
    return ncand + 1


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
        reach = (graph.diag[j] - 1.0) * work.loc[LOC_MOVED]
        if W[j, AN] + reach * (1.0 + 1e-9) + 1e-12 < 1.0:
            return ncand, ntouch
    if fl == STUCK or fl == FRONTIER:
        if force(j, P2, W, graph) >= 1.0:
            ncand = _reveal(j, ncand, work)
    return ncand, ntouch


@inline_kernel
def late_joins(ncand, ntouch, w, keys, graph, work):
    """Joins revealed by the step's crossings, before the commit; returns (ncand, ntouch).

    After the listed stops and joins are applied (``IW[CAND, :ncand]``), only they and their
    slipping neighbours have moved from where the step's scan saw them, so a stuck block
    whose force at the end of the step (``P2``) now reaches 1 is a neighbour of a crossing
    block or of one of its slipping neighbours.  Each such block is revealed (appended to the
    list, and its own neighbours scanned in turn).  The list holds at most one entry per
    block.
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
            ncand, ntouch = _check(n, e >= 0, ncand, ntouch, w, keys, graph, work)
            if IW[FLAG, n] == ACTIVE:
                for r in range(indptr[n], indptr[n + 1]):
                    if indices[r] != b:
                        ncand, ntouch = _check(
                            indices[r], np.bool_(False), ncand, ntouch, w, keys, graph, work
                        )
    return ncand, ntouch
