"""The rest of a step after an interpolated crossing: a joining block's path and its neighbours'.

When block b stops (or j joins) at fraction ``th`` of a step, the step has moved b on past
its stop (j at rest) over the remaining time ``T = (1 - th) h``, and b's slipping neighbours
with it.  The true path of b differs from the step's by ``d(t)``, ``0 <= t <= T``: held at
its stop position instead of moving back on the dense output, or moving on the join's path
instead of resting.  A slipping neighbour n felt the force ``k d(t)`` less than it should
have, and its own motion answers it: to first order in the answer,

    dx'' = k d(t) + g dx' - diag dx,        g = -phi'(v) = oms cfr / (1 + cfr v)^2,

(the velocity weakening of the friction, evaluated at n's mean velocity over the step, and
n's own springs).  At the end of the step that gives

    dv = k (I1 + g I2 - diag I3),   dx = k (I2 + g I3 - diag I4),
    I_m = int_0^T (T - t)^(m - 1) / (m - 1)! d(t) dt

(:func:`respond`).  The first terms alone (``k I1``, ``k I2``) leave the friction and spring
terms out, which with g T and diag T^2 of order 0.1 at the usual steps is the largest error
of the interpolated treatment: with them the 90th percentile of the S error of 2-block
events on the periodic 150^2 lattice is 15 times smaller at coefficient 0.5, that of all
events on the ring W1 11 times smaller at 0.241.

A neighbour that is itself joining in the step answers the same way over the part of the
rest of the step it moves in, with its path's end (``W[n, SV]``, ``W[n, SA]``) corrected
instead (:func:`respond` for a neighbour that joined first, :func:`stop_answer` for a stop).
Every such change of a block's end position (column ``P2``) is summed in
``loc[LOC_MOVED]`` (:mod:`.late_joins`).
A stopping block is held until the commit: the crossings of its neighbours before its stop
shift the stop by its own answer to them (:func:`stop_shift`).

A joining block's own path over ``[th, 1]`` is integrated here (:func:`join_path`), and a
stopping block's up to its stop (:func:`stop_position`): the block alone, its slipping
neighbours following the step's dense output and those that joined before it the cubic from
rest to their path's end; the path is the Taylor series of its equation of motion to the
eighth power of the time (:func:`~.physics.lone_path`), whose moments ``I_m`` are exact.
Four classical RK4 sub-steps per path (16 force evaluations, each with a division) gave the
same 90th percentiles within 1% on W1-W6 at coefficients 0.05 to 0.6 and took 3-7% of W1's
and 2-4% of W6's events/s more.  The joining neighbours follow the cubic (:func:`join_cubic`; a
Taylor start to the fourth power of the time since the join is not accurate enough to keep the
answer above from overcorrecting: its error is of the same order).

``graph`` and ``work`` are the bundles :class:`~faultnet.solver._kernels.bundles.Graph` and
:class:`~faultnet.solver._kernels.bundles.Work`.
"""

import numpy as np

from faultnet.solver._kernels.bundles import DIAG
from faultnet.solver._kernels.carlson_langer.physics import force, friction_slope, lone_path
from faultnet.solver._kernels.carlson_langer.tableau import path_dense
from faultnet.solver._kernels.carlson_langer.work import (
    ACTIVE,
    DN,
    FLAG,
    JOINING,
    LOC_MOVED,
    P2,
    SA,
    STOPPING,
    SV,
    VN,
    VS,
    D,
    V,
)
from faultnet.solver._kernels.jit import forced_kernel, inline_kernel, kernel

__all__ = [
    "answer",
    "join_cubic",
    "join_path",
    "neighbour_poly",
    "path_moments",
    "place_join",
    "respond",
    "stop_answer",
    "stop_shift",
    "stop_position",
]

#: the first moment's order (:func:`_moment`): an int64, which Numba types as such, not as a
#: literal, so that every order shares one compiled signature
_FIRST = np.int64(1)

# 4-point Gauss-Legendre rule on [-1, 1]: exact for the stops' integrands (degree 7)
_GX = (-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526)
_GW = (0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538)


