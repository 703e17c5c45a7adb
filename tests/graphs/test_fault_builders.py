"""Tests for faultnet.graphs.faults: networks of faults and their coupling springs."""

import math

import networkx as nx
import pytest

import faultnet
from faultnet.exceptions import InvalidParameterError
from faultnet.graphs import branch, chain, compose, parallel_faults, ring, step_over
from faultnet.seismicity.geometry import geometry


def _couplings(G):
    """The springs whose blocks lie on two different faults."""
    return [
        (u, v, d) for u, v, d in G.edges(data=True) if G.nodes[u]["fault"] != G.nodes[v]["fault"]
    ]


def _check_network(G, faults):
    """Every block has a fault and a float (x, y); couplings carry k, fault springs none."""
    assert {f for _, f in G.nodes(data="fault")} == set(faults)
    for node, data in G.nodes(data=True):
        assert node == (data["fault"], node[1])
        pos = data["pos"]
        assert isinstance(pos, tuple) and len(pos) == 2 and all(isinstance(x, float) for x in pos)
    for u, v, data in G.edges(data=True):
        if G.nodes[u]["fault"] == G.nodes[v]["fault"]:
            assert "k" not in data


def _fault_spans(G, n_events=300):
    """Number of faults each event's slipping blocks lie on."""
    model = faultnet.CarlsonLanger(G, k=16, sigma=0.01, alpha=1.0)
    result = faultnet.simulate(model, n_events, rng=1, progress=False, record_slips=True)
    slips = result.slips
    fault = slips["node"].map(lambda node: G.nodes[node]["fault"])
    return slips.assign(fault=fault).groupby("event")["fault"].nunique()


# --------------------------------------------------------------------- parallel faults


@pytest.mark.parametrize("periodic", [False, True])
def test_parallel_faults_structure(periodic):
    G = parallel_faults(3, 5, k_coupling=2.0, spacing=1.5, periodic=periodic)
    _check_network(G, {0, 1, 2})
    within = 3 * (5 if periodic else 4)
    assert G.number_of_nodes() == 15 and G.number_of_edges() == within + 2 * 5
    couplings = _couplings(G)
    assert len(couplings) == 10 and all(d == {"k": 2.0} for _, _, d in couplings)
    assert {(u[1], v[1]) for u, v, _ in couplings} == {(i, i) for i in range(5)}
    assert G.nodes[2, 4]["pos"] == (4.0, 3.0)
    assert G.has_edge((0, 4), (0, 0)) is periodic
    assert G.graph.get("period") == ((5.0, None) if periodic else None)


def test_parallel_faults_names_and_zero_coupling():
    G = parallel_faults(2, 4, k_coupling=0, names=["north", ("south", 2)])
    _check_network(G, {"north", ("south", 2)})
    assert _couplings(G) == [] and nx.number_connected_components(G) == 2
    assert list(G)[4] == (("south", 2), 0)


def test_parallel_faults_geometry_wraps_along_strike():
    geo = geometry(parallel_faults(2, 10, k_coupling=1.0, periodic=True, spacing=2.0))
    d = geo.distances(geo.index[0, 0])
    assert d[geo.index[0, 9]] == pytest.approx(1.0)  # across the seam
    assert d[geo.index[1, 9]] == pytest.approx(math.sqrt(5.0))


# --------------------------------------------------------------------- step-over


def test_step_over_overlapping_blocks_face_each_other():
    G = step_over(8, overlap=3, gap=0.5, k_coupling=1.5, names=("west", "east"))
    _check_network(G, {"west", "east"})
    assert G.number_of_nodes() == 16 and G.number_of_edges() == 7 + 7 + 3
    pairs = sorted((u[1], v[1]) for u, v, _ in _couplings(G))
    assert pairs == [(5, 0), (6, 1), (7, 2)]
    for u, v, data in _couplings(G):
        assert data == {"k": 1.5}
        (xu, yu), (xv, yv) = G.nodes[u]["pos"], G.nodes[v]["pos"]
        assert xu == xv and yv - yu == 0.5


