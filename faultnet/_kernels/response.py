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

A joining block's own path over ``[th, 1]`` is integrated here (:func:`join_path`):
``PATH_SUBSTEPS`` classical RK4 steps of the block alone, from rest at the threshold, its
slipping neighbours following the step's dense output (a Taylor start to the fourth power
of the time since the join is not accurate enough to keep the answer above from
overcorrecting: its error is of the same order).

``graph`` and ``work`` are the bundles :class:`~faultnet._kernels.bundles.Graph` and
:class:`~faultnet._kernels.bundles.Work`.
"""

from faultnet._kernels.integrate import ACTIVE, APOS, DN, FLAG, P2, STOPPING, VN, D, P, V, force
from faultnet._kernels.jit import inline_kernel, kernel
from faultnet._kernels.tableau import KV, slot_dense, stage_rows

__all__ = [
    "PATH_SUBSTEPS",
    "join_path",
    "respond",
    "stop_moments",
    "stop_position",
]

#: RK4 sub-steps of a block's own path (a join's over the rest of its step, a stop's up to it;
#: 2 gave the same errors
#: as 8 on the 150^2 lattice and the triangular cluster at coefficients 0.405 and 0.5)
PATH_SUBSTEPS = 4

# 4-point Gauss-Legendre rule on [-1, 1]: exact for the stops' integrands (degree 7)
_GX = (-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526)
_GW = (0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538)


@inline_kernel
def _answer(n, k, i1, i2, i3, i4, W, graph):
    """(dv, dx) of slipping block n through a spring k to a neighbour's path difference."""
    den = 1.0 + graph.cfr[n] * 0.5 * (W[n, V] + W[n, VN])
    g = graph.oms[n] * graph.cfr[n] / (den * den)
    dg = graph.diag[n]
    return k * (i1 + g * i2 - dg * i3), k * (i2 + g * i3 - dg * i4)


@kernel
def respond(b, i1, i2, i3, i4, committed, graph, work):
    """Correct the velocity and position of b's slipping neighbours at the end of the step.

    ``i1`` ... ``i4``: the moments ``I_m`` of b's path difference over the rest of the step
    (module text).  Before the step is committed the end state (VN, DN) is corrected; after it
    (``committed``) the committed one (V, and D with the stage columns P and P2).
    """
    W, IW, kval = work.W, work.IW, graph.kval
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        n = graph.indices[p]
        if IW[FLAG, n] == ACTIVE:
            dv, dx = _answer(n, kval[p], i1, i2, i3, i4, W, graph)
            if committed:
                W[n, V] += dv
                x = W[n, D] + dx
                W[n, D] = x
                W[n, P] = x
                W[n, P2] = x
            else:
                W[n, VN] += dv
                W[n, DN] += dx


@inline_kernel
def stop_moments(xs, th, h, c0, c1, c2, c3, c4):
    """Moments I1..I4 of ``xs - p(s)`` over ``[th, 1]``: a stop at ``xs`` against the step's
    dense output ``p`` (coefficients c0..c4 in the fraction s of the step of length h).
    """
    half = 0.5 * (1.0 - th)
    j1 = j2 = j3 = j4 = 0.0
    for g in range(4):
        s = th + half * (1.0 + _GX[g])
        p = c0 + s * (c1 + s * (c2 + s * (c3 + s * c4)))
        d = (xs - p) * half * _GW[g]
        u = 1.0 - s
        j1 += d
        j2 += u * d
        j3 += 0.5 * u * u * d
        j4 += u * u * u / 6.0 * d
    return h * j1, h * h * j2, h**3 * j3, h**4 * j4


@inline_kernel
def _acc(s, x, v, g1, g2, g3, g4, f0, dg, oms, cfr):
    """Acceleration of a block alone at fraction s, displacement x and velocity v.

    Its force is ``f0 + G(s) - dg x``, ``G(s) = g1 s + ... + g4 s^4`` from its moving
    neighbours (:func:`_neighbours`).
    """
    den = 1.0 + cfr * v
    if den < 0.5:
        den = 0.5
    return f0 + s * (g1 + s * (g2 + s * (g3 + s * g4))) - dg * x - oms / den


@kernel
def _neighbours(b, h, graph, work):
    """``G(s)``'s coefficients: the force on b from its moving neighbours' motion in the step.

    Moving: slipping, or slipping until a stop in this step; they follow the step's dense
    output.
    """
    W, IW = work.W, work.IW
    K = stage_rows(work)
    g1 = g2 = g3 = g4 = 0.0
    for p in range(graph.indptr[b], graph.indptr[b + 1]):
        n = graph.indices[p]
        if IW[FLAG, n] == ACTIVE or IW[FLAG, n] == STOPPING:
            k = graph.kval[p]
            _, c1, c2, c3, c4 = slot_dense(W[n, D], W[n, DN], h, K, IW[APOS, n], KV, W[n, VN])
            g1 += k * c1
            g2 += k * c2
            g3 += k * c3
            g4 += k * c4
    return g1, g2, g3, g4


