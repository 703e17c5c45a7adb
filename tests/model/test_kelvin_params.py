"""The plate's velocity during events (nu) and the springs' viscous coupling (eta): validation,
the per-spring values in the adjacency's CSR order, metadata, repr, forces, block classes."""

import math

import networkx as nx
import numpy as np
import pytest
import scipy.sparse as sp

import faultnet
from faultnet import CarlsonLanger, InvalidParameterError, SparseGraph
from faultnet.model.identity import graph_hash

#: the keys of ``params`` before nu and eta existed (a graph without frame springs)
OLD_PARAMS = {"graph", "n_blocks", "n_springs", "k", "sigma", "alpha", "heterogeneous"}


def _hand_built():
    """Four blocks with string labels, added out of order; per-edge eta on two springs."""
    g = nx.Graph()
    g.add_node("d")
    g.add_edge("b", "a", eta=0.3)
    g.add_edge("a", "c")
    g.add_edge("c", "d", eta=0.0, k=5.0)
    g.add_edge("d", "b", eta=2.0)
    return g


def _eta_of(model, g, default):
    """The eta of every stored entry of ``model.adjacency``, read off the graph by hand."""
    out = []
    for i in range(model.n):
        for p in range(model.adjacency.indptr[i], model.adjacency.indptr[i + 1]):
            a, b = model.nodes[i], model.nodes[model.adjacency.indices[p]]
            out.append(g.edges[a, b].get("eta", default))
    return out


def test_defaults_are_the_model_of_before():
    model = CarlsonLanger(faultnet.graphs.ring(6))
    assert model.nu == 0.0 and model.eta == 0.0 and not model.viscous
    assert model.eta_values.dtype == np.float64
    assert model.eta_values.shape == model.adjacency.data.shape
    assert not model.eta_values.any()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"nu": -0.1}, r"^nu must be finite and >= 0; got -0\.1$"),
        ({"nu": math.nan}, r"^nu must be finite and >= 0; got nan$"),
        ({"nu": math.inf}, r"^nu must be finite and >= 0; got inf$"),
        ({"nu": np.float64(-1.0)}, r"^nu must be finite and >= 0; got -1\.0$"),
        ({"nu": "0.01"}, r"^nu must be a real number; got '0\.01'$"),
        ({"nu": True}, r"^nu must be a real number; got True$"),
        ({"nu": None}, r"^nu must be a real number; got None$"),
        ({"eta": -2}, r"^eta must be finite and >= 0; got -2\.0$"),
        ({"eta": math.nan}, r"^eta must be finite and >= 0; got nan$"),
        ({"eta": -math.inf}, r"^eta must be finite and >= 0; got -inf$"),
        ({"eta": "x"}, r"^eta must be a real number; got 'x'$"),
    ],
)
def test_bad_nu_and_eta_are_refused_by_name(kwargs, match):
    with pytest.raises(InvalidParameterError, match=match):
        CarlsonLanger(faultnet.graphs.ring(4), **kwargs)


def test_numpy_scalars_and_integers_are_floats():
    model = CarlsonLanger(faultnet.graphs.ring(4), nu=np.float32(0.5), eta=np.int64(2))
    assert type(model.nu) is float and type(model.eta) is float
    assert (model.nu, model.eta) == (0.5, 2.0)


@pytest.mark.parametrize(
    "value, match",
    [
        (-1.0, r"eta must be finite and >= 0; got -1\.0 on edge \('b', 'a'\)"),
        (math.nan, r"eta must be finite and >= 0; got nan on edge \('b', 'a'\)"),
        ("0.1", r"eta must be a real number; got '0\.1' on edge \('b', 'a'\)"),
    ],
)
def test_a_bad_edge_attribute_names_its_edge(value, match):
    g = _hand_built()
    g.edges["b", "a"]["eta"] = value
    with pytest.raises(InvalidParameterError, match=match):
        CarlsonLanger(g, eta=0.1)


def test_eta_values_follow_the_adjacency_csr_order():
    g = _hand_built()
    model = CarlsonLanger(g, eta=0.1)
    assert model.nodes == ["d", "b", "a", "c"]
    adj = model.adjacency
    assert model.eta_values.tolist() == _eta_of(model, g, 0.1)
    # rows d, b, a, c; in each, the columns in that order
    assert model.eta_values.tolist() == [2.0, 0.0, 2.0, 0.3, 0.3, 0.1, 0.0, 0.1]
    # the same pattern as the springs (the k = 5 spring keeps its zero eta in place) ...
    eta = sp.csr_matrix((model.eta_values, adj.indices, adj.indptr), shape=adj.shape)
    assert (eta != eta.T).nnz == 0
    assert eta[model.nodes.index("c"), model.nodes.index("d")] == 0.0
    assert adj[model.nodes.index("c"), model.nodes.index("d")] == 5.0
    # ... however the graph was built
    h = nx.Graph()
    h.add_edges_from(reversed(list(g.edges(data=True))))
    other = CarlsonLanger(h, eta=0.1)
    assert other.eta_values.tolist() == _eta_of(other, h, 0.1)
    assert model.viscous and other.viscous


