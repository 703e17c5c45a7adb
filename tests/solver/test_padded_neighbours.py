"""The padded neighbour table of the Graph bundle, and the force sum that reads it.

Where every spring is equal, the DP5 stages and the join scan (``force_hot``) sum the
neighbours' positions over ``Graph.nbr``, padded with the ghost row of W to the largest
degree.  The sum must be the CSR-order sum bit for bit; a graph with hubs gets no table and
the general ``force``.
"""

import networkx as nx
import numba as nb
import numpy as np
import pytest

from faultnet.solver._kernels.bundles import DIAG, graph_bundle, padded_neighbours, work_array
from faultnet.solver._kernels.carlson_langer.physics import force, force_hot
from faultnet.solver._kernels.carlson_langer.work import F0, N_WORK, P


@nb.njit(cache=False)
def _forces(W, graph):
    """(force, force_hot) of every block at the positions in column P."""
    n = graph.block.shape[0]
    out = np.empty((n, 2))
    for i in range(n):
        out[i, 0] = force(i, P, W, graph)
        out[i, 1] = force_hot(i, P, W, graph)
    return out


def _bundle(g, k, rng):
    adj = nx.to_scipy_sparse_array(g, nodelist=range(g.number_of_nodes()), format="csr")
    n = adj.shape[0]
    kval = np.full(adj.nnz, k)
    diag = 1.0 + k * np.diff(adj.indptr)
    return graph_bundle(adj.indptr, adj.indices, kval, diag, np.full(n, 0.99), np.full(n, 2.0))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_uniform_force_is_the_csr_sum_bit_for_bit(seed):
    """A percolation cluster of the triangular lattice: degrees 1 to 6."""
    rng = np.random.default_rng(seed)
    tri = nx.convert_node_labels_to_integers(nx.triangular_lattice_graph(12, 20))
    keep = rng.random(tri.number_of_nodes()) < 0.7
    g = nx.convert_node_labels_to_integers(tri.subgraph(np.flatnonzero(keep).tolist()))
    graph = _bundle(g, 9.5, rng)
    n, deg = g.number_of_nodes(), np.diff(graph.indptr)
    assert graph.k_uniform == 9.5 and graph.nbr.shape == (n, deg.max()) and deg.min() < deg.max()
    W = work_array(n, N_WORK)
    W[:n, P] = rng.normal(0.0, 1e-2, n)
    W[:n, F0] = rng.uniform(0.5, 1.0, n)
    got = _forces(W, graph)
    for i in range(n):
        s = 0.0
        for p in range(graph.indptr[i], graph.indptr[i + 1]):
            s += W[graph.indices[p], P]
        assert got[i, 1] == W[i, F0] + 9.5 * s - graph.block[i, DIAG] * W[i, P]  # bit for bit
        # the general force (kval per spring) agrees to round-off
        assert got[i, 0] == pytest.approx(got[i, 1], rel=0, abs=1e-14)
    assert not W[2 * n].any()  # the ghost row stays zero


def test_table_pads_with_the_ghost_row():
    g = nx.path_graph(4)
    g.add_edge(1, 3)  # degrees 1, 3, 2, 2
    adj = nx.to_scipy_sparse_array(g, nodelist=range(4), format="csr")
    nbr = padded_neighbours(adj.indptr, adj.indices)
    assert nbr.tolist() == [[1, 8, 8], [0, 2, 3], [1, 3, 8], [1, 2, 8]]
    # equal degrees (a ring, a periodic lattice): the CSR rows themselves, no ghost
    ring = nx.to_scipy_sparse_array(nx.cycle_graph(6), format="csr")
    nbr = padded_neighbours(ring.indptr, ring.indices)
    assert nbr.tolist() == ring.indices.reshape(6, 2).tolist()


def test_a_graph_with_hubs_gets_no_table_and_the_general_force():
    rng = np.random.default_rng(3)
    g = nx.cycle_graph(40)
    g.add_edges_from((0, j) for j in range(2, 39))  # block 0 tied to every other block
    graph = _bundle(g, 4.0, rng)
    assert graph.nbr.shape == (40, 0) and graph.k_uniform == 0.0
    W = work_array(40, N_WORK)
    W[:40, P] = rng.normal(0.0, 1e-2, 40)
    got = _forces(W, graph)
    np.testing.assert_array_equal(got[:, 0], got[:, 1])
    adj = nx.to_numpy_array(g, nodelist=range(40))
    want = W[:40, F0] + 4.0 * adj @ W[:40, P] - graph.block[:, DIAG] * W[:40, P]
    np.testing.assert_allclose(got[:, 0], want, rtol=0, atol=1e-14)
