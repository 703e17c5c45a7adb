"""The DP5 step kernel against a dense NumPy Dormand-Prince step.

The kernel evaluates forces through the graph's CSR rows (or the padded neighbour table
where every spring is equal), on stage positions that ping-pong between two columns.  The
reference here builds the full force from a dense spring matrix at every stage, with the
tableau written out from Dormand & Prince (1980).
"""

from fractions import Fraction as Fr

import networkx as nx
import numba as nb
import numpy as np
import pytest
import scipy.sparse

from faultnet.solver._kernels.bundles import Work, graph_bundle, work_array
from faultnet.solver._kernels.carlson_langer.dopri import dopri_step
from faultnet.solver._kernels.carlson_langer.tableau import KA, KV
from faultnet.solver._kernels.carlson_langer.work import (
    ACT,
    ACTIVE,
    AN,
    APOS,
    DN,
    F0,
    FLAG,
    LOC_SIZE,
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
from faultnet.solver._kernels.layout import CNT_SIZE

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
def _step(h, nact, IW, W, graph):
    work = Work(W, IW, np.zeros(LOC_SIZE), np.zeros(CNT_SIZE, dtype=np.int64))
    return dopri_step(h, nact, 0, 1e6, graph, work)


def _reference(h, blocks, x, v0, a0, F0s, K, diag, oms, cfr):
    """DP5 step of ``blocks``; every other block still."""

    def acc(xs, vs):
        X = x.copy()
        X[blocks] = xs
        f = F0s[blocks] + K[blocks] @ X - diag[blocks] * xs
        den = np.maximum(1.0 + cfr[blocks] * vs, 0.5)
        return f - oms[blocks] / den

    x0 = x[blocks]
    kv, ka = [v0], [a0]
    for s in range(1, 6):
        xs = x0 + h * sum(float(c) * k for c, k in zip(_A[s], kv, strict=True))
        vs = v0 + h * sum(float(c) * k for c, k in zip(_A[s], ka, strict=True))
        kv.append(vs)
        ka.append(acc(xs, vs))
    x1 = x0 + h * sum(float(c) * k for c, k in zip(_B, kv, strict=True))
    v1 = v0 + h * sum(float(c) * k for c, k in zip(_B, ka, strict=True))
    return x1, v1, acc(x1, v1), kv, ka


@pytest.mark.parametrize("uniform", [False, True])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_step_matches_a_dense_reference(seed, uniform):
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
    W = work_array(n, N_WORK)  # the stage rows below the blocks', then the ghost row
    IW = np.zeros((N_IWORK, n), dtype=np.int64)
    x = rng.normal(0.0, 1e-2, n)
    F0s = rng.uniform(0.5, 1.0, n)
    W[:n, D] = W[:n, P] = W[:n, P2] = x
    W[:n, F0] = F0s
    IW[FLAG, others] = STUCK
    nact = len(blocks)
    IW[ACT, :nact] = blocks
    IW[APOS, blocks] = np.arange(nact)
    IW[FLAG, blocks] = ACTIVE
    v0 = rng.uniform(0.0, 0.2, len(blocks))
    a0 = rng.normal(0.0, 1.0, len(blocks))
    W[blocks, V] = v0
    W[blocks, A] = a0
    h = 0.04
    before = W.copy()
    graph = graph_bundle(indptr, indices, kval, diag, oms, cfr)
    assert graph.k_uniform == (13.7 if uniform else 0.0)
    _step(h, nact, IW, W, graph)
    x1, v1, a1, kv, ka = _reference(h, blocks, x, v0, a0, F0s, K, diag, oms, cfr)
    # the same scheme in another order of operations: agreement to round-off
    np.testing.assert_allclose(W[blocks, DN], x1, rtol=0, atol=1e-14)
    np.testing.assert_allclose(W[blocks, VN], v1, rtol=0, atol=1e-13)
    np.testing.assert_allclose(W[blocks, AN], a1, rtol=0, atol=1e-12)
    for s in range(6):
        np.testing.assert_allclose(W[n : n + nact, KV + s], kv[s], rtol=0, atol=1e-13)
        np.testing.assert_allclose(W[n : n + nact, KA + s], ka[s], rtol=0, atol=1e-12)
    # the contract: P == P2 == DN on the stepped blocks; stuck blocks untouched
    np.testing.assert_array_equal(W[blocks, P], W[blocks, DN])
    np.testing.assert_array_equal(W[blocks, P2], W[blocks, DN])
    np.testing.assert_array_equal(W[others][:, [D, P, P2]], before[others][:, [D, P, P2]])
    np.testing.assert_array_equal(W[blocks, D], x[blocks])


def test_reference_tableau_is_consistent():
    """The reference's tableau: each row of A sums to its stage time, the weights to 1."""
    assert [sum(row, Fr(0)) for row in _A] == _C
    assert sum(_B, Fr(0)) == 1


def test_stage_columns_fit_a_row_of_the_work_array():
    """The stage rows below the blocks' rows of W hold KV + 0..5 and KA + 0..5."""
    assert 0 <= KV and KV + 6 <= KA and KA + 6 <= N_WORK
