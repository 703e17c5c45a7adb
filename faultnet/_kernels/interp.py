"""Interpolated crossings: stops and joins placed on a step's dense output, no step redone.

The exact treatment (:mod:`faultnet._kernels.stepping`, ``local.py``, ``landing.py``)
reaches every crossing with the whole scheme, so an event keeps the fifth order of its DP5
steps; on 2-D lattices that costs more than the steps themselves.  With this treatment
(:func:`faultnet._kernels.slip.integrate_interpolated`) the event loop takes every full step
as it is and applies all the crossings found inside it at its end, from what the step has
already computed:

- a *stop* of block b at fraction ``th``: b is put at its dense-output position at ``th``
  (4th order) with v = 0;
- a *join* of block j at ``th``: j starts from rest on the Taylor series of its path to
  the fourth power of the time since the join (its acceleration, jerk and snap from the
  force's derivatives, read off the neighbours' dense output at ``th``) over the rest of the
  step;
- the slipping neighbours of b (or j) moved over ``[th, 1]`` with b on its continuation past
  the stop (or j at rest): their velocities and positions get the first-order correction
  ``k ∫ dx_b`` and ``k ∫∫ dx_b`` of the force they missed (integrals of the dense
  polynomial, or of the Taylor start).

Then every stuck block within two springs of a crossing block whose force has reached 1 joins
at the end of the step (nothing farther has moved since the step's scan listed the joins).
Each crossing costs a few passes over a handful of blocks instead of a partial step.
The neglected terms are the neighbours' own response to their correction over the rest of
the step and the dense output's error: the S error of an event grows like ``dt^4`` per
crossing, against ``dt^5`` for the exact treatment (``faultnet.accuracy`` calibrates
which to use for a given rtol).

``graph`` and ``work`` are the bundles :class:`~faultnet._kernels.bundles.Graph` and
:class:`~faultnet._kernels.bundles.Work`.
"""

from faultnet._kernels.context import LOC_NCAND, LOC_THETA, THETA_CACHE
from faultnet._kernels.crossing import join_theta, stick_theta
from faultnet._kernels.integrate import (
    ACT,
    ACTIVE,
    AN,
    APOS,
    CAND,
    DN,
    FLAG,
    P2,
    SA,
    SV,
    UNTOUCHED,
    VN,
    A,
    D,
    P,
    V,
    accel,
    force,
)
from faultnet._kernels.jit import inline_kernel, kernel
from faultnet._kernels.layout import CNT_INTERPOLATED_CROSSINGS
from faultnet._kernels.stepping import activate, deactivate, stick_scan
from faultnet._kernels.tableau import KA, KV, slot_dense, stage_rows

__all__ = ["JOINING", "interpolated_crossings"]

#: flag of a stuck block that joins at the end of this step (between the two passes)
JOINING = 4


@kernel
def _correct(b, dv, dx, graph, work):
    """Add k dv and k dx to the end velocity and position of b's slipping neighbours."""
    W, IW, kval = work.W, work.IW, graph.kval
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        n = graph.indices[p]
        if IW[FLAG, n] == ACTIVE:
            W[n, VN] += kval[p] * dv
            W[n, DN] += kval[p] * dx


@kernel
def _stop(b, th, h, graph, work):
    """Block b stops at fraction th: its end position on the dense output, neighbours corrected."""
    W = work.W
    q = work.IW[APOS, b]
    c0, c1, c2, c3, c4 = slot_dense(W[b, D], W[b, DN], h, stage_rows(work), q, KV, W[b, VN])
    xs = c0 + th * (c1 + th * (c2 + th * (c3 + th * c4)))
    # antiderivatives P(s) = sum c_m s^(m+1)/(m+1), Q(s) = sum c_m s^(m+2)/(m+2)
    p1 = c0 + c1 / 2.0 + c2 / 3.0 + c3 / 4.0 + c4 / 5.0
    pt = th * (c0 + th * (c1 / 2.0 + th * (c2 / 3.0 + th * (c3 / 4.0 + th * c4 / 5.0))))
    q1 = c0 / 2.0 + c1 / 3.0 + c2 / 4.0 + c3 / 5.0 + c4 / 6.0
    qt = th * th * (c0 / 2.0 + th * (c1 / 3.0 + th * (c2 / 4.0 + th * (c3 / 5.0 + th * c4 / 6.0))))
    r = 1.0 - th
    i1 = xs * r - (p1 - pt)  # int_th^1 (x_s - p(s)) ds
    i2 = xs * 0.5 * r * r - ((p1 - pt) - (q1 - qt))  # int_th^1 (1 - s)(x_s - p(s)) ds
    W[b, DN] = xs
    W[b, VN] = 0.0
    _correct(b, h * i1, h * h * i2, graph, work)


