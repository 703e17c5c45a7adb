"""Crossings of a large event handled in small local regions.

In an event with many slipping blocks a stop or a join happens somewhere in
almost every step.  Stepping *all* slipping blocks to each crossing costs
O(n_active) per crossing, O(n_active^2) per unit of time (on a 150^2 lattice
the large events took 26 steps per step length of event time).  After a full
step with crossings inside, :func:`local_step` instead re-integrates only
small *regions* around the crossing blocks, from the start to the end of the
step, locating their crossings exactly as the whole-event loop does, while
the slipping blocks outside keep their full-step results.

- The regions are the slipping blocks within graph distance ``RHO`` of any
  crossing block of the step, split into components of blocks within three
  springs of each other (they share no stuck neighbour and no boundary
  block), each integrated on its own.  A region's *boundary* (slipping blocks
  outside it next to it, or next to one of its stuck neighbours) follows the
  outer step's DP5 dense output during the region's steps
  (:func:`faultnet._kernels.dopri.boundary_positions`).
- The region's change does not feed back into its boundary.  Every crossing
  inside a region must have its slipping neighbours, and those of its stuck
  neighbours, in the region or on its boundary; a crossing that does not
  *escapes*: the step is undone and retried with that block added to the
  crossing blocks (``_MAX_ATTEMPTS`` tries).  The neglected effect is then a
  slip change at least two springs away, of order k^2 a h^6 / 720 per
  crossing; measured on whole events, the error against dt -> 0 is 1.1-2.4
  times the whole-event treatment's (``tests/test_local.py``).
- The step falls back to the whole-event treatment (the caller's, exact)
  after the last try or when the work arrays are too small.  Every block a
  region changes is saved first (columns SV, SA, VS and row SAVE), so undoing
  restores the start of the step exactly.
- The caller adapts the outer step (dt / 16 to dt) to hold about
  ``events._LOCAL_CROSSINGS`` crossings.

Row ``REGION`` holds a region's id for its blocks and stuck neighbours and
minus the id for its boundary; ids come from a counter (``cnt[CNT_REGION_IDS]``) and grow,
so no reset is needed between steps.  ``loc`` is the context shared with the
step kernels (its layout: :mod:`faultnet._kernels.context`): the boundary, the
region step's times, the saves, the boundary blocks' dense-output coefficients
(:func:`faultnet._kernels.dopri.cache_boundary`) and the crossings the outer
step's scan listed.

``graph`` and ``work`` are the bundles :class:`~faultnet._kernels.bundles.Graph` and
:class:`~faultnet._kernels.bundles.Work` (``W``, ``IW``, ``loc``, ``cnt``).
"""

import numpy as np

from faultnet._kernels.context import (
    LOC_BND_END,
    LOC_BND_START,
    LOC_NCAND,
    LOC_NSAVED,
    LOC_OUTER_H,
    LOC_REGION_T,
    LOC_STEP_ID,
    LOC_THETA,
    THETA_CACHE,
)
from faultnet._kernels.crossing import (
    JOIN,
    STATUS_OK,
    STICK,
    candidate,
    join_theta,
    stick_theta,
)
from faultnet._kernels.dopri import boundary_at, cache_boundary
from faultnet._kernels.integrate import (
    ACT,
    ACTIVE,
    AN,
    APOS,
    BND,
    CAND,
    DN,
    FLAG,
    MARK,
    P2,
    QUEUE,
    REGION,
    RES,
    SA,
    SAVE,
    SLIST,
    SV,
    VN,
    VS,
    A,
    D,
    P,
    V,
    accel,
    force,
    new_id,
)
from faultnet._kernels.jit import inline_kernel, kernel
from faultnet._kernels.layout import (
    CNT_BLOCK_STEPS,
    CNT_LOCAL_FALLBACKS,
    CNT_LOCAL_STEPS,
    CNT_REGION_BLOCK_STEPS,
    CTRL_MAX_VELOCITY,
)
from faultnet._kernels.stepping import apply_crossing, commit, step_scan, to_crossing
from faultnet._kernels.tableau import stage_rows

__all__ = ["RHO", "local_step"]

