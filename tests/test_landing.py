"""Landing on a join (faultnet._kernels.landing) against a finely integrated reference.

Also the crossings a local region starts from: those the outer step located.
"""

import numba as nb
import numpy as np
import pytest

import faultnet
from faultnet import default_dt
from faultnet._kernels.bundles import Work, graph_bundle, work_array
from faultnet._kernels.context import (
    LOC_BND_END,
    LOC_BND_START,
    LOC_NCAND,
    LOC_OUTER_H,
    LOC_REGION_T,
    LOC_SIZE,
    LOC_THETA,
)
from faultnet._kernels.crossing import JOIN, STICK
from faultnet._kernels.dopri import cache_boundary, dopri_step
from faultnet._kernels.integrate import (
    ACT,
    ACTIVE,
    APOS,
    BND,
    CAND,
    FLAG,
    N_IWORK,
    N_WORK,
    REGION,
    A,
    D,
    P,
    V,
    accel,
    force,
)
from faultnet._kernels.landing import land, septic_coeffs
from faultnet._kernels.layout import CNT_SIZE
from faultnet._kernels.local import _collect, _first_crossing, _listed
from faultnet._kernels.stepping import activate, commit, touch


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
        th, who, kind, status = dopri_step(h, 0, nact, True, 1e6, graph, work)
        if who >= 0:
            if kind == JOIN and th > 0.0:
                return th, who, n
            return -1.0, who, n
        commit(0, nact, W, IW)
    return -1.0, -1, 10000


@nb.njit(cache=False)
def _land(th, who, h, q0, nact, W, IW, graph, loc):
    """A whole event's landing (q0 = 0) or a region's, on the region's step (qb = q0)."""
    graph, work = _bundles(W, IW, graph, loc)
    return land(th, who, h, q0, q0, nact, graph, work)


@nb.njit(cache=False)
def _fine(h, m, nact, W, IW, graph, loc):
    """m committed DP5 steps of length h / m (no crossing scan)."""
    graph, work = _bundles(W, IW, graph, loc)
    for _ in range(m):
        dopri_step(h / m, 0, nact, False, 1e6, graph, work)
        commit(0, nact, W, IW)


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
    loc[LOC_OUTER_H] = 1.0
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
    end = np.concatenate([W[act, 4] - fine_end[act, D], W[act, 5] - fine_end[act, V]])
    step_err = np.abs(end).max()

    start = W.copy()
    hl = _land(th, who, h, 0, nact, W, IW, arrays, loc)
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
def _region_step(h, q0, nact, W, IW, graph, loc):
    graph, work = _bundles(W, IW, graph, loc)
    return dopri_step(h, q0, nact, True, 1e6, graph, work)


@nb.njit(cache=False)
def _region_fine(h, m, q0, nact, W, IW, graph, loc):
    """m committed region steps of length h / m, the boundary on the outer dense output."""
    graph, work = _bundles(W, IW, graph, loc)
    th0 = loc[LOC_REGION_T]
    for s in range(m):
        loc[LOC_REGION_T] = th0 + s * h / m / loc[LOC_OUTER_H]
        dopri_step(h / m, q0, nact, False, 1e6, graph, work)
        commit(q0, nact, W, IW)
    loc[LOC_REGION_T] = th0


@nb.njit(cache=False)
def _cache(r, b, W, IW, loc):
    cache_boundary(r, b, W, W[IW.shape[1] :], IW, loc)


@pytest.mark.parametrize("alpha", [1.0, 2.0])
@pytest.mark.parametrize("v_boundary", [0.2, 0.8])
def test_landed_join_inside_a_local_region(alpha, v_boundary):
    """Blocks 3, 4, 5 of a ring slip; a region {4, 5} with boundary 3 lands 6's join.

    The boundary follows the outer step's dense output, so the region's blocks'
    jerks and snaps need its velocity and acceleration at the region step's
    ends (the quartic's derivatives).  The landed state must match a fine
    integration of the region (its boundary on the same quartic) as closely as
    the region step's own end does; treating the boundary as still (a mutant)
    is orders of magnitude off.
    """
    n, arrays, hh, W, IW, loc = _ring12(alpha)
    w = 0.0
    keys = np.full(n, 0.5)  # every touched block well below the threshold ...
    keys[3] = keys[4] = keys[5] = w  # ... but the slipping ones
    vel = np.array([v_boundary, 0.5, 0.4])
    keys[6] = w + 16.0 * 0.4 * 0.45 * hh  # block 6 joins about half-way through the step
    nact = _slipping(np.array([3, 4, 5]), vel, w, keys, W, IW, arrays)
    # the outer step (whole event, not committed): its stages give the boundary's dense output
    _region_step(hh, 0, nact, W, IW, arrays, loc)
    # the region {4, 5} in slots 3, 4 above the outer list; block 3 its boundary
    q0 = nact
    for q, b in enumerate((4, 5)):
        IW[ACT, q0 + q] = b
        IW[APOS, b] = q0 + q
    end = q0 + 2
    IW[BND, 0] = 3
    loc[LOC_BND_START], loc[LOC_BND_END], loc[LOC_REGION_T], loc[LOC_OUTER_H] = 0.0, 1.0, 0.0, hh
    _cache(0, 3, W, IW, loc)
    # a region step from a quarter of the outer step to its end
    th0 = 0.25
    _region_fine(th0 * hh, 64, q0, end, W, IW, arrays, loc)
    loc[LOC_REGION_T] = th0
    h = (1.0 - th0) * hh
    start = W.copy()
    th, who, kind, status = _region_step(h, q0, end, W, IW, arrays, loc)
    assert who == 6 and kind == JOIN and 0.0 < th < 1.0, (th, who, kind)
    act = np.array([4, 5])
    fine_end = start.copy()
    _region_fine(h, 256, q0, end, fine_end, IW, arrays, loc)
    step_err = np.abs(
        np.concatenate([W[act, 4] - fine_end[act, D], W[act, 5] - fine_end[act, V]])
    ).max()

    hl = _land(th, who, h, q0, end, W, IW, arrays, loc)
    assert 0.0 < hl < h
    assert abs(hl / h - th) < 1e-4
    assert abs(_force(who, W, arrays) - 1.0) < 1e-13
    ref = start.copy()
    _region_fine(hl, 256, q0, end, ref, IW, arrays, loc)
    land_err = np.abs(np.concatenate([W[act, D] - ref[act, D], W[act, V] - ref[act, V]])).max()
    # the boundary was placed at the join, and the accelerations use it there
    assert abs(W[3, P] - ref[3, P]) < 1e-12
    print(f"region step error {step_err:.2e}, landing error {land_err:.2e}, theta {th:.3f}")
    assert step_err > 0.0
    assert land_err <= 2.0 * step_err