@kernel
def _join(j, th, h, graph, work):
    """Stuck block j reaches the threshold at fraction th: its Taylor start, neighbours corrected.

    The start is the Taylor series of j's path to the fourth power of the time since the
    join: acceleration a0 = 1 - oms, jerk J = F' + oms cfr a0, snap
    S = F'' - diag a0 + oms cfr J - 2 oms cfr^2 a0^2, with F' and F'' from the slipping
    neighbours' dense velocities and accelerations at th.  Keeps the start's displacement and
    velocity in ``W[j, SV]``, ``W[j, SA]`` (columns of the RK4 step, free with DP5) for
    :func:`interpolated_crossings`' second pass.
    """
    W, IW = work.W, work.IW
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    diag, oms, cfr = graph.diag, graph.oms, graph.cfr
    df = 0.0
    ddf = 0.0
    for p in range(indptr[j], indptr[j + 1]):
        n = indices[p]
        if IW[FLAG, n] == ACTIVE:
            q = IW[APOS, n]
            c0, c1, c2, c3, c4 = slot_dense(W[n, V], W[n, VN], h, stage_rows(work), q, KA, W[n, AN])
            df += kval[p] * (c0 + th * (c1 + th * (c2 + th * (c3 + th * c4))))
            ddf += kval[p] * (c1 + th * (2.0 * c2 + th * (3.0 * c3 + th * 4.0 * c4)))
    ddf /= h
    a0 = 1.0 - oms[j]
    g = oms[j] * cfr[j]
    jerk = df + g * a0
    snap = ddf - diag[j] * a0 + g * jerk - 2.0 * g * cfr[j] * a0 * a0
    t = (1.0 - th) * h
    t2 = t * t
    W[j, SV] = t2 * (0.5 * a0 + t * (jerk / 6.0 + snap * t / 24.0))
    W[j, SA] = t * (a0 + t * (0.5 * jerk + snap * t / 6.0))
    t3 = t2 * t
    dv = t3 * (a0 / 6.0 + t * (jerk / 24.0 + snap * t / 120.0))
    dx = t3 * t * (a0 / 24.0 + t * (jerk / 120.0 + snap * t / 720.0))
    _correct(j, dv, dx, graph, work)


@kernel
def _refresh(b, graph, work):
    """Accelerations of b's slipping neighbours (b has moved)."""
    W, IW = work.W, work.IW
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        n = graph.indices[p]
        if IW[FLAG, n] == ACTIVE:
            W[n, A] = accel(n, P, V, W, graph)


@inline_kernel
def _join_at_threshold(j, nact, ntouch, w, keys, graph, work):
    """Activate touched stuck block j if its force is >= 1.  Returns (nact, ntouch)."""
    flag = work.IW[FLAG, j]
    if flag != ACTIVE and flag != UNTOUCHED and force(j, D, work.W, graph) >= 1.0:
        return activate(j, nact, ntouch, w, keys, graph, work)
    return nact, ntouch


