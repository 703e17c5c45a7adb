"""The DP5 step kernel against a dense NumPy Dormand-Prince step.

The kernel evaluates forces through the graph's CSR rows, on stage positions
that ping-pong between two columns, with a local region's boundary blocks
written at each stage time from the outer step's dense output.  The reference
here builds the full force from a dense spring matrix at every stage, with the
boundary blocks on their quartic, and the tableau written out from Dormand &
Prince (1980).
"""

from fractions import Fraction as Fr

import networkx as nx
import numba as nb
import numpy as np
import pytest
import scipy.sparse

from faultnet._kernels.bundles import Work, graph_bundle, work_array
from faultnet._kernels.context import (
    LOC_BND_END,
    LOC_BND_START,
    LOC_CACHE,
    LOC_OUTER_H,
    LOC_REGION_T,
    LOC_SIZE,
)
from faultnet._kernels.dopri import dopri_step
from faultnet._kernels.integrate import (
    ACT,
    ACTIVE,
    AN,
    APOS,
    BND,
    DN,
    F0,
    FLAG,
    N_IWORK,
    N_WORK,
    P2,
    STUCK,
    VN,
    A,
    D,
    P,
    V,
)
from faultnet._kernels.layout import CNT_SIZE
from faultnet._kernels.tableau import KA, KV

_C = [0, Fr(1, 5), Fr(3, 10), Fr(4, 5), Fr(8, 9), 1]
_A = [
    [],
    [Fr(1, 5)],
    [Fr(3, 40), Fr(9, 40)],
    [Fr(44, 45), Fr(-56, 15), Fr(32, 9)],
    [Fr(19372, 6561), Fr(-25360, 2187), Fr(64448, 6561), Fr(-212, 729)],
    [Fr(9017, 3168), Fr(-355, 33), Fr(46732, 5247), Fr(49, 176), Fr(-5103, 18656)],
]
_B = [Fr(35, 384), 0, Fr(500, 1113), Fr(125, 192), Fr(-2187, 6784), Fr(11, 84)]


@nb.njit(cache=False)
def _step(h, q0, nact, IW, W, graph, loc):
    work = Work(W, IW, loc, np.zeros(CNT_SIZE, dtype=np.int64))
    return dopri_step(h, q0, nact, 0, 1e6, graph, work)


def _reference(h, blocks, x, v0, a0, F0s, K, diag, oms, cfr, boundary, th0, hout):
    """DP5 step of ``blocks``; every other block still, except ``boundary`` {block: quartic}."""

    def acc(xs, vs, c):
        X = x.copy()
        X[blocks] = xs
        for b, co in boundary.items():
            t = th0 + c * h / hout
            X[b] = co[0] + t * (co[1] + t * (co[2] + t * (co[3] + t * co[4])))
        f = F0s[blocks] + K[blocks] @ X - diag[blocks] * xs
        den = np.maximum(1.0 + cfr[blocks] * vs, 0.5)
        return f - oms[blocks] / den

    x0 = x[blocks]
    kv, ka = [v0], [a0]
    for s in range(1, 6):
        xs = x0 + h * sum(float(c) * k for c, k in zip(_A[s], kv, strict=True))
        vs = v0 + h * sum(float(c) * k for c, k in zip(_A[s], ka, strict=True))
        kv.append(vs)
        ka.append(acc(xs, vs, float(_C[s])))
    x1 = x0 + h * sum(float(c) * k for c, k in zip(_B, kv, strict=True))
    v1 = v0 + h * sum(float(c) * k for c, k in zip(_B, ka, strict=True))
    return x1, v1, acc(x1, v1, 1.0), kv, ka


