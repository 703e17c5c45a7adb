"""Inside an event: the active list, and reaching a crossing with the whole scheme.

The kernels here keep the lists of an event: the touched blocks ``IW[TOUCH, :ntouch]`` and
the active (slipping) blocks ``IW[ACT, :nact]``.  :func:`to_crossing` and
:func:`apply_crossing` are the exact treatment of a crossing (:func:`.slip.integrate_exact`).

Arguments: ``j``, ``i`` blocks, ``w`` the plate position, ``keys`` the failure keys, ``W``,
``IW`` the work arrays, ``nact``, ``ntouch`` the lengths of the lists, ``h`` a step's length,
``graph`` and ``work`` the bundles :class:`~faultnet.solver._kernels.bundles.Graph` and
:class:`~faultnet.solver._kernels.bundles.Work`.
"""

from faultnet.solver._kernels.carlson_langer.crossing import STATUS_OK, STICK
from faultnet.solver._kernels.carlson_langer.dopri import dopri_step
from faultnet.solver._kernels.carlson_langer.physics import accel, force, force_rate, load
from faultnet.solver._kernels.carlson_langer.work import (
    ACT,
    ACTIVE,
    AN,
    APOS,
    DN,
    F0,
    FLAG,
    FRONTIER,
    P2,
    PLATE,
    Q2,
    STUCK,
    TOUCH,
    UNTOUCHED,
    VN,
    A,
    D,
    P,
    Q,
    V,
)
from faultnet.solver._kernels.jit import inline_kernel, kernel
from faultnet.solver._kernels.layout import (
    CNT_BLOCK_STEPS,
    CNT_PARTIAL_BLOCK_STEPS,
    CNT_RELOCATIONS,
)

__all__ = [
    "activate",
    "apply_crossing",
    "commit",
    "deactivate",
    "join_scan",
    "restore_positions",
    "stick_scan",
    "to_crossing",
    "touch",
]


@kernel
def touch(j, w, keys, W, IW, ntouch):
    """Mark block j touched; store its force at the start of the event (:func:`.physics.load`)."""
    IW[FLAG, j] = FRONTIER
    W[j, F0] = load(j, w, keys)
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
    W[j, A] = accel(j, D, V, W, graph)  # (P == D here: between steps)
    return nact + 1, ntouch


@kernel
def deactivate(i, nact, W, IW):
    """Block i sticks (v = 0); swap it to the end of the active list, which loses it.

    The blocks that stuck since the list had ``n`` entries are then ``IW[ACT, nact:n]``.
    """
    q = IW[APOS, i]
    last = IW[ACT, nact - 1]
    IW[ACT, q] = last
    IW[APOS, last] = q
    IW[ACT, nact - 1] = i
    IW[FLAG, i] = STUCK
    W[i, V] = 0.0
    W[i, VN] = 0.0
    return nact - 1


@kernel
def join_scan(nact, ntouch, w, keys, graph, work):
    """Activate every stuck neighbour of a slipping block whose force is >= 1."""
    W, IW, indptr, indices = work.W, work.IW, graph.indptr, graph.indices
    q = nact - nact
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
def stick_scan(nact, W, IW):
    """Deactivate every slipping block that has stopped (v <= 0, a <= 0).

    A block that has just joined has v = 0 but a > 0 and keeps slipping.
    """
    for q in range(nact - 1, -1, -1):
        i = IW[ACT, q]
        if W[i, V] <= 0.0 and W[i, A] <= 0.0:
            nact = deactivate(i, nact, W, IW)
    return nact


@kernel
def commit(nact, W, IW):
    """The step's end (DN, VN, AN) becomes the committed state (D, V, A), plate included."""
    for q in range(nact):
        i = IW[ACT, q]
        W[i, D] = W[i, DN]
        W[i, V] = W[i, VN]
        W[i, A] = W[i, AN]
    W[PLATE, D] = W[PLATE, DN]


@kernel
def restore_positions(nact, W, IW):
    """Discard a step: the stage positions (velocities, plate) back to the committed ones."""
    for q in range(nact):
        i = IW[ACT, q]
        W[i, P] = W[i, D]
        W[i, P2] = W[i, D]
    W[PLATE, P] = W[PLATE, P2] = W[PLATE, D]


@inline_kernel
def _residual(who, kind, W, IW, graph):
    """Crossing function of block ``who`` and its time derivative at the end of the last step.

    ``kind``: ``STICK`` (the velocity) or a join (the force minus 1).
    """
    if kind == STICK:
        return W[who, VN], W[who, AN]
    return force(who, P, W, graph) - 1.0, force_rate(who, W, IW, graph)


