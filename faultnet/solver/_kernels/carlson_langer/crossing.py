"""Stops and joins inside a step: where a slipping block stops, where a stuck one starts.

A *stick* is a slipping block whose velocity reaches 0; a *join* is a stuck neighbour whose
force reaches the static threshold 1.  Both are located as a fraction ``theta`` of the step
just taken, on the DP5 dense output (fourth order, :func:`.roots.poly_root`).

Arguments: ``h`` the step's length, ``q`` a block's position in the active list, ``i``,
``j`` blocks, ``W`` the work array and ``K`` its stage rows (:func:`~.tableau.stage_rows`),
``graph``, ``work`` the bundles :class:`~faultnet.solver._kernels.bundles.Graph` and ``Work``.
"""

import numpy as np

from faultnet.solver._kernels.carlson_langer.physics import force, force_hot
from faultnet.solver._kernels.carlson_langer.roots import poly_root
from faultnet.solver._kernels.carlson_langer.tableau import (
    KA,
    KV,
    dense_coeffs,
    slot_dense,
    stage_rows,
)
from faultnet.solver._kernels.carlson_langer.work import (
    ACTIVE,
    AN,
    APOS,
    CAND,
    FLAG,
    LOC_NCAND,
    LOC_THETA,
    MARK,
    THETA_CACHE,
    VN,
    VS,
    A,
    D,
    V,
)
from faultnet.solver._kernels.jit import forced_kernel, inline_kernel, kelvin_kernel, kernel

__all__ = [
    "JOIN",
    "STATUS_EVENT_TOO_LONG",
    "STATUS_INTERRUPTED",
    "STATUS_NONFINITE",
    "STATUS_OK",
    "STATUS_RUNAWAY",
    "STATUS_SLIPS_FULL",
    "STICK",
    "block_crossings",
    "join_theta",
    "stick_theta",
]

STATUS_OK = 0
STATUS_SLIPS_FULL = 1
STATUS_NONFINITE = -1
STATUS_RUNAWAY = -2
STATUS_EVENT_TOO_LONG = -3
STATUS_INTERRUPTED = -4  #: ``ctrl[CTRL_STOP]`` was set: the event under way was undone

STICK = 1
JOIN = 2


@kernel
def stick_theta(h, q, i, W, K):
    """Where inside the step block i (active position q) stops; 2.0 if it does not.

    On the dense output of its velocity, ``v(th) = c0 + c1 th + ... + c4 th^4``, whose slope
    at the ends is the step's accelerations (``c1 = h A``, ``h AN`` at th = 1): the root
    where v falls to 0 from above, or, from rest (a block that joined at rest and stops
    again within the step), where ``v / th`` does; a velocity that falls and rises again
    inside a step whose ends are both positive stops where it falls through 0 before its
    minimum, if that minimum is not above 0.
    """
    v0 = W[i, V]
    v1 = W[i, VN]
    if v1 > 0.0 and not (W[i, A] < 0.0 and W[i, AN] > 0.0):
        return 2.0
    c0, c1, c2, c3, c4 = slot_dense(v0, v1, h, K, q, KA, W[i, AN])
    if v1 > 0.0:  # a dip: the minimum, where the slope rises through 0
        lo = poly_root(0.0, 1.0, c1, 2.0 * c2, 3.0 * c3, 4.0 * c4, 0.0)
        if c0 + lo * (c1 + lo * (c2 + lo * (c3 + lo * c4))) > 0.0:
            return 2.0
    elif v0 > 0.0:
        lo = 1.0
    elif c1 > 0.0:  # from rest, rising first
        return poly_root(0.0, 1.0, c1, c2, c3, c4, 0.0)
    else:  # from rest, never rising: it stops at once
        return 0.0
    return poly_root(0.0, lo, c0, c1, c2, c3, c4)


@kelvin_kernel
def _dashpot_rates(g, r, q, b, K, W, graph):
    """The sums ``g`` of :func:`join_theta` plus the dashpot of CSR entry r (slipping block b,
    active position q): its stage accelerations are its velocity's stage derivatives."""
    if not graph.viscous:
        return g
    e = graph.eta[r]
    g1, g3, g4, g5, g6, g7 = g
    return (
        g1 + e * K[q, KA], g3 + e * K[q, KA + 2], g4 + e * K[q, KA + 3],
        g5 + e * K[q, KA + 4], g6 + e * K[q, KA + 5], g7 + e * W[b, AN],
    )  # fmt: skip