#: a region holds the slipping blocks within this graph distance of its crossing
RHO = 2
#: a region needing more steps than this falls back (guards against a stall)
_MAX_SUB_STEPS = 10000


@kernel
def _save(i, step_id, work):
    """Keep block i's state at the start of the step (once per step) for a fallback."""
    W, IW, loc = work.W, work.IW, work.loc
    if IW[SAVE, i] // 4 != step_id:
        IW[SAVE, i] = step_id * 4 + IW[FLAG, i]
        W[i, SV] = W[i, D]
        W[i, SA] = W[i, V]
        W[i, VS] = W[i, A]
        ns = int(loc[LOC_NSAVED])
        IW[SLIST, ns] = i
        loc[LOC_NSAVED] = ns + 1


@kernel
def _restore(nact, work):
    """Undo every region of this step: saved blocks back to the start of the step."""
    W, IW = work.W, work.IW
    for r in range(int(work.loc[LOC_NSAVED])):
        i = IW[SLIST, r]
        f = IW[SAVE, i] % 4
        IW[FLAG, i] = f
        W[i, D] = W[i, SV]
        W[i, V] = W[i, SA]
        W[i, A] = W[i, VS]
        if f != ACTIVE:
            W[i, P] = W[i, D]
            W[i, P2] = W[i, D]
            W[i, V] = 0.0
            W[i, VN] = 0.0
    for q in range(nact):
        IW[APOS, IW[ACT, q]] = q


@kernel
def _listed(mark, IW, loc):
    """The crossings the outer step's scan listed, each block once; -1 if it listed too many.

    The scan (:func:`faultnet._kernels.crossing.block_crossings`) appends a
    join once per slipping neighbour of the joining block; the list is
    compacted in place, keeping the first, so it reads as :func:`_collect`'s.
    """
    n = int(loc[LOC_NCAND])
    if n < 0:
        return n
    m = 0
    for k in range(n):
        c = IW[CAND, k]
        if IW[FLAG, c] != ACTIVE:
            if IW[MARK, c] == mark:
                continue
            IW[MARK, c] = mark
        candidate(m, c, loc[LOC_THETA + k] if k < THETA_CACHE else 2.0, IW, loc)
        m += 1
    return m


@kernel
def _collect(hh, nact, mark, graph, work):
    """Every block with a crossing inside the full step just taken, into ``IW[CAND]``.

    Where the outer step's dense output puts the crossing is kept in ``loc``
    for a clean crossing (a stop where v changes sign, a join where the force
    crosses 1), so that a region can reach its first crossing from the outer
    step; a stop at a dip of v (a grazing crossing) is not located.  The outer
    step's scan lists the same (:func:`_listed`); this is for when it listed
    more than ``IW[CAND]`` holds.
    """
    W, IW, loc = work.W, work.IW, work.loc
    K = stage_rows(work)
    indptr, indices = graph.indptr, graph.indices
    n = 0
    zero = n - n  # int64, not a literal: the scan's signature of join_theta
    for q in range(nact):
        i = IW[ACT, q]
        if W[i, VN] <= 0.0 or W[i, A] < 0.0:
            # the literal method as in the DP5 step's scan: one compiled signature
            th = stick_theta(1, hh, q, i, W, K)
            if th <= 1.0:
                candidate(n, i, th if W[i, V] > 0.0 and W[i, VN] <= 0.0 else 2.0, IW, loc)
                n += 1
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if IW[FLAG, j] != ACTIVE and IW[MARK, j] != mark:
                f1 = force(j, P2, W, graph)
                if f1 >= 1.0:
                    IW[MARK, j] = mark
                    f0 = force(j, D, W, graph)
                    th = 0.0
                    if f0 < 1.0:
                        th = join_theta(1, hh, zero, j, f0, f1, graph, work)
                    candidate(n, j, th, IW, loc)
                    n += 1
    return n


