"""The step's scale: the top eigenvalue of the stiffness matrix, estimated from above."""

import networkx as nx
import numpy as np
import pytest
import scipy.sparse.linalg as sla
from hypothesis import example, given, settings
from hypothesis import strategies as st

import faultnet
from faultnet.model.spectrum import MARGIN, top_stiffness
from faultnet.solver.step_size import omega2_max


def _exact_top(model):
    return float(np.linalg.eigvalsh(model.laplacian.toarray() + np.eye(model.n))[-1])


def _gershgorin(model):
    return float(np.max(1.0 + 2.0 * np.asarray(model.adjacency.sum(axis=1)).ravel()))


@pytest.mark.parametrize(
    ("graph", "expected"),
    [
        (faultnet.graphs.ring(2000), 65.0),
        (faultnet.graphs.square_lattice(40, 40, periodic=True), 129.0),
        (faultnet.graphs.square_lattice(300, 300, periodic=True, sparse=True), 129.0),
    ],
    ids=["ring", "square", "square-sparse"],
)
def test_bipartite_regular_graphs_keep_the_gershgorin_bound(graph, expected):
    # the bound is the eigenvalue there: the step, and so every catalog, is unchanged
    model = faultnet.CarlsonLanger(graph, k=16)
    assert model.top_stiffness == _gershgorin(model) == expected


def test_triangular_lattice_gets_its_own_top():
    model = faultnet.CarlsonLanger(faultnet.graphs.triangular_lattice(90, 90, periodic=True))
    true = 1.0 + 9.0 * 16.0  # 6 - 2 cos a - 2 cos b - 2 cos(a + b) peaks at 9 (a = b = 2 pi / 3)
    assert true <= model.top_stiffness <= true * MARGIN * 1.01
    assert omega2_max(model) == model.top_stiffness + 1.0


def test_large_cluster_within_margin_of_arpack():
    g = faultnet.graphs.site_percolation(
        faultnet.graphs.triangular_lattice(60, 60), 0.5, rng=3, keep="largest"
    )
    model = faultnet.CarlsonLanger(g, k=16)
    assert model.n > 256  # the Lanczos path
    true = float(sla.eigsh(model.laplacian.tocsc(), k=1, which="LA", tol=1e-10)[0][0]) + 1.0
    assert true <= model.top_stiffness <= true * MARGIN * 1.01
    assert model.top_stiffness < _gershgorin(model)


@settings(deadline=None, max_examples=25)
@given(seed=st.integers(0, 10_000), n=st.integers(1, 300), p=st.floats(0.005, 0.2))
@example(seed=274, n=9, p=0.125)  # one spring pair sets the top: eigvalsh 1 ulp above 1 + 2 k
def test_random_graphs_with_random_springs(seed, n, p):
    rng = np.random.default_rng(seed)
    g = nx.gnp_random_graph(n, p, seed=seed)
    for a, b in g.edges:
        g.edges[a, b]["k"] = float(rng.uniform(0.5, 30.0))
    model = faultnet.CarlsonLanger(g, k=16)
    true = _exact_top(model)
    got = top_stiffness(model.adjacency)
    # where Gershgorin's bound is exact (an isolated pair: 1 + 2 k), the dense solver's value
    # may exceed it by a rounding error
    assert true * (1.0 - 1e-13) <= got <= max(true * MARGIN * 1.01, true + 1e-12)
    assert got <= _gershgorin(model)
