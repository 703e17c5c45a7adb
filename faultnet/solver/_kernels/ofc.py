"""The Olami-Feder-Christensen automaton: drive to the next toppling, run its avalanche.

The state is the blocks' *keys* (:data:`~faultnet.solver._kernels.bundles.OFCState`): the drive
``w`` (relative to the frame offset) at which each block's force reaches the threshold 1, so
that the force on block i at drive ``w`` is ``F_i = 1 + (w - key_i)`` and a uniform drive
changes no key.  The next drive is the smallest key, the root of a tournament tree (O(1));
blocks at the threshold are found below it (:func:`at_threshold`).

The tree is two-level: its leaves are chunks of ``2**OFC_CHUNK_SHIFT`` consecutive blocks,
each with its smallest key and the block holding it (``tv``, ``ti``).  A key that falls (a
neighbour's gain) is compared with its chunk's leaf alone, an array small enough to stay in
the fastest cache; a chunk whose smallest key rose (the block holding it toppled) is marked
(``ti`` -2) and scanned again after the avalanche (:func:`scan_chunk`); then each changed
chunk walks its path up, stopping where nothing changes (:func:`chunk_update`).  On the 256^2
lattice this ran 1.5-2 times the avalanches/s of a tree with one leaf per block (where every
touched block walked its own path, cache misses each).

An avalanche (:func:`avalanche`) runs in generations.  The first holds every block at the
threshold, each with the force 1 exactly; its lowest index is the hypocentre.  In a
generation every block of ``cur`` slips by ``dx_i = F_i / K_i`` to the force 0 (its key
becomes ``1 + w``), and then gives ``k_ij dx_i`` to each neighbour (the rest goes to its frame
and plate springs); a neighbour whose force reaches 1 joins the next generation, once, with
the force it has at the end of this one.  The drive ``w`` grows without bound; past
:data:`OFC_RECENTRE_AT` the frame moves by its whole part (the keys and ``w`` lose it exactly:
they stay within a unit of each other).

Arguments: ``e`` (the avalanche's row in the catalog), ``w`` (the drive), ``c`` (a chunk),
``v``, ``b`` (its smallest key and the block holding it), ``keys``, ``tv``, ``ti``, ``cur``
(the blocks found), ``stack`` (work space for the search), and the bundles of
:mod:`~faultnet.solver._kernels.bundles`: ``state`` (:data:`OFCState`), ``graph``
(:data:`OFCGraph`), ``work`` (:data:`OFCWork`) and ``records`` (:data:`OFCRecords`); ``ctrl``
(float64[OFC_CTRL_SIZE]: ``layout.OFC_CTRL_*``) and of the entry ``n_req`` (the avalanches
requested).
"""

import math

from faultnet.solver._kernels.jit import entry, forced_kernel, kernel
from faultnet.solver._kernels.layout import (
    OFC_CAT_BLOCKS,
    OFC_CAT_FAULTS,
    OFC_CAT_GENERATIONS,
    OFC_CAT_HYPOCENTER,
    OFC_CAT_S,
    OFC_CAT_T,
    OFC_CAT_TOPPLINGS,
    OFC_CHUNK_SHIFT,
    OFC_CNT_EVENTS,
    OFC_CNT_GENERATIONS,
    OFC_CNT_STAMP,
    OFC_CNT_TOPPLINGS,
    OFC_CTRL_MAX_TOPPLINGS,
    OFC_CTRL_REBUILD,
    SCAL_OFFSET,
    SCAL_W,
)

__all__ = [
    "OFC_RECENTRE_AT",
    "OFC_STATUS_OK",
    "OFC_STATUS_TOO_MANY_TOPPLINGS",
    "at_threshold",
    "avalanche",
    "build_tree",
    "chunk_update",
    "run_ofc",
    "scan_chunk",
]

#: every avalanche ran
OFC_STATUS_OK = 0
#: an avalanche took more topplings than ``ctrl[OFC_CTRL_MAX_TOPPLINGS]`` (its row holds its
#: hypocentre and the topplings so far; the state is left mid-avalanche)
OFC_STATUS_TOO_MANY_TOPPLINGS = 1
#: the drive ``w`` is moved back by its whole part once it exceeds this
OFC_RECENTRE_AT = 4.0
#: blocks per chunk, a leaf of the tree
CHUNK = 1 << OFC_CHUNK_SHIFT
#: the smallest key no block has (a chunk without blocks; a tie at it goes to the left)
_NONE = math.inf