def test_zero_eta_on_every_edge_is_not_viscous():
    g = faultnet.graphs.ring(5)
    nx.set_edge_attributes(g, 0.0, "eta")
    model = CarlsonLanger(g, eta=0.5)
    assert not model.viscous and not model.eta_values.any()
    assert CarlsonLanger(faultnet.graphs.ring(5), eta=0.5).viscous


def test_sparse_graph_eta_matrix_and_scalar():
    adj = np.array([[0, 1, 1, 0], [1, 0, 0, 1], [1, 0, 0, 1], [0, 1, 1, 0.0]])
    eta = np.zeros((4, 4))
    eta[0, 2] = eta[2, 0] = 0.7
    eta[1, 3] = eta[3, 1] = 0.2
    model = CarlsonLanger(SparseGraph(adj, eta=sp.csr_matrix(eta)), eta=1.0)
    # stored entries (0,1) (0,2) (1,0) (1,3) (2,0) (2,3) (3,1) (3,2); absent entries are 0
    assert model.eta_values.tolist() == [0.0, 0.7, 0.0, 0.2, 0.7, 0.0, 0.2, 0.0]
    assert model.params["eta"] == 1.0 and model.params["eta_heterogeneous"]
    plain = CarlsonLanger(SparseGraph(adj), eta=0.25)
    assert plain.eta_values.tolist() == [0.25] * 8
    assert not plain.params["eta_heterogeneous"]
    assert not CarlsonLanger(SparseGraph(adj)).viscous


def test_sparse_graph_eta_equals_the_networkx_build():
    g = nx.Graph()
    g.add_nodes_from(range(9))
    rng = np.random.default_rng(3)
    for a, b in nx.grid_2d_graph(3, 3).edges():
        g.add_edge(3 * a[0] + a[1], 3 * b[0] + b[1], eta=float(rng.uniform(0.1, 1.0)))
    A = nx.to_scipy_sparse_array(g, nodelist=range(9), weight=None)
    E = nx.to_scipy_sparse_array(g, nodelist=range(9), weight="eta")
    a, b = CarlsonLanger(g), CarlsonLanger(SparseGraph(A, eta=E))
    np.testing.assert_array_equal(a.adjacency.indices, b.adjacency.indices)
    np.testing.assert_array_equal(a.eta_values, b.eta_values)
    assert graph_hash(a) == graph_hash(b)


@pytest.mark.parametrize(
    "eta, match",
    [
        ([[0, 0, 1.0], [0, 0, 0], [1.0, 0, 0]], "no spring links"),
        ([[0, 0.5, 0], [0.4, 0, 0], [0, 0, 0]], "symmetric"),
        ([[0, -0.5, 0], [-0.5, 0, 0], [0, 0, 0]], r"eta must be finite and >= 0.*edge \(0, 1\)"),
        ([[0, np.nan, 0], [np.nan, 0, 0], [0, 0, 0]], "eta must be finite"),
        (np.zeros((2, 2)), "shape"),
    ],
)
def test_sparse_graph_bad_eta(eta, match):
    adj = np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0.0]])
    with pytest.raises(InvalidParameterError, match=match):
        SparseGraph(adj, eta=np.asarray(eta, dtype=float))


@pytest.mark.parametrize("kwargs", [{}, {"nu": 0.0, "eta": 0.0}, {"nu": np.float64(0), "eta": 0}])
def test_metadata_of_runs_without_nu_and_eta_is_unchanged(kwargs):
    model = CarlsonLanger(faultnet.graphs.ring(5), **kwargs)
    assert set(model.params) == OLD_PARAMS
    assert repr(model) == ("CarlsonLanger(graph='ring(5)', n=5, k=16.0, sigma=0.01, alpha=1.0)")
    assert graph_hash(model) == graph_hash(CarlsonLanger(faultnet.graphs.ring(5)))