@kernel
def _first_crossing(cid, ncand, IW, loc):
    """The earliest crossing the outer step located among component cid's candidates.

    Returns (theta, block, kind); block -1 when a candidate of the component
    was not located (then the region finds its first crossing itself).
    """
    best = 2.0
    who = ncand - ncand - 1
    for k in range(ncand):
        c = IW[CAND, k]
        if IW[REGION, c] != cid:
            continue
        th = loc[LOC_THETA + k] if k < THETA_CACHE else 2.0
        if th > 1.0:
            return 2.0, ncand - ncand - 1, who - who
        if th < best:
            best = th
            who = c
    if who < 0:
        return 2.0, who, who - who
    kind = who - who + (STICK if IW[FLAG, who] == ACTIVE else JOIN)
    return best, who, kind


@kernel
def _grow(c, cur, q0, step_id, mark, graph, work):
    """Append the slipping blocks within RHO of block c not yet in the union ``cur``.

    The union is the list ``IW[ACT, q0:end]``; returns the new ``end``.
    """
    IW, indptr, indices = work.IW, graph.indptr, graph.indices
    end = q0
    IW[MARK, c] = mark
    IW[QUEUE, 0] = c
    head, tail = 0, 1
    for depth in range(RHO + 1):
        stop = tail
        while head < stop:
            i = IW[QUEUE, head]
            head += 1
            if IW[FLAG, i] == ACTIVE and IW[REGION, i] != cur:
                IW[REGION, i] = cur
                _save(i, step_id, work)
                IW[ACT, end] = i
                IW[APOS, i] = end
                end += 1
            if depth < RHO:
                for p in range(indptr[i], indptr[i + 1]):
                    j = indices[p]
                    if IW[MARK, j] != mark:
                        IW[MARK, j] = mark
                        IW[QUEUE, tail] = j
                        tail += 1
    return end


@kernel
def _border(m, cur, base, work):
    """Add slipping block m (outside the region) to the boundary; False on a conflict."""
    W, IW, loc = work.W, work.IW, work.loc
    K = stage_rows(work)
    reg = IW[REGION, m]
    if reg == cur or reg == -cur:
        return True
    if reg > base:
        return False  # another component's: not by construction, fall back
    nb_ = int(loc[LOC_BND_END])
    if nb_ >= IW.shape[1]:
        return False
    IW[REGION, m] = -cur
    IW[BND, nb_] = m
    loc[LOC_BND_END] = nb_ + 1
    cache_boundary(nb_, m, W, K, IW, loc)
    return True


@kernel
def _enclose(cur, base, q0, end, step_id, graph, work):
    """Claim the stuck neighbours of the region's blocks; collect its boundary.

    Returns False when a stuck neighbour or a boundary block belongs to another
    component (excluded by the three-spring components; a guard, not a path).
    """
    IW, loc, indptr, indices = work.IW, work.loc, graph.indptr, graph.indices
    loc[LOC_BND_START] = loc[LOC_BND_END]
    for q in range(q0, end):
        i = IW[ACT, q]
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if IW[FLAG, j] == ACTIVE:
                if not _border(j, cur, base, work):
                    return False
                continue
            reg = IW[REGION, j]
            if reg != cur:
                if reg > base:
                    return False
                IW[REGION, j] = cur
                _save(j, step_id, work)
            for p2 in range(indptr[j], indptr[j + 1]):
                m = indices[p2]
                if IW[FLAG, m] == ACTIVE and not _border(m, cur, base, work):
                    return False
    return True


@kernel
def _escapes(j, cur, IW, indptr, indices):
    """Whether a crossing at block j reaches outside the region.

    Its slipping neighbours must be in the region, and so must the slipping
    neighbours of its stuck neighbours, or on the region's boundary.
    """
    for p in range(indptr[j], indptr[j + 1]):
        m = indices[p]
        if IW[FLAG, m] == ACTIVE:
            if IW[REGION, m] != cur:
                return True
            continue
        for p2 in range(indptr[m], indptr[m + 1]):
            b = indices[p2]
            if IW[FLAG, b] == ACTIVE and IW[REGION, b] != cur and IW[REGION, b] != -cur:
                return True
    return False


@kernel
def _claim_neighbours(q0, nact, cur, base, step_id, graph, work):
    """Save and claim the stuck neighbours of the region's slipping blocks before joins."""
    IW, indptr, indices = work.IW, graph.indptr, graph.indices
    for q in range(q0, nact):
        i = IW[ACT, q]
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if IW[FLAG, j] != ACTIVE and IW[REGION, j] != cur:
                if IW[REGION, j] > base:
                    return False
                IW[REGION, j] = cur
                _save(j, step_id, work)
    return True