@forced_kernel
def scan_chunk(c, keys):
    """The smallest key of chunk ``c`` and its block (the lowest index on ties)."""
    lo = c * CHUNK
    hi = lo + CHUNK if lo + CHUNK < len(keys) else len(keys)
    v = _NONE
    b = -1
    for i in range(lo, hi):
        if keys[i] < v:
            v = keys[i]
            b = i
    return v, b


@forced_kernel
def chunk_update(c, v, b, tv, ti):
    """Put chunk ``c``'s smallest key ``v`` (block ``b``) in its leaf and walk up while a node
    changes (ties to the left child)."""
    p = len(tv) // 2 + c
    tv[p] = v
    ti[p] = b
    p //= 2
    while p >= 1:
        left = 2 * p
        if tv[left + 1] < tv[left]:
            left += 1
        if tv[left] == tv[p] and ti[left] == ti[p]:
            return
        tv[p] = tv[left]
        ti[p] = ti[left]
        p //= 2


@kernel
def build_tree(keys, tv, ti):
    """Rebuild the tree over ``keys`` (O(N))."""
    leaves = len(tv) // 2
    for c in range(leaves):
        p = leaves + c
        if c * CHUNK < len(keys):
            tv[p], ti[p] = scan_chunk(c, keys)
        else:
            tv[p] = _NONE
            ti[p] = -1
    for p in range(leaves - 1, 0, -1):
        left = 2 * p
        if tv[left + 1] < tv[left]:
            left += 1
        tv[p] = tv[left]
        ti[p] = ti[left]


@forced_kernel
def at_threshold(w, keys, tv, cur, stack):
    """Put every block whose key is at most ``w`` into ``cur``, by index; return their number.

    A depth-first search of the tree that enters a subtree only where its smallest key is at
    most ``w``, then scans the chunks it reaches.  ``stack`` needs ``log2(leaves) + 2`` entries.
    """
    leaves = len(tv) // 2
    n = len(keys)
    m = 0
    top = 1
    stack[0] = 1
    while top > 0:
        top -= 1
        p = stack[top]
        if tv[p] > w:
            continue
        if p >= leaves:
            lo = (p - leaves) * CHUNK
            for i in range(lo, lo + CHUNK if lo + CHUNK < n else n):
                if keys[i] <= w:
                    cur[m] = i
                    m += 1
        else:
            stack[top] = 2 * p + 1  # the right child under the left: lower indices first
            stack[top + 1] = 2 * p
            top += 2
    return m


