"""Dormand-Prince 5(4) step of the slipping blocks (fixed step, FSAL).

Same contract as :func:`faultnet._kernels.integrate.rk4_step`: from the
committed state (D, V, A) of the active blocks to (DN, VN, AN), leaving
``P == P2 == DN`` on active blocks and D, V, A untouched.  Stage derivatives
live in the rows ``KV + s`` (velocities) and ``KA + s`` (accelerations) of W,
indexed by position in the active list.

For the same accuracy this fifth-order scheme takes steps about five times
longer than RK4 with 6 instead of 4 force evaluations per step (the seventh,
first-same-as-last evaluation is the next step's A), see benchmarks/NOTES.md.
"""

import numba as nb
import numpy as np

from faultnet._kernels.integrate import ACT, AN, DN, N_WORK, P2, VN, A, D, P, V, accel, force

__all__ = ["KA", "KV", "N_WORK_DOPRI", "dense_coeffs", "dopri_step"]

KV = N_WORK  # 6 rows of stage velocities
KA = N_WORK + 6  # 6 rows of stage accelerations
N_WORK_DOPRI = N_WORK + 12

# Butcher tableau (Dormand & Prince 1980), stages 1..6; b of the 5th-order solution
_A = np.array(
    [
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [1 / 5, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3 / 40, 9 / 40, 0.0, 0.0, 0.0, 0.0],
        [44 / 45, -56 / 15, 32 / 9, 0.0, 0.0, 0.0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0, 0.0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0.0],
    ]
)
_B = np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84])
# Dense output (Shampine 1986, as in Hairer's DOPRI5 CONTD5): 4th-order continuous
# extension from the same stages, stage 7 being the derivative at the step's end
_D1 = -12715105075.0 / 11282082432.0
_D3 = 87487479700.0 / 32700410799.0
_D4 = -10690763975.0 / 1880347072.0
_D5 = 701980252875.0 / 199316789632.0
_D6 = -1453857185.0 / 822651844.0
_D7 = 69997945.0 / 29380423.0


@nb.njit(cache=True, nogil=True, inline="always")
def dense_coeffs(y0, y1, k1, k3, k4, k5, k6, k7):
    """Power-basis coefficients (c0..c4) of the DP5 dense output y(theta), theta in [0, 1].

    ``y0``, ``y1`` are the values at the ends of the step, ``k*`` the stage
    derivatives times h (stage 2 does not enter).  Being linear, the formula
    also interpolates any linear functional of the state (a block's force).
    """
    r2 = y1 - y0
    r3 = k1 - r2
    r4 = r2 - k7 - r3
    r5 = _D1 * k1 + _D3 * k3 + _D4 * k4 + _D5 * k5 + _D6 * k6 + _D7 * k7
    return y0, r2 + r3, r4 + r5 - r3, -(r4 + 2.0 * r5), r5


@nb.njit(cache=True, nogil=True, inline="always")
def _stage_input(i, q, s, h, W, pos_row):
    """Write block i's position for stage s into ``pos_row``; return its velocity.

    Stage derivatives are stored by position ``q`` in the active list (compact
    and contiguous), positions by block index (neighbours read them).
    """
    dp = 0.0
    dv = 0.0
    for j in range(s):
        a = _A[s, j]
        dp += a * W[KV + j, q]
        dv += a * W[KA + j, q]
    W[pos_row, i] = W[D, i] + h * dp
    return W[V, i] + h * dv


@nb.njit(cache=True, nogil=True, inline="always")
def _accel_q(i, q, pos, vrow, W, indptr, indices, kval, diag, oms, cfr):
    """accel() with the block's own stage velocity stored at position q."""
    den = 1.0 + cfr[i] * W[vrow, q]
    if den < 0.5:
        den = 0.5
    return force(i, pos, W, indptr, indices, kval, diag) - oms[i] / den


@nb.njit(cache=True, nogil=True)
def dopri_step(h, nact, IW, W, indptr, indices, kval, diag, oms, cfr):
    """One Dormand-Prince 5(4) step of length ``h`` for the active blocks."""
    for q in range(nact):
        i = IW[ACT, q]
        W[KV, q] = W[V, i]
        W[KA, q] = W[A, i]
        W[KV + 1, q] = _stage_input(i, q, 1, h, W, P)
    cur, nxt = P, P2
    for s in range(1, 6):
        # accelerations of stage s read positions from `cur`; inputs of stage
        # s + 1 go to `nxt`, which no block reads during this pass
        for q in range(nact):
            i = IW[ACT, q]
            W[KA + s, q] = _accel_q(i, q, cur, KV + s, W, indptr, indices, kval, diag, oms, cfr)
            if s < 5:
                W[KV + s + 1, q] = _stage_input(i, q, s + 1, h, W, nxt)
        cur, nxt = nxt, cur
    for q in range(nact):
        i = IW[ACT, q]
        dp = 0.0
        dv = 0.0
        for j in range(6):
            dp += _B[j] * W[KV + j, q]
            dv += _B[j] * W[KA + j, q]
        W[DN, i] = W[D, i] + h * dp
        W[VN, i] = W[V, i] + h * dv
        W[P2, i] = W[DN, i]
    for q in range(nact):
        i = IW[ACT, q]
        W[P, i] = W[DN, i]
        W[AN, i] = accel(i, P2, VN, W, indptr, indices, kval, diag, oms, cfr)
