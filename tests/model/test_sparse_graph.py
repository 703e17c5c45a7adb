"""SparseGraph: lattices without networkx, same physics and numbering."""

import networkx as nx
import numpy as np
import pytest
import scipy.sparse as sp

import faultnet
from faultnet.exceptions import InvalidParameterError
from faultnet.runs import specs


@pytest.mark.parametrize("periodic", [False, True])
def test_square_lattice_sparse_equals_networkx(periodic):
    G = faultnet.graphs.square_lattice(5, 7, periodic=periodic)
    S = faultnet.graphs.square_lattice(5, 7, periodic=periodic, sparse=True)
    A = nx.to_scipy_sparse_array(G, nodelist=range(35))
    assert abs(A - S.adjacency).max() == 0
    assert S.number_of_edges() == G.number_of_edges()
    assert S.graph["name"] == G.graph["name"]


def test_simulation_identical_to_networkx_build():
    a = faultnet.CarlsonLanger(faultnet.graphs.square_lattice(20, 20, periodic=True), k=16)
    b = faultnet.CarlsonLanger(
        faultnet.graphs.square_lattice(20, 20, periodic=True, sparse=True), k=16
    )
    ra = faultnet.simulate(a, 2000, rng=4, progress=False, record_slips=True)
    rb = faultnet.simulate(b, 2000, rng=4, progress=False, record_slips=True)
    np.testing.assert_array_equal(ra.events.S, rb.events.S)
    np.testing.assert_array_equal(ra.events.hypocenter, rb.events.hypocenter)
    np.testing.assert_array_equal(ra.slips.node, rb.slips.node)
    assert rb.events.hypocenter.dtype == np.int64
    assert faultnet.model.identity.graph_hash(a) == faultnet.model.identity.graph_hash(b)


def test_values_multiply_k_and_per_block_parameters():
    adj = sp.csr_matrix(np.array([[0, 1, 0], [1, 0, 2.0], [0, 2.0, 0]]))
    g = faultnet.SparseGraph(adj, alpha=[0.5, 1.0, 2.0])
    m = faultnet.CarlsonLanger(g, k=10, sigma=0.02)
    np.testing.assert_array_equal(m.adjacency.toarray(), 10 * adj.toarray())
    np.testing.assert_array_equal(m.alpha_values, [0.5, 1.0, 2.0])
    np.testing.assert_array_equal(m.sigma_values, [0.02] * 3)
    assert m.params["heterogeneous"]
    assert m.with_params(sigma=0.05).sigma_values[0] == 0.05


@pytest.mark.parametrize(
    "adj, kwargs, match",
    [
        (np.array([[0, 1], [0, 0.0]]), {}, "symmetric"),
        (np.array([[1, 1], [1, 0.0]]), {}, "diagonal"),
        (np.array([[0, -1], [-1, 0.0]]), {}, "finite and > 0"),
        (np.zeros((2, 3)), {}, "square"),
        (np.array([[0, 1], [1, 0.0]]), {"sigma": [0.5]}, "shape"),
    ],
)
def test_bad_adjacency(adj, kwargs, match):
    with pytest.raises(InvalidParameterError, match=match):
        faultnet.SparseGraph(adj, **kwargs)


@pytest.mark.parametrize("name, values", [("sigma", [0.5, 1.5]), ("alpha", [0.5, -1.0])])
def test_bad_per_block_parameters_name_the_block(name, values):
    g = faultnet.SparseGraph(np.array([[0, 1], [1, 0.0]]), **{name: values})
    with pytest.raises(InvalidParameterError, match=f"{name}.*at node 1"):
        faultnet.CarlsonLanger(g)


def test_graph_spec_switches_to_sparse_for_big_square_lattices(monkeypatch):
    monkeypatch.setattr(specs, "SPARSE_LATTICE_BLOCKS", 100)
    big = specs.build_graph("square:10x10:periodic")
    small = specs.build_graph("square:9x9:periodic")
    assert isinstance(big, faultnet.SparseGraph) and isinstance(small, nx.Graph)
    assert big.graph["spec"] == "square:10x10:periodic"
    model = specs.build_model("square:10x10:periodic", alpha=2.0)
    assert model.n == 100 and model.alpha == 2.0
