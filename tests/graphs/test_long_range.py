"""Long-range chains and rings (``reach=``, ``k_c=``): Xia, Gould, Klein & Rundle's coupling."""

import math

import networkx as nx
import numpy as np
import pytest

import faultnet
from faultnet.exceptions import InvalidParameterError
from faultnet.graphs import chain, ring


def _pairs(G):
    return sorted(tuple(sorted(e)) for e in G.edges)


# ------------------------------------------------------------------------ structure


@pytest.mark.parametrize(("n", "reach"), [(5, 2), (7, 3), (40, 3), (2000, 10)])
def test_ring_blocks_have_2r_neighbours(n, reach):
    G = ring(n, reach=reach)
    assert list(G.nodes) == list(range(n))
    assert G.number_of_edges() == reach * n
    assert {d for _, d in G.degree()} == {2 * reach}
    assert sorted(G[0]) == sorted({d % n for d in range(-reach, reach + 1)} - {0})
    assert not any(data for _, _, data in G.edges(data=True))  # no k without k_c


@pytest.mark.parametrize(("n", "reach"), [(2, 1), (6, 2), (10, 3), (12, 11)])
def test_chain_springs_are_truncated_at_the_ends(n, reach):
    G = chain(n, reach=reach)
    want = [min(i, reach) + min(n - 1 - i, reach) for i in range(n)]
    assert [G.degree(i) for i in range(n)] == want
    assert _pairs(G) == [(i, j) for i in range(n) for j in range(i + 1, min(i + reach, n - 1) + 1)]
    assert [G.nodes[i]["pos"] for i in range(n)] == [(float(i), 0.0) for i in range(n)]


def test_ring_reach_at_its_limit_is_the_complete_graph_on_an_odd_ring():
    G = ring(9, reach=4)
    assert nx.is_isomorphic(G, nx.complete_graph(9))


# --------------------------------------------------------------------- spring constant


@pytest.mark.parametrize(("builder", "n"), [(ring, 30), (chain, 30)])
@pytest.mark.parametrize(("reach", "k_c"), [(1, 16.0), (3, 12), (10, 100)])
def test_every_edge_gets_k_c_over_2r(builder, n, reach, k_c):
    G = builder(n, reach=reach, k_c=k_c)
    ks = {data["k"] for _, _, data in G.edges(data=True)}
    assert ks == {k_c / (2 * reach)}  # the same on every edge, also at a chain's ends
    assert all(isinstance(k, float) for k in ks)


def test_xia_ring_stiffness_is_one_plus_k_c():
    k_c = 12
    model = faultnet.CarlsonLanger(ring(40, reach=3, k_c=k_c))
    np.testing.assert_allclose(model.stiffness, 1.0 + k_c, rtol=0, atol=1e-12)
    # the model's scalar k only fills edges without their own k: here none
    other = faultnet.CarlsonLanger(ring(40, reach=3, k_c=k_c), k=3.0)
    np.testing.assert_allclose(other.stiffness, 1.0 + k_c, rtol=0, atol=1e-12)


def test_chain_ends_keep_k_c_over_2r_and_so_are_softer():
    model = faultnet.CarlsonLanger(chain(10, reach=2, k_c=8))
    degree = np.array([2, 3, 4, 4, 4, 4, 4, 4, 3, 2])
    np.testing.assert_allclose(model.stiffness, 1.0 + 2.0 * degree)


# ------------------------------------------------------------------------------ names


@pytest.mark.parametrize(
    ("graph", "name"),
    [
        (lambda: ring(2000, reach=10, k_c=100), "ring(2000, reach=10, k_c=100)"),
        (lambda: ring(50, reach=3), "ring(50, reach=3)"),
        (lambda: ring(50, k_c=2.5), "ring(50, k_c=2.5)"),
        (lambda: chain(500, reach=3), "chain(500, reach=3)"),
        (lambda: chain(5, reach=1, k_c=16.0), "chain(5, k_c=16)"),
        (lambda: ring(7, reach=np.int64(2)), "ring(7, reach=2)"),
    ],
)
def test_names_record_reach_and_k_c(graph, name):
    assert graph().graph["name"] == name


