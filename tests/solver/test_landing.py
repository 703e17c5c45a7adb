"""Landing on a join (``carlson_langer.landing``) against a finely integrated reference.

Also the crossings a step's scan lists for the interpolated treatment (scan mode 2).
"""

import numba as nb
import numpy as np
import pytest

import faultnet
from faultnet import default_dt
from faultnet.solver._kernels.bundles import Work, graph_bundle, work_array
from faultnet.solver._kernels.carlson_langer.crossing import JOIN, join_theta
from faultnet.solver._kernels.carlson_langer.dopri import dopri_step
from faultnet.solver._kernels.carlson_langer.landing import land, septic_coeffs
from faultnet.solver._kernels.carlson_langer.physics import accel, force
from faultnet.solver._kernels.carlson_langer.stepping import activate, commit, touch
from faultnet.solver._kernels.carlson_langer.work import (
    ACT,
    ACTIVE,
    AN,
    CAND,
    DN,
    FLAG,
    LOC_NCAND,
    LOC_SIZE,
    LOC_THETA,
    N_IWORK,
    N_WORK,
    P2,
    VN,
    A,
    D,
    P,
    V,
)
from faultnet.solver._kernels.layout import CNT_SIZE


@nb.njit(cache=False)
def _septic(y0, d0, s0, t0, y1, d1, s1, t1):
    return septic_coeffs(y0, d0, s0, t0, y1, d1, s1, t1)


def test_septic_hermite_reproduces_a_degree_7_polynomial():
    rng = np.random.default_rng(7)
    c = rng.normal(size=8)
    p = np.polynomial.Polynomial(c)
    ends = [p.deriv(m)(x) for x in (0.0, 1.0) for m in range(4)]
    np.testing.assert_allclose(_septic(*ends), c, rtol=0, atol=1e-12)


@nb.njit(cache=False)
def _bundles(W, IW, graph, loc):
    """The kernels' Graph and Work bundles of these arrays (fresh counters)."""
    return graph, Work(W, IW, loc, np.zeros(CNT_SIZE, dtype=np.int64))


@nb.njit(cache=False)
def _start(hyp, w, keys, W, IW, graph):
    zero = np.int64(0)
    graph, work = _bundles(W, IW, graph, np.zeros(LOC_SIZE))
    ntouch = touch(hyp, w, keys, W, IW, zero)
    nact, ntouch = activate(hyp, zero, ntouch, w, keys, graph, work)
    return nact


@nb.njit(cache=False)
def _to_join_step(h, nact, W, IW, graph, loc):
    """Full steps, committed, until one has a join inside: (theta, who, steps)."""
    graph, work = _bundles(W, IW, graph, loc)
    for n in range(10000):
        th, who, kind, status = dopri_step(h, nact, 1, 1e6, graph, work)
        if who >= 0:
            if kind == JOIN and th > 0.0:
                return th, who, n
            return -1.0, who, n
        commit(nact, W, IW)
    return -1.0, -1, 10000


@nb.njit(cache=False)
def _land(th, who, h, nact, W, IW, graph, loc):
    """Land the active blocks on the join of ``who`` inside the step just taken."""
    graph, work = _bundles(W, IW, graph, loc)
    return land(th, who, h, nact, graph, work)


@nb.njit(cache=False)
def _fine(h, m, nact, W, IW, graph, loc):
    """m committed DP5 steps of length h / m (no crossing scan)."""
    graph, work = _bundles(W, IW, graph, loc)
    for _ in range(m):
        dopri_step(h / m, nact, 0, 1e6, graph, work)
        commit(nact, W, IW)


@nb.njit(cache=False)
def _force(j, W, graph):
    return force(j, D, W, graph)


def _arrays(model):
    adj = model.adjacency
    oms = 1.0 - model.sigma_values
    return graph_bundle(
        adj.indptr, adj.indices, adj.data, model.stiffness, oms, 2.0 * model.alpha_values / oms
    )


def _ring12(alpha):
    """A 12-block ring (k = 16, sigma = 0.01): its kernel arrays, dt and empty work arrays."""
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(12), k=16, sigma=0.01, alpha=alpha)
    W = work_array(model.n, N_WORK)
    IW = np.zeros((N_IWORK, model.n), dtype=np.int64)
    return model.n, _arrays(model), default_dt(model), W, IW, np.zeros(LOC_SIZE)


