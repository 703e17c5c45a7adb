"""The Carlson-Langer model's physics, written once: the force on a block and the friction law.

A slipping block i, displaced by ``x_i`` since the start of the event, obeys

    x_i'' = F_i - phi_i(x_i'),
    F_i = F0_i + sum_j k_ij x_j - diag_i x_i + nu t + sum_j eta_ij (x_j' - x_i'),
    diag_i = 1 + sum_j k_ij,
    phi_i(v) = oms_i / (1 + cfr_i v),               oms = 1 - sigma, cfr = 2 alpha / (1 - sigma),

``F0_i`` being its force at the start of the event (the plate's pull and the springs'),
``nu t`` the plate's advance during the event (velocity ``graph.nu``; 0 where the plate is
frozen during events), ``eta_ij`` the viscous (Kelvin) coupling and ``phi`` the
velocity-weakening dynamic friction.  The same force acts on a stuck block (``x_i' = 0``).
A stuck block stays stuck while ``F_i < 1`` (the static threshold) and a slipping block
sticks when its velocity reaches 0 with its acceleration <= 0.  Between events the plate moves
and no block does: a stuck block's force is ``1 + w - key_i`` at plate position ``w``
(:func:`block_key`).  ``diag_i`` includes the block's frame springs (column ``FRAME``,
``k wall_i``), which tie it to a frame at rest at the absolute position 0: only the keys see
where the frame is (through the frame offset ``off``).

Every kernel that needs a force, an acceleration or a rate of the friction calls the kernels
here: the DP5 stages (:func:`accel_hot`), the crossings (:func:`force`, :func:`accel`, the
rates :func:`friction_slope` and :func:`jerk_snap`), the lone paths of the interpolated
crossings (:func:`lone_path`), the keys and the solo cache (:func:`block_key`, :func:`load`).
The plate's motion during events and the viscous coupling live in :func:`force` (and its
rate :func:`force_rate`); the interpolated crossings' lone paths do not have them, so a model
with either runs the exact crossings.  Another
friction law is a change of :func:`friction`, :func:`friction_slope` and :func:`jerk_snap`.

Where the time and the velocities enter: a position column ``pos`` of ``W`` comes with the
plate's advance at its instant (``W[PLATE, pos]``) and with the velocities at that
instant (column ``velocities(pos)``), see :mod:`.work`.

Arguments: ``i`` a block, ``pos`` and ``vel`` columns of the work array ``W`` (positions,
velocities), ``v`` a velocity, ``graph`` the ``Graph`` bundle (springs
``indptr``, ``indices``, ``kval``, ``nbr``, ``k_uniform``, the per-block parameters ``block``
with columns ``DIAG`` (``diag_i``), ``OMS``, ``CFR``, ``FRAME`` and ``ETA_SUM``, the plate
velocity ``nu`` and the viscous ``eta``, ``viscous``), ``IW`` the int work array, ``z`` the
displacements between events (relative to the frame offset ``off``), ``keys`` the failure
keys, ``w`` the plate position.
"""

import numpy as np

from faultnet.solver._kernels.bundles import CFR, DIAG, ETA_SUM, FRAME, OMS, kelvin
from faultnet.solver._kernels.carlson_langer.work import (
    ACTIVE,
    AN,
    F0,
    FLAG,
    PLATE,
    VN,
    D,
    velocities,
)
from faultnet.solver._kernels.jit import forced_kernel, inline_kernel, kelvin_kernel, kernel

__all__ = [
    "FRICTION_FLOOR",
    "accel",
    "accel_hot",
    "block_key",
    "force",
    "force_hot",
    "force_rate",
    "friction",
    "friction_slope",
    "jerk_snap",
    "kelvin_terms",
    "load",
    "lone_path",
    "start_accel",
    "stuck_key",
    "uniform_dashpots",
]

#: the friction's denominator ``1 + cfr v`` is floored here: RK stages may probe small
#: negative velocities, where the same analytic formula is used (never reached with sane steps)
FRICTION_FLOOR = 0.5


@kernel
def block_key(i, z, off, graph):
    """Plate position (re-centred frame) at which stuck block ``i``'s force reaches 1.

    ``key_i = 1 + diag_i z_i - sum_j k_ij z_j + frame_i off``: keys do not depend on the plate
    position.  The last term is the pull of the frame springs, at rest at ``x = 0``, that is at
    ``-off`` in the re-centred frame; it is left out where there are none (bit for bit).
    """
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    s = 0.0
    for p in range(indptr[i], indptr[i + 1]):
        s += kval[p] * z[indices[p]]
    key = 1.0 + graph.block[i, DIAG] * z[i] - s
    if graph.block[i, FRAME] != 0.0:
        key += graph.block[i, FRAME] * off
    return key


