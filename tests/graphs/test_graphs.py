"""Tests for faultnet.graphs.builders: lattice constructors and site percolation."""

import math

import networkx as nx
import numpy as np
import pytest

from faultnet.exceptions import InvalidParameterError
from faultnet.graphs import (
    chain,
    percolation_threshold,
    ring,
    site_percolation,
    square_lattice,
    triangular_lattice,
)


def _edge_lengths(G):
    return np.array([math.dist(G.nodes[u]["pos"], G.nodes[v]["pos"]) for u, v in G.edges])


def _has_pos_everywhere(G):
    return all(
        isinstance(pos, tuple) and len(pos) == 2 and all(isinstance(x, float) for x in pos)
        for _, pos in G.nodes(data="pos")
    )


@pytest.fixture(scope="module")
def square150():
    return square_lattice(150, 150)


# --------------------------------------------------------------------- chain / ring


@pytest.mark.parametrize("n", [1, 2, 7])
def test_chain_structure(n):
    G = chain(n)
    assert list(G.nodes) == list(range(n))
    assert G.number_of_edges() == n - 1
    assert all(G.has_edge(i, i + 1) for i in range(n - 1))
    assert [G.nodes[i]["pos"] for i in range(n)] == [(float(i), 0.0) for i in range(n)]
    assert G.graph["name"] == f"chain({n})"


@pytest.mark.parametrize("n", [3, 4, 50])
def test_ring_structure(n):
    G = ring(n)
    assert list(G.nodes) == list(range(n))
    assert G.number_of_edges() == n
    assert all(d == 2 for _, d in G.degree())
    assert nx.is_connected(G)
    assert _has_pos_everywhere(G)
    assert G.graph["name"] == f"ring({n})"


def test_ring_neighbours_about_one_apart():
    lengths = _edge_lengths(ring(2000))
    np.testing.assert_allclose(lengths, 1.0, atol=1e-5)


@pytest.mark.parametrize("n", [1, 2])
def test_ring_too_small_suggests_chain(n):
    with pytest.raises(
        InvalidParameterError, match=rf"ring\({n}\) would double the spring.*chain\({n}\)"
    ):
        ring(n)


# ----------------------------------------------------------------------- lattices


@pytest.mark.parametrize(("rows", "cols"), [(1, 1), (1, 5), (4, 1), (3, 4), (7, 5)])
def test_open_square_lattice(rows, cols):
    G = square_lattice(rows, cols)
    assert G.number_of_nodes() == rows * cols
    assert G.number_of_edges() == 2 * rows * cols - rows - cols
    assert _has_pos_everywhere(G)
    for r in range(rows):
        for c in range(cols):
            assert G.nodes[r * cols + c]["pos"] == (float(c), float(r))
    if G.number_of_edges():
        np.testing.assert_allclose(_edge_lengths(G), 1.0)
    assert G.graph["name"] == f"square_lattice({rows}, {cols})"


@pytest.mark.parametrize(("rows", "cols"), [(3, 3), (3, 5), (6, 4)])
def test_periodic_square_lattice(rows, cols):
    G = square_lattice(rows, cols, periodic=True)
    assert G.number_of_nodes() == rows * cols
    assert G.number_of_edges() == 2 * rows * cols
    assert {d for _, d in G.degree()} == {4}
    assert nx.number_of_selfloops(G) == 0
    assert _has_pos_everywhere(G)
    assert G.graph["name"] == f"square_lattice({rows}, {cols}, periodic=True)"


@pytest.mark.parametrize(("rows", "cols"), [(2, 5), (5, 2), (1, 1)])
def test_periodic_square_lattice_too_small(rows, cols):
    with pytest.raises(InvalidParameterError, match="duplicate edges"):
        square_lattice(rows, cols, periodic=True)


@pytest.mark.parametrize(("rows", "cols"), [(1, 1), (1, 4), (2, 2), (5, 6), (8, 7)])
def test_open_triangular_lattice(rows, cols):
    G = triangular_lattice(rows, cols)
    assert G.number_of_nodes() == rows * cols
    assert _has_pos_everywhere(G)
    for r in range(rows):
        for c in range(cols):
            x, y = G.nodes[r * cols + c]["pos"]
            assert x == pytest.approx(c + 0.5 * (r % 2))
            assert y == pytest.approx(r * math.sqrt(3) / 2)
    if G.number_of_edges():
        np.testing.assert_allclose(_edge_lengths(G), 1.0)
    for r in range(1, rows - 1):
        for c in range(1, cols - 1):
            assert G.degree(r * cols + c) == 6
    # every pair of nodes at distance 1 is connected (no bond missing)
    pos = np.array([G.nodes[i]["pos"] for i in range(rows * cols)])
    dist = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=-1)
    expected = {(i, j) for i, j in zip(*np.nonzero(np.isclose(dist, 1.0)), strict=True) if i < j}
    assert {tuple(sorted(e)) for e in G.edges} == expected