@forced_kernel
def avalanche(e, state, graph, ctrl, work, records):
    """Drive to the next toppling and run its avalanche; write catalog row ``e``.

    Returns ``OFC_STATUS_OK``, or ``OFC_STATUS_TOO_MANY_TOPPLINGS`` (row ``e`` then holds the
    hypocentre and the topplings so far).
    """
    keys, scal, tv, ti = state.keys, state.scal, state.tv, state.ti
    indptr, nbr, kval, width = graph.indptr, graph.nbr, graph.kval, graph.width
    stiff, k_uni, fault = graph.stiff, graph.k_uniform, graph.fault
    cur, nxt, amount, mark, seen = work.cur, work.nxt, work.amount, work.mark, work.seen
    fseen, cmark, clist, cnt = work.fseen, work.cmark, work.clist, work.cnt
    cat_f, cat_i = records.cat_f, records.cat_i
    leaves = len(tv) // 2
    faults = len(fseen) > 1  # a network of faults: count them (else: one, if any)
    w = tv[1]  # the drive at which the first block reaches the threshold
    scal[SCAL_W] = w
    nc = at_threshold(w, keys, tv, cur, nxt)
    cat_f[e, OFC_CAT_T] = scal[SCAL_OFFSET] + w
    cat_i[e, OFC_CAT_HYPOCENTER] = cur[0]
    for q in range(nc):
        amount[q] = 1.0
    stamp = cnt[OFC_CNT_STAMP] + 1
    av = stamp  # this avalanche's tag in seen, fseen and cmark
    rest = 1.0 + w  # the key of a block at force 0
    limit = ctrl[OFC_CTRL_MAX_TOPPLINGS]
    total = 0.0
    ntop = nblk = nflt = ngen = ncl = 0
    while nc > 0:
        ngen += 1
        ntop += nc
        if ntop > limit:
            cat_i[e, OFC_CAT_TOPPLINGS] = ntop
            cnt[OFC_CNT_STAMP] = stamp
            return OFC_STATUS_TOO_MANY_TOPPLINGS
        for q in range(nc):  # every block of the generation topples with its force at the start
            i = cur[q]
            dx = amount[q] / stiff[i]
            amount[q] = dx
            total += dx
            keys[i] = rest
            c = i >> OFC_CHUNK_SHIFT
            if ti[leaves + c] == i:  # its chunk's smallest key rose: scan the chunk again
                ti[leaves + c] = -2
                if cmark[c] != av:
                    cmark[c] = av
                    clist[ncl] = c
                    ncl += 1
            if seen[i] != av:
                seen[i] = av
                nblk += 1
                if faults and fseen[fault[i]] != av:
                    fseen[fault[i]] = av
                    nflt += 1
        stamp += 1
        nn = 0
        for q in range(nc):  # then passes k_ij dx_i to its neighbours
            i = cur[q]
            dx = amount[q]
            kdx = k_uni * dx
            if width > 0:
                start = i * width
                stop = start + width
            else:
                start = indptr[i]
                stop = indptr[i + 1]
            for p in range(start, stop):
                j = nbr[p]
                if j < 0:  # the padding of a short row
                    break
                if k_uni > 0.0:
                    kj = keys[j] - kdx
                else:
                    kj = keys[j] - kval[p] * dx
                keys[j] = kj
                c = j >> OFC_CHUNK_SHIFT
                leaf = leaves + c
                if kj < tv[leaf] and ti[leaf] != -2:
                    tv[leaf] = kj
                    ti[leaf] = j
                    if cmark[c] != av:
                        cmark[c] = av
                        clist[ncl] = c
                        ncl += 1
                if kj <= w and mark[j] != stamp:
                    mark[j] = stamp
                    nxt[nn] = j
                    nn += 1
        for q in range(nn):
            amount[q] = 1.0 + (w - keys[nxt[q]])
        cur, nxt = nxt, cur
        nc = nn
    for q in range(ncl):
        c = clist[q]
        if ti[leaves + c] == -2:
            v, b = scan_chunk(c, keys)
        else:
            v, b = tv[leaves + c], ti[leaves + c]
        chunk_update(c, v, b, tv, ti)
    cnt[OFC_CNT_STAMP] = stamp
    cnt[OFC_CNT_TOPPLINGS] += ntop
    cnt[OFC_CNT_GENERATIONS] += ngen
    cat_f[e, OFC_CAT_S] = total
    cat_i[e, OFC_CAT_TOPPLINGS] = ntop
    cat_i[e, OFC_CAT_BLOCKS] = nblk
    cat_i[e, OFC_CAT_FAULTS] = nflt if faults else (1 if nblk > 0 else 0)
    cat_i[e, OFC_CAT_GENERATIONS] = ngen
    return OFC_STATUS_OK


@kernel
def _recentre(state):
    """Move the frame by the whole part of the drive (exact for the keys and the drive)."""
    keys, scal = state.keys, state.scal
    shift = math.floor(scal[SCAL_W])
    scal[SCAL_OFFSET] += shift
    scal[SCAL_W] -= shift
    for i in range(len(keys)):
        keys[i] -= shift
    build_tree(keys, state.tv, state.ti)


@entry
def run_ofc(n_req, state, graph, ctrl, work, records):
    """Run up to ``n_req`` avalanches into catalog rows ``0 .. n_req - 1``; return a status.

    ``work.cnt[OFC_CNT_EVENTS]`` counts the avalanches done.  The tree is built from the keys
    first where ``ctrl[OFC_CTRL_REBUILD]`` is set.
    """
    if ctrl[OFC_CTRL_REBUILD] != 0.0:
        build_tree(state.keys, state.tv, state.ti)
        ctrl[OFC_CTRL_REBUILD] = 0.0
    cnt = work.cnt
    for e in range(n_req):
        status = avalanche(e, state, graph, ctrl, work, records)
        if status != OFC_STATUS_OK:
            return status
        cnt[OFC_CNT_EVENTS] = e + 1
        if state.scal[SCAL_W] > OFC_RECENTRE_AT:
            _recentre(state)
    return OFC_STATUS_OK
