"""Dormand-Prince 5(4): stage storage and the dense output (the step is :mod:`.dopri`)."""

import numpy as np

from faultnet.solver._kernels.carlson_langer.work import APOS, DN, VN, D
from faultnet.solver._kernels.jit import inline_kernel, kernel

__all__ = ["KA", "KV", "N_STAGE", "dense_coeffs", "path_dense", "slot_dense", "stage_rows"]

# The stage derivatives of the block at active position q are row N + q of the work array
# ``work.W`` (float64[2 N + 2, N_WORK]), below the N blocks' own rows: a block's row then fits in
# 112 bytes, which counts on graphs that do not fit in the cache, and the kernels still take one
# array (a second array in the ``Work`` bundle cost the ring W1 3-5%: every crossing kernel
# takes the bundle).  :func:`stage_rows` is the view of those rows.
KV = np.int64(0)  # 6 columns of stage velocities (int64, not a literal: see work.D)
KA = np.int64(6)  # 6 columns of stage accelerations
N_STAGE = 12

# Dense output (Shampine 1986, as in Hairer's DOPRI5 CONTD5): 4th-order continuous
# extension from the same stages, stage 7 being the derivative at the step's end
_D1 = -12715105075.0 / 11282082432.0
_D3 = 87487479700.0 / 32700410799.0
_D4 = -10690763975.0 / 1880347072.0
_D5 = 701980252875.0 / 199316789632.0
_D6 = -1453857185.0 / 822651844.0
_D7 = 69997945.0 / 29380423.0


@kernel
def dense_coeffs(y0, y1, k1, k3, k4, k5, k6, k7):
    """Power-basis coefficients (c0..c4) of the DP5 dense output y(theta), theta in [0, 1].

    ``y0``, ``y1`` are the values at the ends of the step, ``k1``, ``k3`` ... ``k7`` the stage
    derivatives times h (stage 2 does not enter; ``k7``, the derivative at the end).  Being
    linear, the formula also interpolates any linear functional of the state (a block's force).
    """
    r2 = y1 - y0
    r3 = k1 - r2
    r4 = r2 - k7 - r3
    r5 = _D1 * k1 + _D3 * k3 + _D4 * k4 + _D5 * k5 + _D6 * k6 + _D7 * k7
    return y0, r2 + r3, r4 + r5 - r3, -(r4 + 2.0 * r5), r5


@kernel
def slot_dense(y0, y1, h, K, q, col, end):
    """:func:`dense_coeffs` of a block whose stage derivatives are in row q of K, columns col + s.

    ``y0``, ``y1``: the values at the ends of the step of length ``h``; ``col`` is KV
    (positions: derivatives are the stage velocities) or KA (velocities); ``end`` is the
    derivative at the end of the step.
    """
    k1, k3, k4, k5, k6 = K[q, col], K[q, col + 2], K[q, col + 3], K[q, col + 4], K[q, col + 5]
    return dense_coeffs(y0, y1, h * k1, h * k3, h * k4, h * k5, h * k6, h * end)


@inline_kernel
def stage_rows(work):
    """The DP5 stage derivatives: rows N to 2 N - 1 of ``work.W``, row q for active position q.

    A view; the kernels run without Numba's reference counting, so it costs nothing.
    """
    _, n = work.IW.shape
    return work.W[n : 2 * n]


@kernel
def path_dense(n, h, work):
    """:func:`dense_coeffs` of the position of block n over the step of length ``h`` just taken.

    From its start and end positions (``D``, ``DN``), its stage velocities and its end
    velocity (``VN``): the path of a slipping block, or of a stopping one up to its stop.
    ``work``: the ``Work`` bundle.  One kernel for the crossings' many call sites, each of
    which would otherwise hold the seven arguments' reads again.
    """
    W = work.W
    return slot_dense(W[n, D], W[n, DN], h, stage_rows(work), work.IW[APOS, n], KV, W[n, VN])