@kernel
def _joins_near(b, nact, ntouch, w, keys, graph, work):
    """Joins at the end of a step near crossing block b: b, its neighbours, and theirs.

    After the step's scan listed every join, only b (stopped or started) and its slipping
    neighbours (their ends corrected, :func:`_correct`) moved, so a stuck block that reaches
    the threshold now is a neighbour of b or of one of b's slipping neighbours: scanning
    there finds every block a scan of the whole event would (the whole event's scan cost a
    sixth of the time on a 150^2 lattice at rtol 2e-5), in the order of the crossings.
    """
    indptr, indices, IW = graph.indptr, graph.indices, work.IW
    nact, ntouch = _join_at_threshold(b, nact, ntouch, w, keys, graph, work)
    for p in range(indptr[b], indptr[b + 1]):
        n = indices[p]
        # only a slipping neighbour was corrected; a stuck one has not moved
        corrected = IW[FLAG, n] == ACTIVE
        nact, ntouch = _join_at_threshold(n, nact, ntouch, w, keys, graph, work)
        if corrected:
            for r in range(indptr[n], indptr[n + 1]):
                if indices[r] != b:  # b is checked above
                    nact, ntouch = _join_at_threshold(
                        indices[r], nact, ntouch, w, keys, graph, work
                    )
    return nact, ntouch


@kernel
def interpolated_crossings(h, nact, ntouch, w, keys, graph, work):
    """Apply every crossing the step's scan listed (``IW[CAND]``) at the step's end; commit.

    Called after a DP5 step of length h with ``scan == 2`` (the list complete:
    ``loc[LOC_NCAND] >= 0``).  Returns (nact, ntouch, th_stop): ``th_stop`` is the
    latest stop's fraction of the step (0.0 if none stopped), the event's end when
    no block is left slipping.
    """
    W, IW, loc, cnt = work.W, work.IW, work.loc, work.cnt
    ncand = int(loc[LOC_NCAND])
    one = ncand - ncand + 1  # int64: one signature of the crossing kernels
    th_stop = 0.0
    # first pass, on the step's own values (D, V, A -> DN, VN, AN and the stages)
    for c in range(ncand):
        b = IW[CAND, c]
        th = loc[LOC_THETA + c] if c < THETA_CACHE else 2.0
        if IW[FLAG, b] == ACTIVE:
            if th > 1.0:  # a dip, or a block that joined at rest: its own root
                th = stick_theta(one, h, IW[APOS, b], b, W, stage_rows(work))
            if th > 1.0:
                IW[CAND, c] = -1  # no stop after all
                continue
            _stop(b, th, h, graph, work)
            th_stop = max(th_stop, th)
            IW[CAND, c] = -2 - b
        elif IW[FLAG, b] != JOINING:
            if th > 1.0:
                f0 = force(b, D, W, graph)
                f1 = force(b, P2, W, graph)
                th = 0.0 if f0 >= 1.0 else join_theta(one, h, one - one, b, f0, f1, graph, work)
            _join(b, th, h, graph, work)
            IW[FLAG, b] = JOINING
        else:
            IW[CAND, c] = -1  # listed twice
    # commit the step, then stops, joins and the accelerations they change
    for q in range(nact):
        i = IW[ACT, q]
        x = W[i, DN]
        W[i, D] = x
        W[i, P] = x
        W[i, P2] = x
        W[i, V] = W[i, VN]
        W[i, A] = W[i, AN]
    for c in range(ncand):
        e = IW[CAND, c]
        if e <= -2:
            b = -2 - e
            if IW[FLAG, b] == ACTIVE:
                nact = deactivate(b, nact, W, IW)
                cnt[CNT_INTERPOLATED_CROSSINGS] += 1
        elif e >= 0 and IW[FLAG, e] == JOINING:
            b = e
            W[b, D] += W[b, SV]
            x = W[b, D]
            W[b, P] = x
            W[b, P2] = x
            nact, ntouch = activate(b, nact, ntouch, w, keys, graph, work)
            W[b, V] = W[b, SA]
            W[b, VN] = W[b, SA]
            cnt[CNT_INTERPOLATED_CROSSINGS] += 1
    for c in range(ncand):
        e = IW[CAND, c]
        b = -2 - e if e <= -2 else e
        if e != -1:
            _refresh(b, graph, work)
            if IW[FLAG, b] == ACTIVE:
                W[b, A] = accel(b, P, V, W, graph)
    for c in range(ncand):
        e = IW[CAND, c]
        if e != -1:
            nact, ntouch = _joins_near(-2 - e if e <= -2 else e, nact, ntouch, w, keys, graph, work)
    nact = stick_scan(ntouch - ntouch, nact, W, IW)
    return nact, ntouch, th_stop
