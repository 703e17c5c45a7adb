"""Graph specs (faultnet.runs.specs): parsing, canonical forms, seeds, errors, hashes."""

import networkx as nx
import numpy as np
import pytest

from faultnet.exceptions import GraphSpecError, InvalidParameterError
from faultnet.model.identity import graph_hash
from faultnet.runs.specs import build_graph, build_model, graph_seed, parse_graph_spec


def test_percolation_specs_are_reproducible():
    a = build_model("percolation:square:20x20:p=pc:all", rng=5)
    b = build_model("percolation:square:20x20:p=0.592746:all", rng=5)
    c = build_model("percolation:square:20x20:p=pc:all", rng=6)
    d = build_model("percolation:square:20x20:p=pc:all:seed=9", rng=6)
    e = build_model("percolation:square:20x20:p=pc:all:seed=9", rng=7)
    assert graph_hash(a) == graph_hash(b) != graph_hash(c)
    assert graph_hash(d) == graph_hash(e)
    with pytest.raises(TypeError, match="graph_hash needs a CarlsonLanger.*got Graph"):
        graph_hash(nx.cycle_graph(5))
    assert parse_graph_spec("square:12").canonical == "square:12x12"
    assert parse_graph_spec("percolation:triangular:8x8:periodic:p=pc:prune").canonical == (
        "percolation:triangular:8x8:periodic:p=0.5:largest:prune"
    )


def test_percolation_disorder_comes_from_the_run_seed():
    seq = np.random.SeedSequence(11, spawn_key=(2,))
    G = build_graph("percolation:square:10x10:p=0.7:all", rng=seq)
    child = graph_seed(seq)
    assert (G.graph["seed_entropy"], G.graph["seed_spawn_key"]) == (11, [2, 0])
    assert child.spawn_key == (2, 0)
    # an int seed is SeedSequence(int): the same graph
    same = build_graph("percolation:square:10x10:p=0.7:all", rng=11)
    from_seq = build_graph("percolation:square:10x10:p=0.7:all", rng=np.random.SeedSequence(11))
    assert list(same) == list(from_seq)


def test_bad_specs_name_the_valid_forms():
    with pytest.raises(GraphSpecError, match=r"(?s)unknown graph kind 'hex'.*valid forms:.*ring:N"):
        parse_graph_spec("hex:10")
    assert issubclass(GraphSpecError, InvalidParameterError)
    with pytest.raises(GraphSpecError, match=r"ring:2.*would double the spring"):
        build_graph("ring:2")
    with pytest.raises(GraphSpecError, match="rng must be None, an int >= 0"):
        build_graph("percolation:square:10x10:p=0.7", rng="seven")


def test_graph_attributes_must_be_numbers():
    g = nx.path_graph(3)
    g.graph["k"] = "stiff"
    with pytest.raises(InvalidParameterError, match="graph attribute 'k' must be a number"):
        build_model(g)


@pytest.mark.parametrize(
    ("spec", "canonical", "name"),
    [
        ("ring:2000:reach=10:kc=100", "ring:2000:reach=10:kc=100", "ring(2000, reach=10, k_c=100)"),
        ("ring:50:kc=2.5:reach=3", "ring:50:reach=3:kc=2.5", "ring(50, reach=3, k_c=2.5)"),
        ("chain:500:reach=3", "chain:500:reach=3", "chain(500, reach=3)"),
        ("chain:9:k_c=16.0", "chain:9:kc=16", "chain(9, k_c=16)"),
        ("RING:12:Reach=1:KC=1e1", "ring:12:kc=10", "ring(12, k_c=10)"),
        ("ring:30:reach=1", "ring:30", "ring(30)"),
        ("chain:4", "chain:4", "chain(4)"),
    ],
)
def test_long_range_specs_round_trip(spec, canonical, name):
    gs = parse_graph_spec(spec)
    assert gs.canonical == canonical
    assert parse_graph_spec(canonical) == gs
    G = build_graph(spec)
    assert G.graph["name"] == name and G.graph["spec"] == canonical
    if gs.k_c is not None:
        assert {d["k"] for *_, d in G.edges(data=True)} == {gs.k_c / (2 * gs.reach)}


def test_xia_spec_builds_the_xia_model():
    model = build_model("ring:40:reach=3:kc=12", alpha=2.5)
    np.testing.assert_allclose(model.stiffness, 13.0)
    assert model.alpha == 2.5
    plain = parse_graph_spec("ring:40")
    assert (plain.reach, plain.k_c) == (1, None)
    assert graph_hash(model) != graph_hash(build_model("ring:40:reach=3", alpha=2.5))


@pytest.mark.parametrize(
    ("spec", "why"),
    [
        ("ring:10:reach=5", r"reach must be at most \(N - 1\) // 2 on a ring, here 4; got reach=5"),
        ("chain:6:reach=6", r"reach must be at most N - 1 on a chain, here 5; got reach=6"),
        ("ring:10:reach=0", r"reach must be an integer >= 1, got '0'"),
        ("ring:10:reach=2.5", r"reach must be an integer >= 1, got '2.5'"),
        ("ring:10:reach=", r"reach must be an integer >= 1, got ''"),
        ("ring:10:kc=0", r"kc must be a finite number > 0, got '0'"),
        ("ring:10:kc=-3", r"kc must be a finite number > 0, got '-3'"),
        ("ring:10:kc=nan", r"kc must be a finite number > 0, got 'nan'"),
        ("ring:10:kc=inf", r"kc must be a finite number > 0, got 'inf'"),
        ("ring:10:kc=stiff", r"kc must be a finite number > 0, got 'stiff'"),
        ("ring:10:reach=2:reach=3", r"reach= is given twice"),
        ("ring:10:kc=1:k_c=2", r"kc= is given twice"),
        ("ring:10:periodic", r"unknown ring option 'periodic'; allowed: reach=R .* and kc=K"),
        ("chain:10:q=4", r"unknown chain option 'q=4'; allowed: reach=R"),
        ("chain", r"chain takes a size"),
    ],
)
def test_bad_long_range_specs_name_the_allowed_forms(spec, why):
    with pytest.raises(GraphSpecError, match=rf"(?s){why}.*valid forms:.*ring:N\[:reach=R\]"):
        parse_graph_spec(spec)


def test_ring_too_small_still_fails_when_built():
    assert parse_graph_spec("ring:2").canonical == "ring:2"
    with pytest.raises(GraphSpecError, match=r"ring:2.*would double the spring"):
        build_graph("ring:2")
