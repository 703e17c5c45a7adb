"""Joins revealed by the crossings of an interpolated step (``carlson_langer.late_joins``).

A stuck block pushed over the threshold by a step's crossings crossed it inside the step.
Before the commit it starts where its force, on its neighbours' paths (slipping: the dense
output; stopping: held from the stop on; joining: the cubic of their start), reached 1
(``_late_theta``); a block that stopped in the step and is still over the threshold at its
end goes back from the end (``_late_start``).  On a three-block chain whose moving neighbour
has a constant acceleration the force is exactly quadratic in time, so the crossing time is
known in closed form.
"""

import numba as nb
import numpy as np
import pytest

from faultnet.solver._kernels.bundles import Work, graph_bundle, work_array
from faultnet.solver._kernels.carlson_langer.late_joins import _late_start, _late_theta
from faultnet.solver._kernels.carlson_langer.tableau import KV
from faultnet.solver._kernels.carlson_langer.work import (
    ACTIVE,
    APOS,
    DN,
    F0,
    FLAG,
    JOINING,
    LOC_SIZE,
    N_IWORK,
    N_WORK,
    SA,
    STOPPING,
    STUCK,
    SV,
    VN,
    VS,
    A,
    D,
    P,
    V,
)
from faultnet.solver._kernels.layout import CNT_SIZE

K, SIGMA, ALPHA, H = 16.0, 0.01, 1.0, 0.04


@nb.njit(cache=False)
def _start(j, over, h, W, IW, graph):
    work = Work(W, IW, np.zeros(LOC_SIZE), np.zeros(CNT_SIZE, dtype=np.int64))
    _late_start(j, over, h, graph, work)


@nb.njit(cache=False)
def _theta(j, h, W, IW, graph):
    work = Work(W, IW, np.zeros(LOC_SIZE), np.zeros(CNT_SIZE, dtype=np.int64))
    return _late_theta(j, h, graph, work)


#: the DP5 stage times (fractions of the step) whose derivatives the dense output reads
_NODES = (0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0)


def _slipping(W, IW, b, v0, a2):
    """Block b slips through the step with v = v0 + a2 t: its stage rows and end values.

    The dense output reproduces this quadratic path exactly.
    """
    IW[FLAG, b] = ACTIVE
    IW[APOS, b] = 0
    n = IW.shape[1]
    for s, c in enumerate(_NODES):
        W[n, KV + s] = v0 + a2 * c * H
    W[b, DN] = W[b, D] + v0 * H + 0.5 * a2 * H * H
    W[b, VN] = v0 + a2 * H


def _chain():
    """Blocks 0 - 1 - 2; block 1 (j) is the stuck one."""
    indptr = np.array([0, 1, 3, 4], dtype=np.int64)
    indices = np.array([1, 0, 2, 1], dtype=np.int64)
    kval = np.full(4, K)
    diag = np.array([1.0 + K, 1.0 + 2.0 * K, 1.0 + K])
    oms = np.full(3, 1.0 - SIGMA)
    cfr = 2.0 * ALPHA / oms
    W = work_array(3, N_WORK)
    IW = np.zeros((N_IWORK, 3), dtype=np.int64)
    IW[FLAG, :] = STUCK
    W[1, F0] = 0.9  # any: the late start reads only the neighbours' motion
    return W, IW, graph_bundle(indptr, indices, kval, diag, oms, cfr)


def _expected(tau, dF):
    """Velocity and displacement of j tau after its join, F' = dF there (third order)."""
    a0 = SIGMA
    jerk = dF + (1.0 - SIGMA) * (2.0 * ALPHA / (1.0 - SIGMA)) * a0
    return tau * (a0 + 0.5 * tau * jerk), tau * tau * (0.5 * a0 + tau * jerk / 6.0)