@kernel
def answer(n, k, vbar, i1, i2, i3, i4, graph):
    """(dv, dx) of moving block n (mean velocity ``vbar`` over the step) through a spring k to
    a neighbour's path difference with moments i1..i4."""
    g = friction_slope(n, vbar, graph)
    dg = graph.block[n, DIAG]
    return k * (i1 + g * i2 - dg * i3), k * (i2 + g * i3 - dg * i4)


@forced_kernel
def _join_answer(n, k, i1, i2, i3, i4, graph, work):
    """Joining block n's answer (:func:`answer`, at its path's mean velocity) through a spring
    k to a neighbour's path difference with moments i1..i4: its path's end (``W[n, SV]``,
    ``W[n, SA]``, :func:`join_path`) and end position corrected."""
    W = work.W
    dv, dx = answer(n, k, 0.5 * W[n, SA], i1, i2, i3, i4, graph)
    W[n, SA] += dv
    W[n, SV] += dx
    W[n, P2] = W[n, D] + W[n, SV]
    work.loc[LOC_MOVED] += abs(dx)


@kernel
def respond(b, th, i1, i2, i3, i4, graph, work):
    """Correct the velocity and position of b's moving neighbours at the end of the step.

    ``i1`` ... ``i4``: the moments ``I_m`` of b's path difference over the rest of the step
    from ``th`` (module text).  Before the step is committed: the end state (VN, DN) of a
    slipping neighbour, and that of a neighbour joining before ``th`` (its path end in
    ``W[n, SV]``, ``W[n, SA]``, :func:`join_path`), which moves over all of ``[th, 1]``.
    """
    W, IW, kval = work.W, work.IW, graph.kval
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        n = graph.indices[p]
        if IW[FLAG, n] == ACTIVE:
            dv, dx = answer(n, kval[p], 0.5 * (W[n, V] + W[n, VN]), i1, i2, i3, i4, graph)
            W[n, VN] += dv
            W[n, DN] += dx
            W[n, P2] = W[n, DN]
            work.loc[LOC_MOVED] += abs(dx)
        elif IW[FLAG, n] == JOINING and W[n, VS] < th:
            _join_answer(n, kval[p], i1, i2, i3, i4, graph, work)


@kernel
def stop_answer(m, k, xs, th, h, c0, c1, c2, c3, c4, graph, work):
    """Joining block m's answer to a neighbour's stop at th (position xs, spring k).

    m's path (:func:`join_path`, end in ``W[m, SV]``, ``W[m, SA]``) saw the stopping
    neighbour on the step's dense output (coefficients c0..c4), its force normalised to 1 at
    its join ``tm = W[m, VS]``; the neighbour in fact stays at xs from th on.  The path
    difference is ``xs - p(s)`` over ``[th, 1]`` if m joined first, ``p(tm) - p(s)`` over
    ``[tm, 1]`` if the neighbour stopped first.
    """
    W = work.W
    tm = W[m, VS]
    t0, x0 = th, xs
    if tm > th:
        t0 = tm
        x0 = c0 + tm * (c1 + tm * (c2 + tm * (c3 + tm * c4)))
    i1, i2, i3, i4 = path_moments(x0, t0, 1.0, h, 0.0, c0, c1, c2, c3, c4)
    _join_answer(m, k, i1, i2, i3, i4, graph, work)


@kernel
def place_join(j, th, h, graph, work):
    """Stuck block j joins at fraction th: its path, and its moving neighbours' answer to it.

    Its path over the rest of the step is :func:`join_path`; its displacement and velocity at
    the end of the step are kept in ``W[j, SV]``, ``W[j, SA]`` (:mod:`.work`) for the
    commit, its end position in ``P2``.
    """
    W = work.W
    x, v, i1, i2, i3, i4 = join_path(j, th, h, graph, work)
    W[j, SV] = x
    W[j, SA] = v
    W[j, P2] = W[j, D] + x
    work.loc[LOC_MOVED] += abs(x)
    respond(j, th, i1, i2, i3, i4, graph, work)