@inline_kernel
def _sub_run(
    hh, q0, nact, ntouch, cur, base, step_id, s0, th1, who1, kind1, w, keys, ctrl, graph, work
):
    """Integrate the region ``IW[ACT, q0:nact]`` over the whole outer step (length hh).

    With ``who1 >= 0`` the region's first crossing is block who1's (kind1),
    where the outer step put it (fraction th1): it is reached from the outer
    step's start, a join landed on the outer step itself, without a first
    region step over the whole outer step.

    Returns (status, end of the region's list, ntouch, steps, escaper): a
    block whose crossing reaches outside the region (the caller grows the
    regions by it and retries), -2 when out of work space or steps (the
    caller falls back), else -1.
    """
    W, IW, loc, cnt = work.W, work.IW, work.loc, work.cnt
    K = stage_rows(work)
    indptr, indices = graph.indptr, graph.indices
    vmax = ctrl[CTRL_MAX_VELOCITY]
    tau = 0.0
    n = 0
    cap = IW.shape[1]
    while nact > q0:
        h = hh - tau
        if h <= 1e-12 * hh:
            break
        loc[LOC_REGION_T] = tau / hh
        qb = q0  # a join is landed on the region's step (boundary on the outer dense output)
        if who1 >= 0:
            th, who, kind = th1, who1, kind1
            who1 = -1
            qb = q0 - q0  # ... or on the outer step, every block at its ends
        else:
            th, who, kind, status = step_scan(1, h, q0, nact, vmax, n - n + 1, graph, work)
            n += 1
            cnt[CNT_BLOCK_STEPS] += nact - q0
            if status != STATUS_OK:
                return status, nact, ntouch, n, -1
            if who < 0:
                commit(q0, nact, W, IW)
                break
        hs, who, kind, k, status = to_crossing(th, who, kind, h, 1, q0, qb, nact, vmax, graph, work)
        n += k
        if status != STATUS_OK:
            return status, nact, ntouch, n, -1
        if _escapes(who, cur, IW, indptr, indices):
            return STATUS_OK, nact, ntouch, n, who
        tau += hs
        loc[LOC_REGION_T] = tau / hh
        boundary_at(loc[LOC_REGION_T], W, K, IW, loc)
        if not _claim_neighbours(q0, nact, cur, base, step_id, graph, work):
            return STATUS_OK, nact, ntouch, n, who
        nact, ntouch = apply_crossing(who, kind, q0, nact, ntouch, w, keys, graph, work)
        # every block that started or stopped must have its neighbourhood inside
        for r in range(s0, int(loc[LOC_NSAVED])):
            i = IW[SLIST, r]
            if IW[REGION, i] == cur and (IW[FLAG, i] == ACTIVE) != (IW[SAVE, i] % 4 == ACTIVE):
                if _escapes(i, cur, IW, indptr, indices):
                    return STATUS_OK, nact, ntouch, n, i
        if nact + 1 >= cap or n > _MAX_SUB_STEPS:
            return STATUS_OK, nact, ntouch, n, np.int64(-2)
    return STATUS_OK, nact, ntouch, n, np.int64(-1)


@kernel
def _quiet(cur, s0, graph, work):
    """A stuck block of the region at the threshold at the end of the step, or -1.

    A stuck block whose slipping neighbours in the region all stopped is not
    scanned in the region's last steps; its force at the end is checked here
    (the boundary at its end position, column P2).
    """
    W, IW, loc = work.W, work.IW, work.loc
    K = stage_rows(work)
    boundary_at(1.0, W, K, IW, loc)
    for r in range(s0, int(loc[LOC_NSAVED])):
        j = IW[SLIST, r]
        if IW[FLAG, j] != ACTIVE and IW[REGION, j] == cur:
            if force(j, P2, W, graph) >= 1.0:
                return j
    return np.int64(-1)