@pytest.mark.parametrize(("rows", "cols"), [(4, 3), (4, 4), (6, 5), (10, 10)])
def test_periodic_triangular_lattice(rows, cols):
    G = triangular_lattice(rows, cols, periodic=True)
    assert G.number_of_nodes() == rows * cols
    assert G.number_of_edges() == 3 * rows * cols
    assert {d for _, d in G.degree()} == {6}
    assert nx.number_of_selfloops(G) == 0
    assert _has_pos_everywhere(G)
    assert G.graph["name"] == f"triangular_lattice({rows}, {cols}, periodic=True)"


@pytest.mark.parametrize(("rows", "cols"), [(5, 4), (3, 4), (2, 4), (4, 2)])
def test_periodic_triangular_lattice_invalid(rows, cols):
    with pytest.raises(InvalidParameterError, match=rf"even rows >= 4 and cols >= 3.*rows={rows}"):
        triangular_lattice(rows, cols, periodic=True)


@pytest.mark.parametrize(
    ("func", "args", "exc", "pattern"),
    [
        (chain, (0,), InvalidParameterError, r"n must be .*got 0"),
        (chain, (2.5,), InvalidParameterError, r"n must be an integer.*2\.5"),
        (chain, (True,), InvalidParameterError, r"n must be an integer.*True"),
        (ring, ("5",), InvalidParameterError, r"n must be an integer.*'5'"),
        (square_lattice, (0, 4), InvalidParameterError, r"rows must be .*got 0"),
        (square_lattice, (4, -2), InvalidParameterError, r"cols must be .*got -2"),
        (square_lattice, (4, 3.0), InvalidParameterError, r"cols must be an integer.*3\.0"),
        (triangular_lattice, (False, 3), InvalidParameterError, r"rows must be an integer.*False"),
        (triangular_lattice, (3, 0), InvalidParameterError, r"cols must be .*got 0"),
    ],
)
def test_bad_sizes_raise_with_value(func, args, exc, pattern):
    with pytest.raises(exc, match=pattern):
        func(*args)


def test_numpy_integers_accepted():
    G = square_lattice(np.int64(3), np.int32(4))
    assert G.number_of_nodes() == 12
    assert G.graph["name"] == "square_lattice(3, 4)"


def test_percolation_threshold():
    assert percolation_threshold("square") == 0.592746
    assert percolation_threshold("triangular") == 0.5
    with pytest.raises(InvalidParameterError, match="'honeycomb'"):
        percolation_threshold("honeycomb")


# ---------------------------------------------------------------- site percolation


def test_percolation_reproducible_with_seed():
    L = square_lattice(30, 30)
    a = site_percolation(L, 0.6, rng=42, keep="all")
    b = site_percolation(L, 0.6, rng=42, keep="all")
    c = site_percolation(L, 0.6, rng=43, keep="all")
    assert list(a.nodes) == list(b.nodes)
    assert set(a.edges) == set(b.edges)
    assert set(a.nodes) != set(c.nodes)


def test_percolation_rng_forms_agree():
    L = square_lattice(20, 20)
    from_int = site_percolation(L, 0.5, rng=7, keep="all")
    from_gen = site_percolation(L, 0.5, rng=np.random.default_rng(7), keep="all")
    ss = np.random.SeedSequence(7)
    from_ss = site_percolation(L, 0.5, rng=ss, keep="all")
    assert list(from_int) == list(from_gen) == list(from_ss)
    assert from_int.graph["seed"] == 7
    assert from_gen.graph["seed"] is None
    assert from_ss.graph["seed"] == ss.entropy


def test_percolation_seed_none_is_recorded_and_replayable():
    L = square_lattice(20, 20)
    G = site_percolation(L, 0.7, keep="all")
    seed = G.graph["seed"]
    assert isinstance(seed, int)
    replay = site_percolation(L, 0.7, rng=np.random.SeedSequence(seed), keep="all")
    assert list(replay) == list(G)


def test_percolation_draw_order_follows_graph_nodes():
    L = chain(50)
    p = 0.5
    draws = np.random.default_rng(3).random(50)
    G = site_percolation(L, p, rng=3, keep="all")
    assert list(G) == [i for i in range(50) if draws[i] < p]


def test_largest_cluster_is_connected_and_largest():
    L = square_lattice(40, 40)
    G = site_percolation(L, 0.55, rng=1)
    everything = site_percolation(L, 0.55, rng=1, keep="all")
    assert nx.is_connected(G)
    assert G.number_of_nodes() == max(len(c) for c in nx.connected_components(everything))