def test_step_over_end_to_end_and_full_overlap():
    G = step_over(5, overlap=0, gap=0.0, k_coupling=3.0)
    assert [(u, v) for u, v, _ in _couplings(G)] == [(("A", 4), ("B", 0))]
    assert G.nodes["B", 0]["pos"] == (5.0, 0.0)
    full = step_over(5, overlap=5, gap=1.0, k_coupling=3.0)
    assert len(_couplings(full)) == 5 and full.nodes["B", 0]["pos"] == (0.0, 1.0)
    assert _couplings(step_over(5, overlap=2, gap=1.0, k_coupling=0.0)) == []


# --------------------------------------------------------------------- branch


def test_branch_leaves_the_main_fault_at_an_angle():
    G = branch(10, 4, at=3, angle_deg=60, k_coupling=5.0)
    _check_network(G, {"main", "branch"})
    assert G.number_of_nodes() == 14 and G.number_of_edges() == 9 + 3 + 1
    assert [(u, v, d) for u, v, d in _couplings(G)] == [(("main", 3), ("branch", 0), {"k": 5.0})]
    x, y = G.nodes["branch", 3]["pos"]
    assert x == pytest.approx(3.0 + 4 * 0.5) and y == pytest.approx(4 * math.sqrt(3) / 2)
    below = branch(10, 4, at=9, angle_deg=-90, names=("M", "B"))
    assert below.nodes["B", 0]["pos"][1] == pytest.approx(-1.0)
    assert [d for _, _, d in _couplings(below)] == [{}]  # k_coupling=None: the model's k
    assert nx.number_connected_components(branch(5, 2, at=0, k_coupling=0)) == 2


# --------------------------------------------------------------------- compose


def test_compose_keeps_attributes_and_labels_nodes_by_fault():
    a = chain(3)
    a.nodes[1]["sigma"] = 0.02
    a.edges[0, 1]["k"] = 7.0
    b = ring(4)
    G = compose({"a": a, ("b", 1): b}, [("a", 2, ("b", 1), 0, 1.0), ("a", 0, ("b", 1), 2, None)])
    assert all(isinstance(node, tuple) and len(node) == 2 for node in G)
    assert list(G)[:3] == [("a", 0), ("a", 1), ("a", 2)]
    assert G.nodes["a", 1] == {"pos": (1.0, 0.0), "sigma": 0.02, "fault": "a"}
    assert G.nodes[("b", 1), 0]["pos"] == b.nodes[0]["pos"]
    assert G.edges[("a", 0), ("a", 1)] == {"k": 7.0}
    assert G.edges[("a", 2), (("b", 1), 0)] == {"k": 1.0}
    assert G.edges[("a", 0), (("b", 1), 2)] == {}
    assert G.number_of_edges() == 2 + 4 + 2
    model = faultnet.CarlsonLanger(G, k=16)
    assert model.sigma_values[1] == 0.02 and model.nodes == list(G)


# --------------------------------------------------------------------- validation