# ------------------------------------------------------------- reach=1 is today's graph


@pytest.mark.parametrize("n", [1, 2, 3, 8])
def test_chain_with_reach_1_is_the_path(n):
    reference = nx.Graph(name=f"chain({n})")
    reference.add_nodes_from((i, {"pos": (float(i), 0.0)}) for i in range(n))
    reference.add_edges_from((i, i + 1) for i in range(n - 1))
    for G in (chain(n), chain(n, reach=1), chain(n, reach=1, k_c=None)):
        assert G.graph == reference.graph
        assert list(G.nodes(data=True)) == list(reference.nodes(data=True))
        assert list(G.edges(data=True)) == list(reference.edges(data=True))


@pytest.mark.parametrize("n", [3, 4, 9])
def test_ring_with_reach_1_is_the_cycle(n):
    reference = nx.Graph(name=f"ring({n})")
    radius = n / (2.0 * math.pi)
    for i in range(n):
        theta = 2.0 * math.pi * i / n
        reference.add_node(i, pos=(radius * math.cos(theta), radius * math.sin(theta)))
    reference.add_edges_from((i, (i + 1) % n) for i in range(n))
    for G in (ring(n), ring(n, reach=1), ring(n, reach=1, k_c=None)):
        assert G.graph == reference.graph
        assert list(G.nodes(data=True)) == list(reference.nodes(data=True))
        assert list(G.edges(data=True)) == list(reference.edges(data=True))


def test_reach_and_k_c_are_keyword_only():
    with pytest.raises(TypeError):
        ring(10, 2)
    with pytest.raises(TypeError):
        chain(10, 2, 4.0)


# --------------------------------------------------------------------------- refusals


@pytest.mark.parametrize(
    ("builder", "n", "reach", "pattern"),
    [
        (ring, 10, 5, r"1 <= reach <= \(n - 1\) // 2 = 4 for ring\(10\).*two springs.*reach=5"),
        (ring, 4, 2, r"reach <= \(n - 1\) // 2 = 1 for ring\(4\).*got reach=2"),
        (ring, 10, 0, r"reach must be an integer with 1 <= reach.*got reach=0"),
        (ring, 10, -1, r"got reach=-1"),
        (ring, 10, 2.0, r"reach must be an integer.*got reach=2\.0"),
        (ring, 10, "2", r"reach must be an integer.*got reach='2'"),
        (ring, 10, True, r"reach must be an integer.*got reach=True"),
        (ring, 10, None, r"reach must be an integer.*got reach=None"),
        (chain, 6, 6, r"1 <= reach <= max\(n - 1, 1\) = 5 for chain\(6\); got reach=6"),
        (chain, 1, 2, r"= 1 for chain\(1\); got reach=2"),
        (chain, 6, 0, r"reach must be an integer with 1 <= reach.*got reach=0"),
        (chain, 6, 1.5, r"got reach=1\.5"),
    ],
)
def test_bad_reach_is_refused(builder, n, reach, pattern):
    with pytest.raises(InvalidParameterError, match=pattern):
        builder(n, reach=reach)


@pytest.mark.parametrize("builder", [ring, chain])
@pytest.mark.parametrize(
    ("k_c", "shown"),
    [
        (0, "0"),
        (0.0, r"0\.0"),
        (-1.0, r"-1\.0"),
        (float("nan"), "nan"),
        (float("inf"), "inf"),
        ("100", "'100'"),
        (True, "True"),
        (1 + 2j, r"\(1\+2j\)"),
    ],
)
def test_bad_k_c_is_refused(builder, k_c, shown):
    with pytest.raises(
        InvalidParameterError,
        match=rf"k_c must be None \(no edge attribute k\) or a finite real number > 0; "
        rf"got k_c={shown}$",
    ):
        builder(10, reach=2, k_c=k_c)


def test_ring_size_is_checked_before_reach():
    with pytest.raises(InvalidParameterError, match=r"ring\(2\) would double the spring"):
        ring(2, reach=3)