@inline_kernel
def _rk4(s0, tau, h, x, v, g1, g2, g3, g4, f0, dg, oms, cfr):
    """One classical RK4 step of length tau of a block alone from fraction s0: (x, v)."""
    sm, s1 = s0 + 0.5 * tau / h, s0 + tau / h
    a1 = _acc(s0, x, v, g1, g2, g3, g4, f0, dg, oms, cfr)
    x2, v2 = x + 0.5 * tau * v, v + 0.5 * tau * a1
    a2 = _acc(sm, x2, v2, g1, g2, g3, g4, f0, dg, oms, cfr)
    x3, v3 = x + 0.5 * tau * v2, v + 0.5 * tau * a2
    a3 = _acc(sm, x3, v3, g1, g2, g3, g4, f0, dg, oms, cfr)
    x4, v4 = x + tau * v3, v + tau * a3
    a4 = _acc(s1, x4, v4, g1, g2, g3, g4, f0, dg, oms, cfr)
    return (
        x + tau / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4),
        v + tau / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4),
    )


@kernel
def stop_position(b, th, h, graph, work):
    """Position of slipping block b at its stop, fraction th of the step.

    ``PATH_SUBSTEPS`` RK4 steps of b alone from the start of the step to th, its moving
    neighbours on the step's dense output.  The step's own end values (and with them its
    dense output and any interpolant through them) continue b past its stop with v < 0, where
    the friction law is continued analytically and floored: at alpha 2 a block's lone slip
    placed on them is off by 6e-5 at coefficient 0.38, placed here by 3e-6.
    """
    W = work.W
    g1, g2, g3, g4 = _neighbours(b, h, graph, work)
    f0 = force(b, D, W, graph)
    oms, cfr, dg = graph.oms[b], graph.cfr[b], graph.diag[b]
    tau = th * h / PATH_SUBSTEPS
    x, v, s = 0.0, W[b, V], 0.0
    for _ in range(PATH_SUBSTEPS):
        x, v = _rk4(s, tau, h, x, v, g1, g2, g3, g4, f0, dg, oms, cfr)
        s += tau / h
    return W[b, D] + x


@inline_kernel
def _hermite_weighted(tau, x0, v0, x1, v1, w0, w1, dw0, dw1):
    """int over a sub-step of w(t) x(t) dt, Hermite rule (w x and its derivative at both ends)."""
    return 0.5 * tau * (w0 * x0 + w1 * x1) + tau * tau / 12.0 * (
        (dw0 * x0 + w0 * v0) - (dw1 * x1 + w1 * v1)
    )


@kernel
def join_path(j, th, h, graph, work):
    """Path of stuck block j from its join at fraction th to the end of the step.

    Returns (x, v, i1, i2, i3, i4): its displacement and velocity at the end of the step and
    the moments of its displacement over the rest of the step.  Its moving neighbours
    (slipping, or slipping until a stop in this step) follow the step's dense output; the
    force is 1 at the join.
    """
    g1, g2, g3, g4 = _neighbours(j, h, graph, work)
    f0 = 1.0 - th * (g1 + th * (g2 + th * (g3 + th * g4)))
    oms, cfr, dg = graph.oms[j], graph.cfr[j], graph.diag[j]
    T = (1.0 - th) * h
    tau = T / PATH_SUBSTEPS
    x = v = t = 0.0
    i1 = i2 = i3 = i4 = 0.0
    for _ in range(PATH_SUBSTEPS):
        xn, vn = _rk4(th + t / h, tau, h, x, v, g1, g2, g3, g4, f0, dg, oms, cfr)
        # the moments' weights (T - t)^(m - 1) / (m - 1)! and their derivatives at both ends
        u0, u1 = T - t, T - t - tau
        i1 += _hermite_weighted(tau, x, v, xn, vn, 1.0, 1.0, 0.0, 0.0)
        i2 += _hermite_weighted(tau, x, v, xn, vn, u0, u1, -1.0, -1.0)
        i3 += _hermite_weighted(tau, x, v, xn, vn, 0.5 * u0 * u0, 0.5 * u1 * u1, -u0, -u1)
        i4 += _hermite_weighted(
            tau, x, v, xn, vn, u0**3 / 6.0, u1**3 / 6.0, -0.5 * u0 * u0, -0.5 * u1 * u1
        )
        x, v, t = xn, vn, t + tau
    return x, v, i1, i2, i3, i4