@inline_kernel
def _taylor_shift(dh, nact, graph, work):
    """Move the end of the step by a tiny ``dh``: x += v dh + a dh^2 / 2, v += a dh.

    Used only for |dh| <= ``_TAYLOR_MAX`` times the step, where the neglected
    third-order term is below round-off; costs one force pass instead of a step.
    """
    W, IW = work.W, work.IW
    half = 0.5 * dh * dh
    for q in range(nact):
        i = IW[ACT, q]
        x = W[i, DN] + dh * W[i, VN] + half * W[i, AN]
        W[i, DN] = x
        W[i, P] = x
        W[i, P2] = x
        W[i, VN] += dh * W[i, AN]
        if graph.viscous:
            W[i, Q] = W[i, VN]
            W[i, Q2] = W[i, VN]
    if graph.nu > 0.0:
        W[PLATE, DN] += graph.nu * dh
        W[PLATE, P] = W[PLATE, DN]
        W[PLATE, P2] = W[PLATE, DN]
    for q in range(nact):
        i = IW[ACT, q]
        W[i, AN] = accel(i, P, VN, W, graph)


#: largest Newton correction, as a fraction of the step, done by a Taylor shift
_TAYLOR_MAX = 1e-4


@kernel
def _polish(h, hmax, who, kind, nact, graph, work):
    """Newton on the true crossing residual of block ``who`` (``kind``) at the end of a step of
    length h, no longer than ``hmax``.

    A small correction shifts the end by a Taylor step; a large one (a poor first estimate)
    redoes the step from the committed state.  The crossing ends located to round-off.
    Returns the step length and the number of full step evaluations it took.
    """
    W = work.W
    n = 0
    for _ in range(6):
        g, dg = _residual(who, kind, W, work.IW, graph)
        if dg == 0.0:
            break
        dh = -g / dg
        hn = h + dh
        if not (0.0 < hn <= hmax) or abs(dh) <= 1e-13 * hmax:
            break
        if abs(dh) <= _TAYLOR_MAX * hmax:
            _taylor_shift(dh, nact, graph, work)
        else:
            dopri_step(hn, nact, n - n, 0.0, graph, work)
            n += 1
        h = hn
    return h, n


@inline_kernel
def to_crossing(th, who, kind, h, nact, vmax, graph, work):
    """Reach the crossing of block ``who`` (``kind``) found at fraction ``th`` of a step of length
    ``h``; commit there.  ``vmax``: the fastest velocity allowed in a partial step.

    A partial step to the crossing; if another crossing is found earlier inside it, go to that
    one instead; then Newton-polish the crossing to round-off and commit.  ``th == 0`` (a
    crossing at the start) discards the step.  Returns (time advanced, block, kind, steps
    taken, status).  Counts its work in ``work.cnt``.
    """
    W, IW, cnt = work.W, work.IW, work.cnt
    n = 0
    one = n + 1  # int64, not a literal: one typing of the scan
    if th <= 0.0:
        restore_positions(nact, W, IW)
        return 0.0, who, kind, n, STATUS_OK
    hmax = h
    for _ in range(64):
        h = th * h
        th2, who2, kind2, status = dopri_step(h, nact, one, vmax, graph, work)
        n += 1
        cnt[CNT_BLOCK_STEPS] += nact
        cnt[CNT_PARTIAL_BLOCK_STEPS] += nact
        if status != STATUS_OK:
            return h, who2, kind2, n, status
        if who2 < 0 or who2 == who or th2 >= 1.0 - 1e-9 or th2 <= 0.0:
            break
        th, who, kind = th2, who2, kind2
        cnt[CNT_RELOCATIONS] += 1
    h, npart = _polish(h, hmax, who, kind, nact, graph, work)
    n += npart
    cnt[CNT_BLOCK_STEPS] += npart * nact
    cnt[CNT_PARTIAL_BLOCK_STEPS] += npart * nact
    commit(nact, W, IW)
    return h, who, kind, n, STATUS_OK


@inline_kernel
def apply_crossing(who, kind, nact, ntouch, w, keys, graph, work):
    """After committing at a crossing: joins (``who`` and any other block at threshold), then stops.

    ``kind``: the crossing's kind, ``STICK`` or ``JOIN``.  Returns (nact, ntouch, hi): the
    blocks that stuck here are ``IW[ACT, nact:hi]``.
    """
    W, IW = work.W, work.IW
    if kind != STICK and IW[FLAG, who] != ACTIVE:
        nact, ntouch = activate(who, nact, ntouch, w, keys, graph, work)
    # joins first: the neighbours of a block that sticks now are scanned too
    nact, ntouch = join_scan(nact, ntouch, w, keys, graph, work)
    hi = nact
    if kind == STICK and IW[FLAG, who] == ACTIVE:
        nact = deactivate(who, nact, W, IW)
    nact = stick_scan(nact, W, IW)
    if graph.viscous:  # a stuck block's stage velocities are 0 for its neighbours' forces
        for q in range(nact, hi):
            W[IW[ACT, q], Q] = 0.0
            W[IW[ACT, q], Q2] = 0.0
    return nact, ntouch, hi