@pytest.mark.parametrize("a2", [0.0, 0.3, -0.03])
def test_join_through_a_slipping_neighbour(a2):
    """Neighbour 2 slips with v(t) = v0 + a2 t: F = 1 at t*, found back from the end."""
    W, IW, g = _chain()
    v0, t_star = 2e-3, 0.013
    IW[FLAG, 2] = ACTIVE
    IW[APOS, 2] = 0
    W[2, V] = v0 + a2 * H  # at the step's end
    W[2, A] = a2

    def rise(t):  # force gained since the step's start
        return K * (v0 * t + 0.5 * a2 * t * t)

    over = rise(H) - rise(t_star)  # F(t*) = 1
    x1 = W[1, D]
    _start(1, over, H, W, IW, g)
    tau = H - t_star
    v, dx = _expected(tau, K * (v0 + a2 * t_star))
    np.testing.assert_allclose(W[1, V], v, rtol=1e-12)
    np.testing.assert_allclose(W[1, D] - x1, dx, rtol=1e-12)
    assert W[1, P] == W[1, D]


def test_no_moving_neighbour_starts_a_whole_step_back():
    """With no slipping neighbour the force has no motion to go back through: a whole step."""
    W, IW, g = _chain()
    _start(1, 1e-4, H, W, IW, g)
    assert W[1, V] == pytest.approx(_expected(H, 0.0)[0])


def test_no_crossing_inside_the_step_starts_at_its_beginning():
    """A force over 1 that the local model cannot bring back to 1 within h starts at the cap."""
    W, IW, g = _chain()
    IW[FLAG, 2] = ACTIVE
    W[2, V] = 1e-4
    W[2, A] = 0.0
    _start(1, 1.0, H, W, IW, g)  # far over the threshold
    v, _ = _expected(H, K * 1e-4)
    np.testing.assert_allclose(W[1, V], v, rtol=1e-12)
    assert np.isfinite(W[1, A])


@pytest.mark.parametrize("a2", [0.0, 0.3, -0.03])
def test_late_theta_through_a_slipping_neighbour(a2):
    """F = 1 - gap at the step's start; the slipping neighbour closes the gap at t*."""
    W, IW, g = _chain()
    v0, gap = 2e-3, 6e-4
    _slipping(W, IW, 2, v0, a2)
    W[1, F0] = 1.0 - gap  # every displacement is 0 at the start: F = F0
    # K (v0 t + a2 t^2 / 2) = gap
    t_star = gap / (K * v0) if a2 == 0.0 else (-v0 + (v0 * v0 + 2 * a2 * gap / K) ** 0.5) / a2
    assert 0.0 < t_star < H
    assert _theta(1, H, W, IW, g) == pytest.approx(t_star / H, abs=1e-11)
    # a neighbour that stops after t* does not move the crossing; one over the threshold
    # at the step's start starts at its beginning
    IW[FLAG, 2] = STOPPING
    W[2, VS] = 0.9
    W[2, SV] = W[2, DN]
    assert _theta(1, H, W, IW, g) == pytest.approx(t_star / H, abs=1e-11)
    W[1, F0] = 1.0 + 1e-9
    assert _theta(1, H, W, IW, g) == 0.0


def test_late_theta_through_a_joining_neighbour():
    """Neighbour 2 joined at fraction 0.3 of the step and moves on the cubic from rest to its
    path's end (x1, v1): the crossing is the cubic's root."""
    W, IW, g = _chain()
    tj, x1, v1, gap = 0.3, 4e-6, 3e-4, 3e-5
    IW[FLAG, 2] = JOINING
    W[2, VS], W[2, SV], W[2, SA] = tj, x1, v1
    W[1, F0] = 1.0 - gap
    L = 1.0 - tj
    d1 = H * v1 * L  # dx/du at the end, u = (s - tj) / L
    # K (a u^2 + c u^3) = gap, a = 3 x1 - d1, c = d1 - 2 x1
    roots = np.roots([d1 - 2 * x1, 3 * x1 - d1, 0.0, -gap / K])
    u = min(r.real for r in roots if abs(r.imag) < 1e-12 and 0.0 < r.real < 1.0)
    assert _theta(1, H, W, IW, g) == pytest.approx(tj + u * L, abs=1e-11)
