"""The component search of local regions against a slow reference (networkx).

:func:`faultnet._kernels.local._component` splits the union of a step's
regions into groups of slipping blocks within three springs of each other
(paths through any block).  The oracle: connected components of the union in
the third power of the graph.
"""

import networkx as nx
import numba as nb
import numpy as np
import pytest

from faultnet import graphs
from faultnet._kernels.integrate import ACT, ACTIVE, APOS, FLAG, MARK, N_IWORK, REGION
from faultnet._kernels.local import _component


@nb.njit(cache=False)
def _call(s, cur, cid, q, IW, indptr, indices):
    # the kernel is built without a Python wrapper: called from compiled code
    return _component(s, cur, cid, q, IW, indptr, indices)


def _csr(g):
    nodes = list(g.nodes)
    a = nx.to_scipy_sparse_array(g, nodelist=nodes, format="csr")
    return nodes, a.indptr.astype(np.int64), a.indices.astype(np.int64)


def _kernel_components(n, indptr, indices, union, slipping, first_id=7):
    IW = np.zeros((N_IWORK, n), dtype=np.int64)
    IW[MARK, :] = np.arange(n) % 5 + 1  # stale positive marks from other searches
    IW[FLAG, slipping] = ACTIVE
    cur = first_id
    IW[REGION, union] = cur
    q0 = 3  # the components are listed after q0 (the outer active list)
    end = q0
    cid = cur
    parts = []
    for s in union:
        if IW[REGION, s] != cur:
            continue
        cid += 1
        new_end = _call(s, cur, cid, end, IW, indptr, indices)
        members = IW[ACT, end:new_end]
        assert (IW[REGION, members] == cid).all()
        assert (IW[APOS, members] == np.arange(end, new_end)).all()
        parts.append(frozenset(members.tolist()))
        end = new_end
    return set(parts)


def _reference_components(g, nodes, union):
    g3 = nx.power(g, 3)
    idx = {u: k for k, u in enumerate(nodes)}
    sub = g3.subgraph([nodes[i] for i in union])
    return {frozenset(idx[u] for u in c) for c in nx.connected_components(sub)}


@pytest.mark.parametrize(
    "graph",
    [
        graphs.square_lattice(30, 30, periodic=True),
        graphs.triangular_lattice(20, 20),
        graphs.ring(200),
    ],
    ids=["square", "triangular", "ring"],
)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_components_match_graph_power(graph, seed):
    rng = np.random.default_rng(seed)
    nodes, indptr, indices = _csr(graph)
    n = len(nodes)
    slipping = np.flatnonzero(rng.random(n) < 0.2)
    # the union: some slipping blocks (regions cover part of the active set)
    union = rng.permutation(slipping[rng.random(slipping.size) < 0.3])
    got = _kernel_components(n, indptr, indices, union, slipping)
    want = _reference_components(graph, nodes, union)
    assert got == want
    assert sum(len(c) for c in got) == union.size
    assert len(got) > 1  # the case splits