@kernel
def load(j, w, keys):
    """Force on stuck block ``j`` at plate position ``w``: ``1 + (w - key)``.

    Exactly 1 at the hypocentre, whose key is ``w``, so that its slip equals the cached free
    single-block slip bit for bit (:mod:`.solo`); ``(1 + w) - key`` rounds to 1 +- 2.2e-16.
    """
    return 1.0 + (w - keys[j])


@kernel
def force(i, pos, W, graph):
    """Force on touched block ``i`` for the displacements in column ``pos`` of ``W``.

    Columns are passed by index, never as views: creating a view costs an atomic
    reference-count update, which dominated the cost of a step.  The plate's advance and the
    viscous pull are added last, where the model has them (:func:`kelvin_terms`).
    """
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    s = 0.0
    for p in range(indptr[i], indptr[i + 1]):
        s += kval[p] * W[indices[p], pos]
    return kelvin_terms(W[i, F0] + s - graph.block[i, DIAG] * W[i, pos], i, pos, W, graph)


@kelvin_kernel
def kelvin_terms(f, i, pos, W, graph):
    """Force ``f`` on block ``i`` (column ``pos``) plus the plate's advance and the viscous
    pull ``sum_j eta_ij (v_j - v_i)``, the velocities of column ``velocities(pos)``."""
    if graph.nu > 0.0:
        f += W[PLATE, pos]
    if graph.viscous:
        vel = velocities(pos)
        s = 0.0
        for p in range(graph.indptr[i], graph.indptr[i + 1]):
            s += graph.eta[p] * W[graph.indices[p], vel]
        f += s - graph.block[i, ETA_SUM] * W[i, vel]
    return f


@kelvin_kernel
def uniform_dashpots(k, i, pos, W, graph):
    """:func:`force_hot` with uniform springs ``k`` and dashpots (``graph.eta_uniform``): the
    neighbours' velocities summed in the positions' pass (21% more events/s than two passes)."""
    nbr = graph.nbr
    _, width = nbr.shape
    vel = velocities(pos)
    s = 0.0
    sv = 0.0
    for c in range(width):
        s += W[nbr[i, c], pos]
        sv += W[nbr[i, c], vel]
    f = W[i, F0] + k * s - graph.block[i, DIAG] * W[i, pos]
    if graph.nu > 0.0:
        f += W[PLATE, pos]
    return f + (graph.eta_uniform * sv - graph.block[i, ETA_SUM] * W[i, vel])


@forced_kernel
def force_hot(i, pos, W, graph):
    """:func:`force` for the hot loops: the DP5 stages and the step's join scan.

    Where every spring has the same constant (``graph.k_uniform``) the neighbours' positions
    are summed and multiplied once, without reading ``kval``: 8% more block-steps per second
    on a lattice (bit-identical when k is a power of two).  The sum runs over the padded
    neighbour table ``graph.nbr``, the same number of terms for every block: where degrees
    vary (the percolation clusters) the loop's exit is then predicted, 12-15% more events/s,
    and the zeros it adds leave the sum bit-identical.  Where the dashpots are uniform too
    (``graph.eta_uniform``) the same pass sums the neighbours' velocities.
    """
    k = graph.k_uniform
    if k > 0.0:
        if kelvin(graph) and graph.eta_uniform > 0.0:
            return uniform_dashpots(k, i, pos, W, graph)
        nbr = graph.nbr
        _, width = nbr.shape
        s = 0.0
        for c in range(width):
            s += W[nbr[i, c], pos]
        f = W[i, F0] + k * s - graph.block[i, DIAG] * W[i, pos]
        return kelvin_terms(f, np.int64(i), pos, W, graph)
    return force(np.int64(i), pos, W, graph)  # int64: dopri_step's blocks are unsigned


@kernel
def force_rate(i, W, IW, graph):
    """Rate of change of the force on stuck block ``i`` at the end of a step (DN, VN, AN).

    ``sum_j k_ij v_j + nu + sum_j eta_ij a_j`` over its slipping neighbours: the springs'
    rate, the plate's and the viscous pull's.
    """
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    r = graph.nu
    for p in range(indptr[i], indptr[i + 1]):
        b = indices[p]
        r += kval[p] * W[b, VN]
        if graph.viscous and IW[FLAG, b] == ACTIVE:
            r += graph.eta[p] * W[b, AN]
    return r


@kernel
def stuck_key(i, w, W, graph):
    """The plate position at which stuck block ``i`` reaches 1 if no neighbour moves on.

    From its force now (column D at plate position ``w`` plus the advance ``W[plate, D]``):
    the event's counterpart of :func:`block_key`.
    """
    return w + W[PLATE, D] + (1.0 - force(i, D, W, graph))


@kernel
def friction(i, v, graph):
    """Dynamic friction ``phi_i(v)`` of block ``i`` at velocity ``v`` (floored denominator)."""
    den = 1.0 + graph.block[i, CFR] * v
    if den < FRICTION_FLOOR:
        den = FRICTION_FLOOR
    return graph.block[i, OMS] / den