@kernel
def _finish(nact, nres, graph, work):
    """Commit the blocks outside every region; the new active list; returns its length."""
    W, IW, loc = work.W, work.IW, work.loc
    step_id = np.int64(loc[LOC_STEP_ID])
    nrest = 0
    for q in range(nact):
        i = IW[ACT, q]
        if IW[SAVE, i] // 4 == step_id:
            continue  # a region's block: its state is the region's
        W[i, D] = W[i, DN]
        W[i, V] = W[i, VN]
        W[i, A] = W[i, AN]
        IW[ACT, nrest] = i
        IW[APOS, i] = nrest
        nrest += 1
    for r in range(nres):
        i = IW[RES, r]
        IW[ACT, nrest] = i
        IW[APOS, i] = nrest
        nrest += 1
    # boundary blocks' accelerations with their region neighbours' new positions
    for r in range(int(loc[LOC_BND_END])):
        b = IW[BND, r]
        if IW[FLAG, b] == ACTIVE and IW[SAVE, b] // 4 != step_id:
            W[b, A] = accel(b, D, V, W, graph)
    for q in range(nrest):
        i = IW[ACT, q]
        W[i, P] = W[i, D]
        W[i, P2] = W[i, D]
    return nrest


@kernel
def _component(s, cur, cid, q, IW, indptr, indices):
    """Blocks of the union (``REGION == cur``) within three springs of each other, from s.

    Relabelled ``cid`` and listed at ``IW[ACT, q:end]``; returns ``end``, or -1
    when the search queue overflows (the caller falls back).  Blocks further
    apart share no stuck neighbour and no boundary block, so the components are
    integrated independently; three, not two: a stuck block that joins next to
    one component must have the slipping blocks two springs from it in the same
    component (else it escapes at every retry).

    A breadth-first search to depth 3 from all the component's blocks at once:
    every block visited keeps its least distance from the component in
    ``IW[MARK]`` (as ``-(4 cid + d)``, apart from the positive marks of
    :func:`_grow` and :func:`_collect`), so it is expanded again only when that
    distance shrinks, not once per component block near it (deg^3 paths each).
    """
    n = IW.shape[1]
    tag = 4 * cid
    IW[REGION, s] = cid
    IW[ACT, q] = s
    IW[APOS, s] = q
    IW[MARK, s] = -tag
    end = q + 1
    IW[QUEUE, 0] = s
    head = 0
    tail = 1
    while head < tail:
        i = IW[QUEUE, head % n]
        head += 1
        nd = 1 - IW[MARK, i] - tag  # its distance (the least so far) plus one
        if nd > 3:
            continue
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            dj = -IW[MARK, j] - tag
            if 0 <= dj <= nd:
                continue  # already reached as close
            if IW[FLAG, j] == ACTIVE and IW[REGION, j] == cur:
                IW[REGION, j] = cid
                IW[ACT, end] = j
                IW[APOS, j] = end
                end += 1
                IW[MARK, j] = -tag
            else:
                IW[MARK, j] = -(tag + nd)
                if nd == 3:
                    continue
            if tail - head >= n:
                return q - q - 1
            IW[QUEUE, tail % n] = j
            tail += 1
    return end


