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