@pytest.mark.parametrize("uniform", [False, True])
@pytest.mark.parametrize("region", [False, True])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_step_matches_a_dense_reference(region, seed, uniform):
    """Heterogeneous springs, and equal ones (``k_uniform``: the stages' own force sum)."""
    rng = np.random.default_rng(seed)
    g = nx.convert_node_labels_to_integers(nx.triangular_lattice_graph(5, 8, periodic=True))
    n = g.number_of_nodes()
    K = np.zeros((n, n))
    for u, w in g.edges:
        K[u, w] = K[w, u] = 13.7 if uniform else rng.uniform(4.0, 20.0)
    diag = K.sum(1) + 1.0
    csr = scipy.sparse.csr_array(K)
    indptr, indices = csr.indptr.astype(np.int64), csr.indices.astype(np.int64)
    kval = csr.data
    oms = 1.0 - rng.uniform(0.005, 0.05, n)
    cfr = 2.0 * rng.uniform(0.5, 2.0, n) / oms
    # a connected cluster of slipping blocks, the rest stuck
    blocks = np.array(list(nx.bfs_tree(g, int(rng.integers(n)), depth_limit=2)))[:12]
    others = np.setdiff1d(np.arange(n), blocks)
    boundary = {}
    if region:
        # slipping neighbours of the cluster outside it follow a quartic in time
        ring = sorted({int(j) for i in blocks for j in g[i]} - set(blocks.tolist()))
        for b in ring[:4]:
            boundary[b] = rng.normal(0.0, 1e-3, 5)
    W = work_array(n, N_WORK)  # the stage rows below the blocks', then the ghost row
    IW = np.zeros((N_IWORK, n), dtype=np.int64)
    loc = np.zeros(LOC_SIZE)
    x = rng.normal(0.0, 1e-2, n)
    F0s = rng.uniform(0.5, 1.0, n)
    W[:n, D] = W[:n, P] = W[:n, P2] = x
    W[:n, F0] = F0s
    IW[FLAG, others] = STUCK
    q0 = len(boundary) + 3 if region else 0  # the outer list's slots come first
    for r, b in enumerate(boundary):
        IW[FLAG, b] = ACTIVE
        IW[APOS, b] = r  # its outer slot, outside the region's list
        IW[ACT, r] = b
        IW[BND, r] = b
        loc[LOC_CACHE + 5 * r : LOC_CACHE + 5 * r + 5] = boundary[b]
    th0, hout = 0.3, 0.1  # the region step starts at 0.3 of an outer step of length 0.1
    if region:
        loc[LOC_BND_START], loc[LOC_BND_END] = 0.0, len(boundary)
        loc[LOC_REGION_T], loc[LOC_OUTER_H] = th0, hout
    nact = q0 + len(blocks)
    IW[ACT, q0:nact] = blocks
    IW[APOS, blocks] = np.arange(q0, nact)
    IW[FLAG, blocks] = ACTIVE
    v0 = rng.uniform(0.0, 0.2, len(blocks))
    a0 = rng.normal(0.0, 1.0, len(blocks))
    W[blocks, V] = v0
    W[blocks, A] = a0
    h = 0.04
    before = W.copy()
    graph = graph_bundle(indptr, indices, kval, diag, oms, cfr)
    assert graph.k_uniform == (13.7 if uniform else 0.0)
    _step(h, q0, nact, IW, W, graph, loc)
    x1, v1, a1, kv, ka = _reference(
        h, blocks, x, v0, a0, F0s, K, diag, oms, cfr, boundary, th0, hout
    )
    # the same scheme in another order of operations: agreement to round-off
    np.testing.assert_allclose(W[blocks, DN], x1, rtol=0, atol=1e-14)
    np.testing.assert_allclose(W[blocks, VN], v1, rtol=0, atol=1e-13)
    np.testing.assert_allclose(W[blocks, AN], a1, rtol=0, atol=1e-12)
    for s in range(6):
        np.testing.assert_allclose(W[n + q0 : n + nact, KV + s], kv[s], rtol=0, atol=1e-13)
        np.testing.assert_allclose(W[n + q0 : n + nact, KA + s], ka[s], rtol=0, atol=1e-12)
    # the contract: P == P2 == DN on the stepped blocks; stuck blocks untouched
    np.testing.assert_array_equal(W[blocks, P], W[blocks, DN])
    np.testing.assert_array_equal(W[blocks, P2], W[blocks, DN])
    still = [j for j in others if j not in boundary]
    np.testing.assert_array_equal(W[still][:, [D, P, P2]], before[still][:, [D, P, P2]])
    np.testing.assert_array_equal(W[blocks, D], x[blocks])


def test_stage_columns_fit_a_row_of_the_work_array():
    """The stage rows below the blocks' rows of W hold KV + 0..5 and KA + 0..5."""
    assert 0 <= KV and KV + 6 <= KA and KA + 6 <= N_WORK
