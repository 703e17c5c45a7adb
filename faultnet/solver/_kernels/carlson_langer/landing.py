"""Reaching a join without a partial step: Hermite landing (DP5).

After a full step (D, V, A) -> (DN, VN, AN) in which a stuck block's force
reaches the threshold, every slipping block's path over the step follows
from its two ends alone: the degree-7 Hermite interpolant of the position
through (x, v, a, jerk) at both ends, and of the velocity through
(v, a, jerk, snap), jerk and snap being the first two time derivatives of
the acceleration (one pass over the neighbours each end, no force
evaluation).  The interpolation error, O(h^8), is far below the step's own,
O(h^6), so the landed state is as accurate as the step's end.  The joining
block's force is linear in the positions, hence a degree-7 polynomial over
the step too; its root next to the dense output's estimate is the join,
located to round-off.  Every slipping block is then moved there and only
its acceleration is recomputed (one force pass).  This replaces the partial
DP5 step to the join and its Newton polish (6 + 1 force passes).

Stops are not landed: the end of a step past a stop lies on the friction
law's continuation to negative velocities, whose derivatives grow like
(1 + 2 alpha v / (1 - sigma))^-n, and interpolating through it cost
accuracy (one block at alpha = 2 lost up to 20x).  Whenever the landing is not
clean (no root next to the estimate, or another block found across its own
crossing at the join) the caller takes the partial-step path instead.

Scratch columns (free outside a step), by slot q of the active list:
``K[q, KV]``, ``K[q, KV + 1]`` the jerks at the start and the end of the
step, ``K[q, KV + 3]``, ``K[q, KV + 4]`` the snaps, ``K[q, KV + 2]`` the
landed velocity.

Arguments: ``th`` and ``t`` fractions of the step of length ``h``, ``who`` the joining block,
``i`` a slipping block, ``nact`` the number of slipping blocks, ``c0`` ... ``c7`` a degree-7
polynomial's power-basis coefficients in the fraction of the step, ``graph`` and ``work`` the
bundles ``Graph`` and ``Work`` (:mod:`~faultnet.solver._kernels.bundles`).
"""

from faultnet.solver._kernels.carlson_langer.physics import accel, force, jerk_snap
from faultnet.solver._kernels.carlson_langer.tableau import KV, stage_rows
from faultnet.solver._kernels.carlson_langer.work import (
    ACT,
    ACTIVE,
    AN,
    APOS,
    DN,
    FLAG,
    P2,
    VN,
    A,
    D,
    P,
    V,
)
from faultnet.solver._kernels.jit import inline_kernel, kernel

__all__ = ["land", "septic_coeffs", "septic_root"]


#: the root may differ from the dense output's estimate by at most this (fraction of the step)
LAND_WINDOW = 1e-3

_J0 = KV
_J1 = KV + 1
_VL = KV + 2
_S0 = KV + 3
_S1 = KV + 4


@kernel
def septic_coeffs(y0, d0, s0, t0, y1, d1, s1, t1):
    """Power-basis coefficients of the degree-7 Hermite interpolant on [0, 1].

    ``y0``, ``d0``, ``s0``, ``t0`` and ``y1``, ``d1``, ``s1``, ``t1``: the value and its first
    three derivatives (in units of the interval) at 0 and at 1.
    """
    c2 = 0.5 * s0
    c3 = t0 / 6.0
    r0 = y1 - y0 - d0 - c2 - c3
    r1 = d1 - d0 - 2.0 * c2 - 3.0 * c3
    r2 = s1 - 2.0 * c2 - 6.0 * c3
    r3 = t1 - 6.0 * c3
    return (
        y0,
        d0,
        c2,
        c3,
        35.0 * r0 - 15.0 * r1 + 2.5 * r2 - r3 / 6.0,
        -84.0 * r0 + 39.0 * r1 - 7.0 * r2 + 0.5 * r3,
        70.0 * r0 - 34.0 * r1 + 6.5 * r2 - 0.5 * r3,
        -20.0 * r0 + 10.0 * r1 - 2.0 * r2 + r3 / 6.0,
    )


@kernel
def _eval7(t, c0, c1, c2, c3, c4, c5, c6, c7):
    return c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * (c5 + t * (c6 + t * c7))))))


@inline_kernel
def _slope7(t, c1, c2, c3, c4, c5, c6, c7):
    return c1 + t * (
        2.0 * c2 + t * (3.0 * c3 + t * (4.0 * c4 + t * (5.0 * c5 + t * (6.0 * c6 + t * 7.0 * c7))))
    )


@kernel
def septic_root(th, c0, c1, c2, c3, c4, c5, c6, c7):
    """Root of the polynomial by Newton from ``th``; -1.0 unless it converges inside the window."""
    t = th
    for _ in range(16):
        d = _slope7(t, c1, c2, c3, c4, c5, c6, c7)
        if d == 0.0:
            return -1.0
        dt = _eval7(t, c0, c1, c2, c3, c4, c5, c6, c7) / d
        t -= dt
        if abs(t - th) > LAND_WINDOW or not (0.0 < t <= 1.0):
            return -1.0
        if abs(dt) <= 1e-13:
            # quadratic convergence: one more step is at round-off
            t -= _eval7(t, c0, c1, c2, c3, c4, c5, c6, c7) / d
            return min(t, 1.0)
    return -1.0


