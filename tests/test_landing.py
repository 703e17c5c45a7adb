"""Landing on a join (faultnet._kernels.landing) against a finely integrated reference."""

import numba as nb
import numpy as np
import pytest

import faultnet
from faultnet._kernels.crossing import JOIN
from faultnet._kernels.dopri import dopri_step
from faultnet._kernels.integrate import ACT, N_IWORK, D, V, force
from faultnet._kernels.landing import land, septic_coeffs
from faultnet._kernels.stepping import activate, commit, touch
from faultnet._kernels.tableau import N_WORK_DOPRI
from faultnet.simulate import default_dt


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
def _start(hyp, w, keys, W, IW, indptr, indices, kval, diag, oms, cfr):
    zero = np.int64(0)
    ntouch = touch(hyp, w, keys, W, IW, zero)
    nact, ntouch = activate(
        hyp, zero, ntouch, w, keys, W, IW, indptr, indices, kval, diag, oms, cfr
    )
    return nact


@nb.njit(cache=False)
def _to_join_step(h, nact, W, IW, indptr, indices, kval, diag, oms, cfr, loc):
    """Full steps, committed, until one has a join inside: (theta, who, steps)."""
    for n in range(10000):
        th, who, kind, status = dopri_step(
            h, 0, nact, IW, W, indptr, indices, kval, diag, oms, cfr, True, 1e6, loc
        )
        if who >= 0:
            if kind == JOIN and th > 0.0:
                return th, who, n
            return -1.0, who, n
        commit(0, nact, W, IW)
    return -1.0, -1, 10000


@nb.njit(cache=False)
def _land(th, who, h, nact, W, IW, indptr, indices, kval, diag, oms, cfr):
    return land(th, who, h, nact, IW, W, indptr, indices, kval, diag, oms, cfr)


@nb.njit(cache=False)
def _fine(h, m, nact, W, IW, indptr, indices, kval, diag, oms, cfr, loc):
    """m committed DP5 steps of length h / m (no crossing scan)."""
    for _ in range(m):
        dopri_step(h / m, 0, nact, IW, W, indptr, indices, kval, diag, oms, cfr, False, 1e6, loc)
        commit(0, nact, W, IW)


@nb.njit(cache=False)
def _force(j, W, indptr, indices, kval, diag):
    return force(j, D, W, indptr, indices, kval, diag)


def _arrays(model):
    adj = model.adjacency
    oms = 1.0 - model.sigma_values
    return (
        adj.indptr.astype(np.int64),
        adj.indices.astype(np.int64),
        adj.data.astype(np.float64),
        model.stiffness.astype(np.float64),
        oms,
        2.0 * model.alpha_values / oms,
    )


@pytest.mark.parametrize("gap", [0.001, 0.003, 0.006])
@pytest.mark.parametrize("alpha", [1.0, 2.0])
def test_landed_join_is_as_accurate_as_the_step(gap, alpha):
    """A block slips from the threshold on a ring; its neighbour, ``gap`` below, joins.

    The landed state must match a fine integration from the start of the
    step to the landed instant as closely as the full step's own end matches
    a fine integration over the whole step (the landing adds no error of its
    own); the joining block's force there is 1 to round-off.
    """
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(12), k=16, sigma=0.01, alpha=alpha)
    arrays = _arrays(model)
    n = model.n
    h = default_dt(model)
    W = np.zeros((n, N_WORK_DOPRI))
    IW = np.zeros((N_IWORK, n), dtype=np.int64)
    loc = np.zeros(6)
    loc[3] = 1.0
    w = 0.0
    keys = np.full(n, 1.0)  # keys: plate position at which a block fails; force = 1 + w - key
    keys[5] = w
    keys[6] = w + gap
    nact = _start(5, w, keys, W, IW, *arrays)
    th, who, steps = _to_join_step(h, nact, W, IW, *arrays, loc)
    assert who == 6 and 0.0 < th < 1.0, (th, who, steps)
    act = IW[ACT, :nact].copy()

    # the full step's end against a fine integration over the whole step
    fine_end = W.copy()
    _fine(h, 256, nact, fine_end, IW, *arrays, loc)
    end = np.concatenate([W[act, 4] - fine_end[act, D], W[act, 5] - fine_end[act, V]])
    step_err = np.abs(end).max()

    start = W.copy()
    hl = _land(th, who, h, nact, W, IW, *arrays)
    assert 0.0 < hl < h
    assert abs(hl / h - th) < 1e-4  # next to the dense output's estimate
    assert abs(_force(who, W, *arrays[:4]) - 1.0) < 1e-13
    ref = start
    _fine(hl, 256, nact, ref, IW, *arrays, loc)
    landed = np.concatenate([W[act, D] - ref[act, D], W[act, V] - ref[act, V]])
    land_err = np.abs(landed).max()
    print(f"step error {step_err:.2e}, landing error {land_err:.2e}, theta {th:.3f}")
    assert step_err > 0.0
    assert land_err <= 2.0 * step_err
