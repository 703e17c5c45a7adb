"""CarlsonLanger: operators, per-edge/per-node attributes, and bad input."""

import math

import networkx as nx
import numpy as np
import pytest

import faultnet
from faultnet import CarlsonLanger, InvalidParameterError


def test_laplacian_and_forces_match_the_definition():
    g = faultnet.graphs.ring(6)
    g.edges[0, 1]["k"] = 3.0
    model = CarlsonLanger(g, k=16)
    x = np.linspace(0.0, 0.05, 6)
    u = 0.7
    expected = [
        sum(model.adjacency[i, j] * (x[j] - x[i]) for j in g.neighbors(i)) + (u - x[i])
        for i in range(6)
    ]
    np.testing.assert_allclose(model.forces(x, u), expected, rtol=1e-14)
    assert model.adjacency[0, 1] == model.adjacency[1, 0] == 3.0
    assert model.adjacency[1, 2] == 16.0
    np.testing.assert_allclose(model.laplacian.sum(axis=1), 0.0, atol=1e-12)
    np.testing.assert_allclose(
        model.stiffness, 1.0 + np.asarray(model.adjacency.sum(axis=1)).ravel()
    )


def test_node_attributes_and_fallbacks():
    g = nx.Graph()
    g.add_edge("a", "b")
    g.add_node("c")
    g.nodes["a"]["sigma"] = 0.05
    g.nodes["b"]["alpha"] = 0.3
    model = CarlsonLanger(g, sigma=0.01, alpha=2.0)
    assert model.nodes == ["a", "b", "c"]
    np.testing.assert_array_equal(model.sigma_values, [0.05, 0.01, 0.01])
    np.testing.assert_array_equal(model.alpha_values, [2.0, 0.3, 2.0])
    assert model.params["heterogeneous"]
    assert model.with_params(alpha=1.0).alpha_values.tolist() == [1.0, 0.3, 1.0]


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"sigma": 0.0}, "sigma.*0.0"),
        ({"sigma": 1.0}, "sigma.*1.0"),
        ({"sigma": -0.5}, "sigma.*-0.5"),
        ({"sigma": math.nan}, "sigma"),
        ({"alpha": -0.1}, "alpha.*-0.1"),
        ({"alpha": math.inf}, "alpha"),
        ({"k": 0.0}, "k.*0.0"),
        ({"k": -3.0}, "k.*-3.0"),
        ({"k": math.inf}, "k.*inf"),
        ({"k": "16"}, "k.*'16'"),
    ],
)
def test_bad_scalars(kwargs, match):
    with pytest.raises(InvalidParameterError, match=match):
        CarlsonLanger(faultnet.graphs.ring(4), **kwargs)


def test_bad_attributes_name_the_place():
    g = faultnet.graphs.chain(3)
    g.edges[1, 2]["k"] = -1.0
    with pytest.raises(InvalidParameterError, match=r"k.*-1.0.*edge \(1, 2\)"):
        CarlsonLanger(g)
    g = faultnet.graphs.chain(3)
    g.nodes[2]["sigma"] = 1.5
    with pytest.raises(InvalidParameterError, match="sigma.*1.5.*node 2"):
        CarlsonLanger(g)
    g = faultnet.graphs.chain(3)
    g.nodes[0]["alpha"] = -2
    with pytest.raises(InvalidParameterError, match="alpha.*node 0"):
        CarlsonLanger(g)


def test_bad_graphs():
    with pytest.raises(InvalidParameterError, match="empty"):
        CarlsonLanger(nx.Graph())
    g = faultnet.graphs.chain(3)
    g.add_edge(1, 1)
    with pytest.raises(InvalidParameterError, match="self-loops.*\\(1, 1\\)"):
        CarlsonLanger(g)
    with pytest.raises(InvalidParameterError, match="undirected"):
        CarlsonLanger(nx.DiGraph([(0, 1)]))
    with pytest.raises(InvalidParameterError, match="networkx.Graph"):
        CarlsonLanger([[0, 1]])