# A local region's first crossing, where the outer step located it (local._collect,
# local._first_crossing): reached from the outer step, a join landed on it (qb = 0).


@nb.njit(cache=False)
def _first(cid, ncand, IW, loc):
    return _first_crossing(cid, ncand, IW, loc)


@nb.njit(cache=False)
def _outer_scan(h, nact, W, IW, graph, loc):
    """A whole-event step whose scan also lists every crossing (scan mode 2)."""
    loc[LOC_NCAND] = 0.0
    graph, work = _bundles(W, IW, graph, loc)
    th, who, kind, status = dopri_step(h, 0, nact, 2, 1e6, graph, work)
    return th, who, kind


@nb.njit(cache=False)
def _listed_(mark, IW, loc):
    return _listed(mark, IW, loc)


@nb.njit(cache=False)
def _collect_(h, nact, mark, W, IW, graph, loc):
    graph, work = _bundles(W, IW, graph, loc)
    return _collect(h, nact, mark, graph, work)


def test_first_crossing_is_the_earliest_located_candidate_of_the_component():
    n = 20
    IW = np.zeros((N_IWORK, n), dtype=np.int64)
    loc = np.zeros(LOC_SIZE)
    cand = [4, 9, 11, 15]
    theta = [0.7, 0.2, 0.5, 0.1]
    for k, (c, t) in enumerate(zip(cand, theta, strict=True)):
        IW[CAND, k] = c
        loc[LOC_THETA + k] = t
    IW[REGION, [4, 9, 11]] = 5
    IW[REGION, 15] = 6
    IW[FLAG, 9] = ACTIVE  # a stop; the others are joins
    assert _first(5, 4, IW, loc) == (0.2, 9, STICK)
    assert _first(6, 4, IW, loc) == (0.1, 15, JOIN)
    assert _first(5, 0, IW, loc)[1] == -1  # a retry: nothing located
    assert _first(7, 4, IW, loc)[1] == -1  # no candidate
    loc[LOC_THETA + 2] = 2.0  # one candidate of the component not located (a grazing stop)
    assert _first(5, 4, IW, loc)[1] == -1
    assert _first(6, 4, IW, loc) == (0.1, 15, JOIN)


@pytest.mark.parametrize("v_boundary", [0.2, 0.8])
def test_listed_crossings_match_the_outer_scan(v_boundary):
    """The crossings the scan lists (each block once) are _collect's, with the scan's thetas.

    Blocks 3, 4, 5 and 7 of a ring slip: 6 joins, next to two slipping blocks
    (listed twice by the scan), 2 joins later or not at all.
    """
    n, arrays, h, W, IW, loc = _ring12(1.0)
    keys = np.full(n, 0.5)
    keys[[3, 4, 5, 7]] = 0.0
    keys[6] = 16.0 * (0.4 + 0.3) * 0.45 * h  # joins about half-way through the step
    keys[2] = 16.0 * v_boundary * 0.6 * h  # joins later, or not at all
    vel = np.array([v_boundary, 0.5, 0.4, 0.3])
    nact = _slipping(np.array([3, 4, 5, 7]), vel, 0.0, keys, W, IW, arrays)
    th, who, kind = _outer_scan(h, nact, W, IW, arrays, loc)
    assert kind == JOIN and 0.0 < th < 1.0
    raw = IW[CAND, : int(loc[LOC_NCAND])].tolist()
    assert raw.count(6) == 2
    n = _listed_(98, IW, loc)
    listed = IW[CAND, :n].tolist(), loc[LOC_THETA : LOC_THETA + n].tolist()
    n = _collect_(h, nact, 99, W, IW, arrays, loc)
    collected = IW[CAND, :n].tolist(), loc[LOC_THETA : LOC_THETA + n].tolist()
    assert listed == collected
    got = dict(zip(*listed, strict=True))
    assert sorted(got) == sorted(set(raw))
    assert got[who] == pytest.approx(th, abs=1e-13)
    assert min(got.values()) == got[who]