@kernel
def accel(i, pos, vel, W, graph):
    """Acceleration of slipping block ``i`` (columns ``pos``, ``vel`` of ``W``).

    The friction takes the block unsigned, as from the DP5 stages: one compiled signature.
    """
    return force(i, pos, W, graph) - friction(np.uint64(i), W[i, vel], graph)


@forced_kernel
def accel_hot(i, pos, v, W, graph):
    """Acceleration of block ``i`` at stage positions ``pos`` and stage velocity ``v``.

    For the DP5 stages: LLVM inlines it at every site (typed once by Numba).
    """
    return force_hot(i, pos, W, graph) - friction(i, v, graph)


@kernel
def start_accel(i, graph):
    """Acceleration of block ``i`` starting from rest at the threshold: ``1 - phi_i(0)``."""
    return 1.0 - graph.block[i, OMS]


@kernel
def friction_slope(i, v, graph):
    """``g = -phi_i'(v) = oms cfr / (1 + cfr v)^2``: how much the friction weakens with speed.

    0 where the denominator is floored (the friction is constant there).
    """
    cfr = graph.block[i, CFR]
    den = 1.0 + cfr * v
    if den < FRICTION_FLOOR:
        return 0.0
    return graph.block[i, OMS] * cfr / (den * den)


@inline_kernel
def jerk_snap(i, v, a, sv, sa, graph):
    """Jerk and snap (time derivatives of the acceleration) of slipping block ``i``.

    From its velocity ``v``, acceleration ``a`` and the spring sums of its neighbours'
    velocities ``sv`` and accelerations ``sa``:
    ``J = sv - diag v + g a``, ``S = sa - diag a + g J - 2 g cfr a^2 / (1 + cfr v)``.
    """
    dg, cfr = graph.block[i, DIAG], graph.block[i, CFR]
    g = friction_slope(i, v, graph)
    j = sv - dg * v + g * a
    return j, sa - dg * a + g * j - 2.0 * g * cfr * a * a / (1.0 + cfr * v)


@kernel
def lone_path(i, v0, p0, p1, p2, p3, p4, graph):
    """Taylor coefficients (a1, ..., a8) of block i's lone path ``x(t) = a1 t + ... + a8 t^8``.

    The block starts at x = 0 with velocity ``v0`` and obeys
    ``x'' = P(t) - diag x - phi(x')``, ``P(t) = p0 + p1 t + ... + p4 t^4`` (its force at rest
    with its moving neighbours' motion; coefficients ``p0`` ... ``p4``).  The friction's series
    follows from ``w = 1 / u``, ``u = 1 + cfr x'``: ``w_k = -w_0 (u_1 w_(k-1) + ... + u_k w_0)``,
    and ``a_(k+2) = (p_k - diag a_k - oms w_k) / ((k + 1)(k + 2))``.  A path spans at most a step
    and ``omega^2 = diag <= omega2_max``, so ``omega t`` is at most the step coefficient and
    the truncation error of order ``(omega t)^9 / 9!``: 3e-7 of the path at coefficient 0.8,
    4e-11 at 0.29.
    """
    dg, oms, cfr = graph.block[i, DIAG], graph.block[i, OMS], graph.block[i, CFR]
    a1 = v0
    u1 = cfr * a1
    w0 = 1.0 / (1.0 + u1)
    a2 = (p0 - oms * w0) / 2.0
    u2 = cfr * 2.0 * a2
    w1 = -w0 * (u2 * w0)
    a3 = (p1 - dg * a1 - oms * w1) / 6.0
    u3 = cfr * 3.0 * a3
    w2 = -w0 * (u2 * w1 + u3 * w0)
    a4 = (p2 - dg * a2 - oms * w2) / 12.0
    u4 = cfr * 4.0 * a4
    w3 = -w0 * (u2 * w2 + u3 * w1 + u4 * w0)
    a5 = (p3 - dg * a3 - oms * w3) / 20.0
    u5 = cfr * 5.0 * a5
    w4 = -w0 * (u2 * w3 + u3 * w2 + u4 * w1 + u5 * w0)
    a6 = (p4 - dg * a4 - oms * w4) / 30.0
    u6 = cfr * 6.0 * a6
    w5 = -w0 * (u2 * w4 + u3 * w3 + u4 * w2 + u5 * w1 + u6 * w0)
    a7 = (-dg * a5 - oms * w5) / 42.0
    u7 = cfr * 7.0 * a7
    w6 = -w0 * (u2 * w5 + u3 * w4 + u4 * w3 + u5 * w2 + u6 * w1 + u7 * w0)
    a8 = (-dg * a6 - oms * w6) / 56.0
    return a1, a2, a3, a4, a5, a6, a7, a8