@kernel
def join_theta(h, j, f0, f1, graph, work):
    """Where inside the step the force on stuck block j reaches 1 (``f0 < 1 <= f1``).

    The force is linear in the positions, the plate's advance and the velocities, so its dense
    output is that of its slipping neighbours' positions summed through the springs, plus
    ``nu t``, plus their velocities summed through the viscous coupling (whose stage
    derivatives are the stage accelerations).
    """
    W, IW = work.W, work.IW
    K = stage_rows(work)
    indptr, indices, kval = graph.indptr, graph.indices, graph.kval
    g1 = g3 = g4 = g5 = g6 = g7 = graph.nu
    for r in range(indptr[j], indptr[j + 1]):
        b = indices[r]
        if IW[FLAG, b] == ACTIVE:
            c = kval[r]
            q = IW[APOS, b]
            g1 += c * K[q, KV]
            g3 += c * K[q, KV + 2]
            g4 += c * K[q, KV + 3]
            g5 += c * K[q, KV + 4]
            g6 += c * K[q, KV + 5]
            g7 += c * W[b, VN]
            g1, g3, g4, g5, g6, g7 = _dashpot_rates((g1, g3, g4, g5, g6, g7), r, q, b, K, W, graph)
    c0, c1, c2, c3, c4 = dense_coeffs(
        f0 - 1.0, f1 - 1.0, h * g1, h * g3, h * g4, h * g5, h * g6, h * g7
    )
    return poly_root(0.0, 1.0, c0, c1, c2, c3, c4)


@forced_kernel
def _list(b, th, IW, loc):
    """Append block b's crossing (at fraction th, 2.0: not located) to ``IW[CAND]``.

    The count is ``loc[LOC_NCAND]``; -1 once the row is full (the list is then not used).
    """
    n = np.int64(loc[LOC_NCAND])
    _, width = IW.shape
    if n >= width:
        loc[LOC_NCAND] = -1.0
    elif n >= 0:
        IW[CAND, n] = b
        if n < THETA_CACHE:
            loc[LOC_THETA + n] = th
        loc[LOC_NCAND] = n + 1.0


@inline_kernel
def block_crossings(h, q, i, pos, vmax, best, who, kind, keep, stamp, K, graph, work):
    """Fold the crossings owned by active block i into (best, who, kind).

    Block i's own stop, and the joins of its stuck neighbours, whose end-of-step forces are
    read from column ``pos`` (every active block's end position).  With ``keep`` (the
    interpolated crossings) every crossing is also appended to ``IW[CAND]``, a stop at a dip
    of v (a grazing crossing) as not located; each stuck neighbour's force at the end of the
    step is kept in its (unused) ``AN`` column, a join's fraction of the step in its ``VS``
    column, and the block tagged with the step's ``stamp`` in ``IW[MARK]``: a stuck block
    next to several slipping ones is evaluated (and its join located) once per step, and
    listed again from what was kept.  Returns (best, who, kind, status); a non-finite or
    runaway velocity (not below ``vmax``) stops the scan with its status and the block in
    ``who``.  Inlined into the step's last pass: ``graph`` and ``work`` cost nothing here, and
    ``K`` is the step's stage rows.
    """
    W, IW, loc = work.W, work.IW, work.loc
    indptr, indices = graph.indptr, graph.indices
    v1 = W[i, VN]
    if not (v1 < vmax):
        return best, i, kind, STATUS_NONFINITE if v1 != v1 else STATUS_RUNAWAY
    if v1 <= 0.0 or W[i, A] < 0.0:
        th = stick_theta(h, q, i, W, K)
        if th < best:
            best, who, kind = th, i, STICK
        if keep and th <= 1.0:
            _list(i, th if W[i, V] > 0.0 and v1 <= 0.0 else 2.0, IW, loc)
    for p in range(np.uint64(indptr[i]), np.uint64(indptr[i + 1])):
        j = indices[p]
        u = np.uint64(j)  # unsigned: no negative-index wrap-around in the hot accesses
        if IW[FLAG, u] == ACTIVE:
            continue
        seen = keep and IW[MARK, u] == stamp  # evaluated for an earlier neighbour in this step
        f1 = W[u, AN] if seen else force_hot(u, pos, W, graph)
        if keep and not seen:
            W[u, AN] = f1
            IW[MARK, u] = stamp
        if f1 < 1.0:
            continue
        if seen:
            th = W[j, VS]
        else:
            f0 = force(j, D, W, graph)
            th = 0.0 if f0 >= 1.0 else join_theta(h, j, f0, f1, graph, work)
            if keep:
                W[j, VS] = th
        if th < best:
            best, who, kind = th, j, JOIN
        if keep:
            _list(j, th, IW, loc)
    return best, who, kind, STATUS_OK