@forced_kernel
def join_cubic(n, h, W):
    """Block n's path after its join in the step, ``a (s - t)^2 + c (s - t)^3``: (t, a, c).

    The cubic in the fraction s of the step from rest at its join (``t = W[n, VS]``) to the
    end of its integrated path (:func:`join_path`: ``W[n, SV]``, ``W[n, SA]``).
    """
    # x(u) = a' u^2 + c' u^3, u = (s - t) / L: x(1) = SV, dx/ds(1) = h SA
    t = W[n, VS]
    L = 1.0 - t
    x1, d1 = W[n, SV], h * W[n, SA] * L
    return t, (3.0 * x1 - d1) / (L * L), (d1 - 2.0 * x1) / (L * L * L)


@inline_kernel
def stop_shift(b, th, h, graph, work):
    """Shift of slipping block b's stop (at fraction th) by its neighbours' earlier crossings.

    :func:`stop_position` moves b's neighbours on the step's dense output.  A neighbour that
    joined before th in fact pushed b from its join on (its path's cubic,
    :func:`join_cubic`), one that stopped before th (its stop already placed, ``W[m, SV]``)
    held b back: to first order the stop moves by b's answer (:func:`answer`) to those path
    differences up to th.
    """
    W, IW = work.W, work.IW
    shift = 0.0
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        m = graph.indices[p]
        fl = IW[FLAG, m]
        t0 = W[m, VS]
        if (fl != JOINING and fl != STOPPING) or not (t0 < th):
            continue
        if fl == STOPPING:  # held at W[m, SV] instead of moving on the dense output
            x0, z0 = W[m, SV], 0.0
            c0, c1, c2, c3, c4 = path_dense(m, h, work)
        else:  # moving on its cubic in s - t0 instead of resting: 0 - (-cubic)
            x0, z0 = 0.0, t0
            _, a, c = join_cubic(m, h, W)
            c0, c1, c2, c3, c4 = 0.0, 0.0, -a, -c, 0.0
        i1, i2, i3, i4 = path_moments(x0, t0, th, h, z0, c0, c1, c2, c3, c4)
        _, dx = answer(b, graph.kval[p], 0.5 * W[b, V], i1, i2, i3, i4, graph)
        shift += dx
    return shift


@kernel
def path_moments(x0, t0, t1, h, z0, c0, c1, c2, c3, c4):
    """Moments I1..I4 of a path difference ``x0 - p(s)`` over ``[t0, t1]``.

    ``I_m = h^m int (t1 - s)^(m - 1) / (m - 1)! (x0 - p(s)) ds`` in the fraction s of the step
    of length h, where ``p(s) = c0 + c1 z + c2 z^2 + c3 z^3 + c4 z^4``, ``z = s - z0``: the
    step's dense output (``z0 = 0``) against a block held at ``x0``, or a join's cubic about
    its join (``x0 = 0``, the cubic negated).  Four-point Gauss-Legendre, exact for these
    integrands (degree 7 at most).
    """
    half = 0.5 * (t1 - t0)
    j1 = j2 = j3 = j4 = 0.0
    for g in range(4):
        s = t0 + half * (1.0 + _GX[g])
        z = s - z0
        p = c0 + z * (c1 + z * (c2 + z * (c3 + z * c4)))
        d = (x0 - p) * half * _GW[g]
        u = t1 - s
        j1 += d
        j2 += u * d
        j3 += 0.5 * u * u * d
        j4 += u * u * u / 6.0 * d
    h2 = h * h
    return h * j1, h2 * j2, h * h2 * j3, h2 * h2 * j4