def test_largest_cluster_tie_goes_to_smallest_label():
    # two equal-size clusters: the one holding the smallest label wins
    two_pairs = nx.Graph([(0, 1), (3, 4)], name="pairs")
    assert set(site_percolation(two_pairs, 1.0, rng=0)) == {0, 1}
    reverse = nx.Graph([(9, 8), (2, 3)])
    assert set(site_percolation(reverse, 1.0, rng=0)) == {2, 3}


def test_keep_all_prune_isolated_has_no_isolated_nodes():
    L = square_lattice(30, 30)
    raw = site_percolation(L, 0.4, rng=5, keep="all")
    pruned = site_percolation(L, 0.4, rng=5, keep="all", prune_isolated=True)
    assert any(d == 0 for _, d in raw.degree())
    assert all(d > 0 for _, d in pruned.degree())
    assert set(pruned) == {n for n, d in raw.degree() if d > 0}
    assert pruned.graph["prune_isolated"] is True


def test_percolation_preserves_labels_and_attributes():
    L = triangular_lattice(12, 12)
    nx.set_edge_attributes(L, 2.5, "k")
    G = site_percolation(L, 0.7, rng=11, keep="all")
    assert set(G) <= set(L)
    for node, data in G.nodes(data=True):
        assert data["pos"] == L.nodes[node]["pos"]
    for u, v, data in G.edges(data=True):
        assert L.has_edge(u, v)
        assert data["k"] == 2.5
    # induced: every parent edge between kept nodes is present
    assert G.number_of_edges() == L.subgraph(G.nodes).number_of_edges()
    # a fresh copy, not a view sharing attribute dicts with the parent
    G.nodes[next(iter(G))]["pos"] = (-1.0, -1.0)
    assert all(pos != (-1.0, -1.0) for _, pos in L.nodes(data="pos"))
    assert not nx.is_frozen(G)


def test_p_one_returns_whole_graph():
    L = square_lattice(10, 12, periodic=True)
    G = site_percolation(L, 1.0, rng=0)
    assert set(G.nodes) == set(L.nodes)
    assert set(map(frozenset, G.edges)) == set(map(frozenset, L.edges))
    assert G.graph["name"] == (
        "site_percolation(square_lattice(10, 12, periodic=True), p=1.0, keep='largest')"
    )
    assert G.graph["p"] == 1.0
    assert G.graph["keep"] == "largest"
    assert G.graph["prune_isolated"] is False
    assert G.graph["seed"] == 0


def test_p_zero_and_empty_results_raise():
    with pytest.raises(
        InvalidParameterError, match=r"no site occupied at p=0\.0 on a 4-node graph"
    ):
        site_percolation(chain(4), 0.0, rng=0)
    with pytest.raises(InvalidParameterError, match=r"p=0\.01.*4-node"):
        site_percolation(chain(4), 0.01, rng=0)
    # a lone occupied site is pruned away -> nothing left
    with pytest.raises(InvalidParameterError, match=r"isolated.*p=1\.0"):
        site_percolation(nx.empty_graph(3), 1.0, rng=0, prune_isolated=True)


@pytest.mark.parametrize("p", [-0.1, 1.5, float("nan")])
def test_bad_p_raises(p):
    with pytest.raises(InvalidParameterError, match=rf"p={p!r}"):
        site_percolation(chain(5), p)


def test_bad_keep_raises_listing_allowed():
    with pytest.raises(InvalidParameterError, match=r"'largest', 'all'.*keep='biggest'"):
        site_percolation(chain(5), 0.5, keep="biggest")


def test_bad_rng_raises_naming_the_allowed_values():
    for rng in (True, "7", 1.5, -1):
        with pytest.raises(InvalidParameterError, match="rng must be None, an int >= 0"):
            site_percolation(chain(5), 0.5, rng=rng)


def test_errors_are_value_errors():
    """InvalidParameterError is a ValueError: ``except ValueError`` keeps working."""
    with pytest.raises(ValueError, match="n must be an integer"):
        chain(2.5)


def test_bad_graph_and_p_types_raise():
    with pytest.raises(InvalidParameterError, match="undirected"):
        site_percolation(nx.DiGraph([(0, 1)]), 0.5)
    with pytest.raises(InvalidParameterError, match="p=True"):
        site_percolation(chain(5), True)


def test_occupied_fraction_matches_p():
    L = square_lattice(100, 100)
    G = site_percolation(L, 0.3, rng=2024, keep="all")
    assert abs(G.number_of_nodes() / L.number_of_nodes() - 0.3) < 0.02


def test_largest_cluster_near_and_below_threshold(square150):
    n = square150.number_of_nodes()
    at_pc = site_percolation(square150, 0.5927, rng=2024)
    below = site_percolation(square150, 0.4, rng=2024)
    assert at_pc.number_of_nodes() / n > 0.10
    assert below.number_of_nodes() / n < 0.05
    assert (
        at_pc.graph["name"]
        == "site_percolation(square_lattice(150, 150), p=0.5927, keep='largest')"
    )