def test_metadata_and_repr_with_nu_and_eta():
    model = CarlsonLanger(faultnet.graphs.ring(5), nu=0.01, eta=0.1)
    assert model.params == {
        "graph": "ring(5)", "n_blocks": 5, "n_springs": 5, "k": 16.0, "sigma": 0.01,
        "alpha": 1.0, "heterogeneous": False, "nu": 0.01, "eta": 0.1,
        "eta_heterogeneous": False,
    }  # fmt: skip
    assert repr(model) == (
        "CarlsonLanger(graph='ring(5)', n=5, k=16.0, sigma=0.01, alpha=1.0, nu=0.01, eta=0.1)"
    )
    only_nu = CarlsonLanger(faultnet.graphs.ring(5), nu=0.01)
    assert set(only_nu.params) == OLD_PARAMS | {"nu"}
    assert repr(only_nu).endswith("alpha=1.0, nu=0.01)")
    g = _hand_built()  # per-edge eta and a scalar of 0
    het = CarlsonLanger(g)
    assert het.params["eta"] == 0.0 and het.params["eta_heterogeneous"] is True
    assert set(het.params) == OLD_PARAMS | {"eta", "eta_heterogeneous"}
    assert repr(het).endswith("alpha=1.0, eta=0.0)")


def test_with_params_keeps_or_replaces_nu_and_eta():
    g = _hand_built()
    model = CarlsonLanger(g, nu=0.01, eta=0.1)
    same = model.with_params(alpha=2.0)
    assert (same.nu, same.eta, same.alpha) == (0.01, 0.1, 2.0)
    np.testing.assert_array_equal(same.eta_values, model.eta_values)
    other = model.with_params(nu=0.0, eta=0.5)
    assert (other.nu, other.eta) == (0.0, 0.5)
    assert other.eta_values.tolist() == _eta_of(other, g, 0.5)  # the edges' eta still win
    with pytest.raises(InvalidParameterError, match="nu must be finite"):
        model.with_params(nu=-1.0)


def test_graph_hash_covers_nu_and_every_eta():
    g = _hand_built()
    base = CarlsonLanger(g, eta=0.1)
    hashes = {
        graph_hash(base),
        graph_hash(base.with_params(nu=0.01)),
        graph_hash(base.with_params(nu=0.02)),
        graph_hash(base.with_params(eta=0.2)),
    }
    g2 = _hand_built()
    g2.edges["b", "a"]["eta"] = 0.31  # one spring's dashpot
    hashes.add(graph_hash(CarlsonLanger(g2, eta=0.1)))
    assert len(hashes) == 5
    assert graph_hash(base) == graph_hash(CarlsonLanger(_hand_built(), eta=0.1))


def test_forces_with_velocities():
    g = _hand_built()
    model = CarlsonLanger(g, k=2.0, eta=0.1)
    rng = np.random.default_rng(0)
    x, v, u = rng.uniform(0, 0.1, 4), rng.uniform(0, 1, 4), 0.4
    index = {node: i for i, node in enumerate(model.nodes)}
    expected = []
    for node in model.nodes:
        i = index[node]
        f = u - x[i]
        for nbr, data in g[node].items():
            j = index[nbr]
            f += data.get("k", 2.0) * (x[j] - x[i]) + data.get("eta", 0.1) * (v[j] - v[i])
        expected.append(f)
    np.testing.assert_allclose(model.forces(x, u, v=v), expected, rtol=1e-13)
    np.testing.assert_allclose(model.forces(x, u), model.forces(x, u, v=np.zeros(4)))
    plain = CarlsonLanger(faultnet.graphs.ring(4), k=2.0)  # no dashpots: v changes nothing
    np.testing.assert_array_equal(plain.forces(x, u, v=v), plain.forces(x, u))


def test_block_classes_separate_blocks_by_their_total_eta():
    g = faultnet.graphs.ring(6)
    assert CarlsonLanger(g).block_classes.tolist() == [0] * 6
    assert CarlsonLanger(g, eta=0.3).block_classes.tolist() == [0] * 6  # 0.6 each
    g.edges[0, 1]["eta"] = 1.0
    classes = CarlsonLanger(g, eta=0.3).block_classes
    assert classes[0] == classes[1] != classes[2]
    assert len(set(classes[2:].tolist())) == 1
    h = faultnet.graphs.ring(6)
    h.edges[0, 1]["eta"] = 0.0
    h.edges[3, 4]["eta"] = 0.0
    classes = CarlsonLanger(h, eta=0.3).block_classes  # totals 0.3, 0.3, 0.6, 0.3, 0.3, 0.6
    assert classes.tolist() == [0, 0, 1, 0, 0, 1]