@inline_kernel
def _derivs(i, graph, work):
    """Jerk and snap (time derivatives of the acceleration) of block i at both ends of the step.

    Neighbours that are not slipping have zero velocity and acceleration.
    """
    W, IW = work.W, work.IW
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    sv0 = sa0 = sv1 = sa1 = 0.0
    for p in range(indptr[i], indptr[i + 1]):
        b = indices[p]
        if IW[FLAG, b] == ACTIVE:
            c = kval[p]
            sv0 += c * W[b, V]
            sa0 += c * W[b, A]
            sv1 += c * W[b, VN]
            sa1 += c * W[b, AN]
    j0, s0 = jerk_snap(i, W[i, V], W[i, A], sv0, sa0, graph)
    j1, s1 = jerk_snap(i, W[i, VN], W[i, AN], sv1, sa1, graph)
    return j0, s0, j1, s1


@kernel
def _join_theta(th, who, h, graph, work):
    """Where the force on stuck block ``who`` reaches 1 on the step's interpolant; -1.0 if not
    next to ``th``.

    The force is linear in the positions and stuck neighbours do not move, so
    its derivatives are sums over the slipping neighbours (their jerks by slot).
    """
    W, IW = work.W, work.IW
    K = stage_rows(work)
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    h2 = h * h
    h3 = h2 * h
    g0 = g1 = a0 = a1 = j0 = j1 = 0.0
    for r in range(indptr[who], indptr[who + 1]):
        b = indices[r]
        if IW[FLAG, b] == ACTIVE:
            c = kval[r]
            q = IW[APOS, b]
            g0 += c * W[b, V]
            g1 += c * W[b, VN]
            a0 += c * W[b, A]
            a1 += c * W[b, AN]
            j0 += c * K[q, _J0]
            j1 += c * K[q, _J1]
    c0, c1, c2, c3, c4, c5, c6, c7 = septic_coeffs(
        force(who, D, W, graph) - 1.0,
        h * g0,
        h2 * a0,
        h3 * j0,
        force(who, P2, W, graph) - 1.0,
        h * g1,
        h2 * a1,
        h3 * j1,
    )
    return septic_root(th, c0, c1, c2, c3, c4, c5, c6, c7)


@kernel
def _place(t, who, h, nact, graph, work):
    """Every slipping block's interpolated position (P, P2) and velocity (slot column) at ``t``.

    Returns True when no other block has crossed by then: every slipping
    block still moves forward and every other stuck neighbour is below the
    threshold.
    """
    W, IW = work.W, work.IW
    K = stage_rows(work)
    h2 = h * h
    h3 = h2 * h
    for q in range(nact):
        i = IW[ACT, q]
        j0 = K[q, _J0]
        j1 = K[q, _J1]
        c0, c1, c2, c3, c4, c5, c6, c7 = septic_coeffs(
            W[i, D], h * W[i, V], h2 * W[i, A], h3 * j0,
            W[i, DN], h * W[i, VN], h2 * W[i, AN], h3 * j1,
        )  # fmt: skip
        x = _eval7(t, c0, c1, c2, c3, c4, c5, c6, c7)
        c0, c1, c2, c3, c4, c5, c6, c7 = septic_coeffs(
            W[i, V], h * W[i, A], h2 * j0, h3 * K[q, _S0],
            W[i, VN], h * W[i, AN], h2 * j1, h3 * K[q, _S1],
        )  # fmt: skip
        v = _eval7(t, c0, c1, c2, c3, c4, c5, c6, c7)
        W[i, P] = x
        W[i, P2] = x
        if v < 0.0:
            return False
        K[q, _VL] = v
    for q in range(nact):
        i = IW[ACT, q]
        for p in range(graph.indptr[i], graph.indptr[i + 1]):
            j = graph.indices[p]
            if j != who and IW[FLAG, j] != ACTIVE:
                if force(j, P, W, graph) >= 1.0:
                    return False
    return True


@kernel
def land(th, who, h, nact, graph, work):
    """Move the slipping blocks ``IW[ACT, :nact]`` to the join of ``who`` inside the step just
    taken; commit there.

    ``th`` is the dense output's estimate of the join (a fraction of the
    step of length ``h``).  Returns the
    time advanced, or -1.0 when the landing is not clean; the committed state
    (D, V, A) is then unchanged and the positions P, P2 of the slipping blocks
    are rewritten by the next step.
    """
    W, IW = work.W, work.IW
    K = stage_rows(work)
    for q in range(nact):
        i = IW[ACT, q]
        K[q, _J0], K[q, _S0], K[q, _J1], K[q, _S1] = _derivs(i, graph, work)
    t = _join_theta(th, who, h, graph, work)
    if t < 0.0:
        return -1.0
    if not _place(t, who, h, nact, graph, work):
        return -1.0
    for q in range(nact):
        i = IW[ACT, q]
        x = W[i, P]
        W[i, D] = x
        W[i, DN] = x
        v = K[q, _VL]
        W[i, V] = v
        W[i, VN] = v
    for q in range(nact):
        i = IW[ACT, q]
        a = accel(i, P, V, W, graph)
        W[i, A] = a
        W[i, AN] = a
    return t * h