@pytest.mark.parametrize("gap", [0.001, 0.003, 0.006])
@pytest.mark.parametrize("alpha", [1.0, 2.0])
def test_landed_join_is_as_accurate_as_the_step(gap, alpha):
    """A block slips from the threshold on a ring; its neighbour, ``gap`` below, joins.

    The landed state must match a fine integration from the start of the
    step to the landed instant as closely as the full step's own end matches
    a fine integration over the whole step (the landing adds no error of its
    own); the joining block's force there is 1 to round-off.
    """
    n, arrays, h, W, IW, loc = _ring12(alpha)
    w = 0.0
    keys = np.full(n, 1.0)  # keys: plate position at which a block fails; force = 1 + w - key
    keys[5] = w
    keys[6] = w + gap
    nact = _start(5, w, keys, W, IW, arrays)
    th, who, steps = _to_join_step(h, nact, W, IW, arrays, loc)
    assert who == 6 and 0.0 < th < 1.0, (th, who, steps)
    act = IW[ACT, :nact].copy()

    # the full step's end against a fine integration over the whole step
    fine_end = W.copy()
    _fine(h, 256, nact, fine_end, IW, arrays, loc)
    end = np.concatenate([W[act, DN] - fine_end[act, D], W[act, VN] - fine_end[act, V]])
    step_err = np.abs(end).max()

    start = W.copy()
    hl = _land(th, who, h, nact, W, IW, arrays, loc)
    assert 0.0 < hl < h
    assert abs(hl / h - th) < 1e-4  # next to the dense output's estimate
    assert abs(_force(who, W, arrays) - 1.0) < 1e-13
    ref = start
    _fine(hl, 256, nact, ref, IW, arrays, loc)
    landed = np.concatenate([W[act, D] - ref[act, D], W[act, V] - ref[act, V]])
    land_err = np.abs(landed).max()
    print(f"step error {step_err:.2e}, landing error {land_err:.2e}, theta {th:.3f}")
    assert step_err > 0.0
    assert land_err <= 2.0 * step_err


@nb.njit(cache=False)
def _slipping(blocks, vel, w, keys, W, IW, graph):
    """Blocks slipping at velocities ``vel`` from displacement 0 (active list in this order)."""
    nact = np.int64(0)
    ntouch = np.int64(0)
    graph, work = _bundles(W, IW, graph, np.zeros(LOC_SIZE))
    for b in blocks:
        ntouch = touch(b, w, keys, W, IW, ntouch)
    for b in blocks:
        nact, ntouch = activate(b, nact, ntouch, w, keys, graph, work)
    for r in range(blocks.shape[0]):
        W[blocks[r], V] = vel[r]
    for b in blocks:
        W[b, A] = accel(b, P, V, W, graph)
    return nact


@nb.njit(cache=False)
def _scan(h, nact, mode, W, IW, graph, loc):
    """One step with crossing scan ``mode`` (1: the earliest; 2: also list every crossing)."""
    loc[LOC_NCAND] = 0.0
    graph, work = _bundles(W, IW, graph, loc)
    th, who, kind, status = dopri_step(h, nact, mode, 1e6, graph, work)
    return th, who, kind


@nb.njit(cache=False)
def _fresh_join(h, j, W, IW, graph, loc):
    """Where j's force reaches 1 in the step just taken, and its force at the end, afresh."""
    graph, work = _bundles(W, IW, graph, loc)
    f0 = force(j, D, W, graph)
    f1 = force(j, P2, W, graph)
    return join_theta(h, j, f0, f1, graph, work), f1


@pytest.mark.parametrize("v3", [0.2, 0.8])
def test_listed_crossings_match_the_scan(v3):
    """The interpolated scan (mode 2) lists every join, once per slipping neighbour.

    Blocks 3, 4, 5 and 7 of a ring slip: 6 joins, next to two slipping blocks
    (evaluated once, listed twice from what was kept), 2 joins later.
    Each listed join sits where a fresh evaluation puts it, the earliest is the one the
    step returns, and the same step without the list (mode 1) returns the same crossing.
    """
    n, arrays, h, W, IW, loc = _ring12(1.0)
    keys = np.full(n, 0.5)
    keys[[3, 4, 5, 7]] = 0.0
    keys[6] = 16.0 * (0.4 + 0.3) * 0.45 * h  # joins about half-way through the step
    keys[2] = 16.0 * v3 * 0.6 * h  # joins later in the step
    vel = np.array([v3, 0.5, 0.4, 0.3])
    nact = _slipping(np.array([3, 4, 5, 7]), vel, 0.0, keys, W, IW, arrays)
    W1, IW1, loc1 = W.copy(), IW.copy(), loc.copy()
    th, who, kind = _scan(h, nact, 2, W, IW, arrays, loc)
    assert kind == JOIN and who == 6 and 0.0 < th < 1.0
    ncand = int(loc[LOC_NCAND])
    raw = IW[CAND, :ncand].tolist()
    thetas = loc[LOC_THETA : LOC_THETA + ncand].tolist()
    assert raw.count(6) == 2
    assert all(IW[FLAG, j] != ACTIVE for j in raw)  # no stop in this step
    for j, t in zip(raw, thetas, strict=True):
        fresh, f1 = _fresh_join(h, j, W, IW, arrays, loc)
        assert t == fresh and 0.0 < t < 1.0
        assert W[j, AN] == f1 >= 1.0  # the force at the step's end, kept (k = 16: bit for bit)
    assert min(thetas) == th
    assert raw[thetas.index(th)] == who
    assert (2 in raw) == (_fresh_join(h, 2, W, IW, arrays, loc)[1] >= 1.0)
    # the scan without the list finds the same crossing, bit for bit
    assert _scan(h, nact, 1, W1, IW1, arrays, loc1) == (th, who, kind)
    assert loc1[LOC_NCAND] == 0.0