@inline_kernel
def _attempt(hh, nact, ncand, nfirst, ntouch, w, keys, ctrl, graph, work):
    """Regions around the candidates ``IW[CAND, :ncand]``, each integrated over the step.

    A region whose candidates are all among the first ``nfirst`` (located by
    the outer step, whose end state its blocks still hold) starts from its
    earliest crossing (:func:`_first_crossing`).

    Returns (status, nres, ntouch, steps, escaper): the regions' slipping
    blocks at the end are ``IW[RES, :nres]``; ``escaper`` >= 0 names a block
    whose crossing left its region (the caller restores and retries).
    """
    IW, loc, cnt = work.IW, work.loc, work.cnt
    step_id = np.int64(loc[LOC_STEP_ID])  # saves are kept once per step, whatever the attempt
    base = new_id(cnt)
    cur = new_id(cnt)
    q0 = nact
    uend = q0
    for k in range(ncand):
        uend = _grow(IW[CAND, k], cur, uend, step_id, new_id(cnt), graph, work)
        if q0 + 2 * (uend - q0) + _SPARE >= IW.shape[1]:
            return STATUS_OK, q0 - q0, ntouch, q0 - q0, np.int64(-2)
    nres = 0
    steps = 0
    for u in range(q0, uend):
        if IW[REGION, IW[ACT, u]] != cur:
            continue
        cid = new_id(cnt)
        end = _component(IW[ACT, u], cur, cid, uend, IW, graph.indptr, graph.indices)
        s0 = int(loc[LOC_NSAVED])
        if end < 0 or not _enclose(cid, base, uend, end, step_id, graph, work):
            return STATUS_OK, nres, ntouch, steps, np.int64(-2)
        th1, who1, kind1 = _first_crossing(cid, nfirst, IW, loc)
        status, end, ntouch, n, esc = _sub_run(
            hh, uend, end, ntouch, cid, base, step_id, s0, th1, who1, kind1, w, keys, ctrl, graph,
            work,
        )  # fmt: skip
        steps += n
        if status != STATUS_OK or esc >= 0:
            return status, nres, ntouch, steps, esc
        esc = _quiet(cid, s0, graph, work)
        if esc >= 0:
            return STATUS_OK, nres, ntouch, steps, esc
        for q in range(uend, end):
            i = IW[ACT, q]
            IW[RES, nres] = i
            IW[APOS, i] = -1
            nres += 1
    return STATUS_OK, nres, ntouch, steps, np.int64(-1)


#: rows of the work arrays kept free above a region's list for its joins
_SPARE = 64
#: escapes a step may retry (each adds the escaping block to the candidates)
_MAX_ATTEMPTS = 4


@inline_kernel
def local_step(hh, nact, ntouch, w, keys, ctrl, graph, work):
    """Handle the crossings inside the full DP5 step just taken (length hh) in local regions.

    Returns (status, nact, ntouch, steps, candidates, done).  ``done`` False:
    nothing changed since the full step (every region undone), the caller
    handles the step as usual.  Counters: ``cnt[CNT_LOCAL_STEPS]`` steps done locally,
    ``cnt[CNT_LOCAL_FALLBACKS]`` fallbacks, ``cnt[CNT_REGION_BLOCK_STEPS]`` block-steps inside
    the regions (undone attempts included).
    """
    IW, loc, cnt = work.IW, work.loc, work.cnt
    c4 = cnt[CNT_BLOCK_STEPS]
    loc[LOC_STEP_ID] = new_id(cnt)  # saves are kept once per step, whatever the attempt
    loc[LOC_OUTER_H] = hh
    loc[LOC_NSAVED] = 0.0
    mark = new_id(cnt)
    ncand = _listed(mark, IW, loc)
    if ncand < 0:
        ncand = _collect(hh, nact, mark, graph, work)
    ncand0 = ncand
    steps = 0
    for attempt in range(_MAX_ATTEMPTS):
        loc[LOC_BND_START] = 0.0
        loc[LOC_BND_END] = 0.0
        # a retry starts every region with a step of its own (the regions' blocks no longer
        # hold the outer step's end state)
        nfirst = ncand if attempt == 0 else ncand - ncand
        status, nres, ntouch, n, esc = _attempt(
            hh, nact, ncand, nfirst, ntouch, w, keys, ctrl, graph, work
        )
        steps += n
        if status == STATUS_OK and esc == -1:
            nact = _finish(nact, nres, graph, work)
            loc[LOC_BND_START] = 0.0
            loc[LOC_BND_END] = 0.0
            cnt[CNT_LOCAL_STEPS] += 1
            cnt[CNT_REGION_BLOCK_STEPS] += cnt[CNT_BLOCK_STEPS] - c4
            return STATUS_OK, nact, ntouch, steps, ncand0, True
        _restore(nact, work)
        if status != STATUS_OK or esc < 0 or ncand >= IW.shape[1]:
            break
        IW[CAND, ncand] = esc
        ncand += 1
    loc[LOC_BND_START] = 0.0
    loc[LOC_BND_END] = 0.0
    cnt[CNT_LOCAL_FALLBACKS] += 1
    cnt[CNT_REGION_BLOCK_STEPS] += cnt[CNT_BLOCK_STEPS] - c4
    return status, nact, ntouch, steps, ncand0, False