@kernel
def neighbour_poly(b, h, th, graph, work):
    """``G(s)``'s coefficients: the force on b from its moving neighbours' motion in the step.

    Moving: slipping, or slipping until a stop in this step, on the step's dense output; and
    the neighbours n joining before ``th`` (-1.0: none), whose paths :func:`join_path` has
    integrated (``W[n, SV]``, ``W[n, SA]`` at the end of the step), on the cubic from rest at
    their join (``W[n, VS]``) to that end (:func:`join_cubic`).  The constant term is left
    out: it cancels.
    """
    W, IW = work.W, work.IW
    g1 = g2 = g3 = g4 = 0.0
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        n = graph.indices[p]
        k = graph.kval[p]
        if IW[FLAG, n] == ACTIVE or IW[FLAG, n] == STOPPING:
            _, c1, c2, c3, c4 = path_dense(n, h, work)
            g1 += k * c1
            g2 += k * c2
            g3 += k * c3
            g4 += k * c4
        elif IW[FLAG, n] == JOINING and W[n, VS] < th:
            t, a, c = join_cubic(n, h, W)
            g1 += k * (3.0 * c * t * t - 2.0 * a * t)
            g2 += k * (a - 3.0 * c * t)
            g3 += k * c
    return g1, g2, g3, g4


@kernel
def _at(t, a):
    """Displacement and velocity at time t on the path with Taylor coefficients ``a``."""
    x = 0.0
    v = 0.0
    for k in range(8, 0, -1):
        x = (x + a[k - 1]) * t
        v = v * t + k * a[k - 1]
    return x, v


@kernel
def _moment(T, m, a):
    """``int_0^T (T - t)^(m - 1) / (m - 1)! x(t) dt`` on the path with Taylor coefficients ``a``.

    The power t^k contributes ``a_k k! T^(k + m) / (k + m)!``.
    """
    c = 1.0
    for q in range(2, m + 2):
        c /= q  # 1! / (1 + m)!
    s = 0.0
    # tk = T^(m + 1) by squaring, as Numba's ``**`` computes it, which without the rewrite
    # passes would be a library of its own
    tk, sq, e = 1.0, T, m + 1
    while e != 0:
        if e & 1:
            tk *= sq
        e >>= 1
        sq *= sq
    for k in range(1, 9):
        s += a[k - 1] * c * tk
        c *= (k + 1.0) / (k + 1.0 + m)
        tk *= T
    return s


@inline_kernel
def stop_position(b, th, h, graph, work):
    """Position of slipping block b at its stop, fraction th of the step.

    b's path alone (:func:`~.physics.lone_path`) from the start of the step to th, its moving
    neighbours on the step's dense output.  The step's own end values (and with them its
    dense output and any interpolant through them) continue b past its stop with v < 0, where
    the friction law is continued analytically and floored: at alpha 2 a block's lone slip
    placed on them is off by 6e-5 at coefficient 0.38, placed here by 3e-6.
    """
    W = work.W
    g1, g2, g3, g4 = neighbour_poly(b, h, -1.0, graph, work)
    r = 1.0 / h
    r2 = r * r
    a = lone_path(
        b, W[b, V], force(b, D, W, graph), g1 * r, g2 * r * r, g3 * (r * r2), g4 * (r2 * r2), graph
    )
    x, _ = _at(th * h, a)
    return W[b, D] + x


@inline_kernel
def join_path(j, th, h, graph, work):
    """Path of stuck block j from its join at fraction th to the end of the step.

    Returns (x, v, i1, i2, i3, i4): its displacement and velocity at the end of the step and
    the moments of its displacement over the rest of the step.  Its moving neighbours
    (slipping, or slipping until a stop in this step) follow the step's dense output; the
    force is 1 at the join.
    """
    g1, g2, g3, g4 = neighbour_poly(j, h, th, graph, work)
    # G(s) re-expanded about th, in the time since the join; the force is 1 there
    r = 1.0 / h
    r2 = r * r
    p1 = (g1 + th * (2.0 * g2 + th * (3.0 * g3 + th * 4.0 * g4))) * r
    p2 = (g2 + th * (3.0 * g3 + th * 6.0 * g4)) * r * r
    p3 = (g3 + th * 4.0 * g4) * (r * r2)
    a = lone_path(j, 0.0, 1.0, p1, p2, p3, g4 * (r2 * r2), graph)
    T = (1.0 - th) * h
    x, v = _at(T, a)
    m = _FIRST
    return x, v, _moment(T, m, a), _moment(T, m + 1, a), _moment(T, m + 2, a), _moment(T, m + 3, a)