@pytest.mark.parametrize(
    "build, match",
    [
        (lambda: parallel_faults(0, 5, k_coupling=1.0), "n_faults"),
        (lambda: parallel_faults(2, 2.5, k_coupling=1.0), "n_blocks"),
        (lambda: parallel_faults(2, 2, k_coupling=1.0, periodic=True), "n_blocks >= 3"),
        (lambda: parallel_faults(2, 5, k_coupling=-1.0), "k_coupling"),
        (lambda: parallel_faults(2, 5, k_coupling="x"), "k_coupling"),
        (lambda: parallel_faults(2, 5, k_coupling=1.0, spacing=0), "spacing"),
        (lambda: parallel_faults(2, 5, k_coupling=1.0, names=["a"]), "names"),
        (lambda: parallel_faults(2, 5, k_coupling=1.0, names=["a", "a"]), "names"),
        (lambda: parallel_faults(2, 5, k_coupling=1.0, names=["a", 1.5]), "names"),
        (lambda: step_over(0, overlap=0, gap=1.0, k_coupling=1.0), "n_blocks"),
        (lambda: step_over(5, overlap=6, gap=1.0, k_coupling=1.0), "overlap"),
        (lambda: step_over(5, overlap=-1, gap=1.0, k_coupling=1.0), "overlap"),
        (lambda: step_over(5, overlap=2, gap=0.0, k_coupling=1.0), "gap"),
        (lambda: step_over(5, overlap=0, gap=-1.0, k_coupling=1.0), "gap"),
        (lambda: step_over(5, overlap=2, gap=1.0, k_coupling=math.inf), "k_coupling"),
        (lambda: step_over(5, overlap=2, gap=1.0, k_coupling=1.0, names="AB"), "names"),
        (lambda: branch(0, 3, at=0), "n_main"),
        (lambda: branch(5, 0, at=0), "n_branch"),
        (lambda: branch(5, 3, at=5), "at"),
        (lambda: branch(5, 3, at=1, angle_deg=0), "angle_deg"),
        (lambda: branch(5, 3, at=1, angle_deg=180), "angle_deg"),
        (lambda: branch(5, 3, at=1, k_coupling=-2), "k_coupling"),
        (lambda: compose({}, []), "graphs"),
        (lambda: compose([chain(2)], []), "graphs"),
        (lambda: compose({1.5: chain(2)}, []), "graphs"),
        (lambda: compose({"a": nx.DiGraph()}, []), r"graphs\['a'\]"),
        (lambda: compose({"a": chain(2)}, 5), "couplings"),
        (lambda: compose({"a": chain(2), "b": chain(2)}, [("a", 0, "b")]), r"couplings\[0\]"),
        (lambda: compose({"a": chain(2), "b": chain(2)}, [("a", 0, "c", 0, 1)]), "'c'"),
        (lambda: compose({"a": chain(2), "b": chain(2)}, [("a", 0, ["b"], 0, 1)]), "fault"),
        (lambda: compose({"a": chain(2), "b": chain(2)}, [("a", 5, "b", 0, 1)]), "block 5"),
        (lambda: compose({"a": chain(3), "b": chain(2)}, [("a", 0, "a", 2, 1)]), "different"),
        (lambda: compose({"a": chain(2), "b": chain(2)}, [("a", 0, "b", 0, 0)]), "k of"),
        (
            lambda: compose({"a": chain(2), "b": chain(2)}, [("a", 0, "b", 0, 1)] * 2),
            r"couplings\[1\] repeats",
        ),
    ],
)
def test_invalid_arguments_are_named(build, match):
    with pytest.raises(InvalidParameterError, match=match):
        build()


# --------------------------------------------------------------------- simulations


@pytest.mark.parametrize(
    "G",
    [
        parallel_faults(3, 8, k_coupling=4.0, periodic=True),
        step_over(10, overlap=4, gap=1.0, k_coupling=2.0),
        step_over(10, overlap=0, gap=1.0, k_coupling=2.0),
        branch(12, 6, at=5, k_coupling=8.0),
        compose({"x": chain(6), "y": ring(5)}, [("x", 5, "y", 0, 3.0)]),
    ],
    ids=["parallel", "step_over", "end_to_end", "branch", "compose"],
)
def test_carlson_langer_runs_on_every_network(G):
    model = faultnet.CarlsonLanger(G, k=16, sigma=0.01, alpha=1.0)
    result = faultnet.simulate(model, 200, rng=1, progress=False)
    assert len(result.events) == 200
    assert set(result.events["hypocenter"]) <= set(G)


def test_uncoupled_faults_never_slip_together():
    spans = _fault_spans(parallel_faults(2, 30, k_coupling=0.0))
    assert spans.max() == 1 and len(spans) == 300


def test_strongly_coupled_faults_slip_together():
    spans = _fault_spans(parallel_faults(2, 30, k_coupling=16.0))
    assert (spans == 2).sum() > 10
