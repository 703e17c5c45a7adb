"""Lattice boundaries: periodic, free and fixed (frame springs, node attribute ``wall``)."""

import numpy as np
import pytest

import faultnet
from faultnet.exceptions import GraphSpecError, InvalidParameterError
from faultnet.graphs import square_lattice, triangular_lattice
from faultnet.runs.specs import build_graph, parse_graph_spec


def _edges(G):
    return sorted(tuple(sorted(e)) for e in G.edges)


@pytest.mark.parametrize("rows, cols", [(1, 1), (1, 5), (3, 3), (4, 7)])
def test_fixed_square_lattice_walls_complete_the_coordination(rows, cols):
    fixed = square_lattice(rows, cols, boundary="fixed")
    free = square_lattice(rows, cols, boundary="free")
    assert _edges(fixed) == _edges(free)
    assert all(d + fixed.nodes[v]["wall"] == 4 for v, d in fixed.degree())
    assert sum(fixed.nodes[v]["wall"] for v in fixed) == 2 * (rows + cols)
    assert fixed.graph["boundary"] == "fixed" and free.graph["boundary"] == "free"
    assert not any("wall" in data for _, data in free.nodes(data=True))
    assert fixed.graph["name"] == f"square_lattice({rows}, {cols}, boundary='fixed')"


@pytest.mark.parametrize("rows, cols", [(1, 1), (2, 3), (5, 4), (6, 6)])
def test_fixed_triangular_lattice_walls_complete_the_coordination(rows, cols):
    fixed = triangular_lattice(rows, cols, boundary="fixed")
    assert _edges(fixed) == _edges(triangular_lattice(rows, cols))
    assert all(d + fixed.nodes[v]["wall"] == 6 for v, d in fixed.degree())
    assert fixed.graph["name"] == f"triangular_lattice({rows}, {cols}, boundary='fixed')"


def test_the_older_periodic_argument_keeps_working():
    for build, size in ((square_lattice, (4, 5)), (triangular_lattice, (4, 5))):
        assert _edges(build(*size, periodic=True)) == _edges(build(*size, boundary="periodic"))
        assert _edges(build(*size, periodic=False)) == _edges(build(*size, boundary="free"))
        assert _edges(build(*size, True)) == _edges(build(*size, boundary="periodic"))
        assert build(*size, periodic=True).graph["name"].endswith("periodic=True)")
        assert build(*size, periodic=True, boundary="periodic").graph["boundary"] == "periodic"
        fixed = build(*size, periodic=False, boundary="fixed")
        assert fixed.graph["boundary"] == "fixed"
    assert square_lattice(3, 3).graph["name"] == "square_lattice(3, 3)"


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"boundary": "open"}, r"boundary must be one of 'periodic', 'free', 'fixed'"),
        ({"boundary": 1}, "boundary must be one of"),
        ({"periodic": True, "boundary": "fixed"}, r"periodic=True contradicts boundary='fixed'"),
        ({"periodic": True, "boundary": "free"}, "contradicts"),
        ({"periodic": False, "boundary": "periodic"}, "contradicts"),
        ({"periodic": "yes"}, "periodic must be True or False"),
    ],
)
def test_bad_boundaries_get_one_clear_error(kwargs, match):
    for build in (square_lattice, triangular_lattice):
        with pytest.raises(InvalidParameterError, match=match):
            build(4, 4, **kwargs)


@pytest.mark.parametrize("boundary", ["free", "periodic", "fixed"])
def test_sparse_lattice_carries_the_same_boundary(boundary):
    dense = square_lattice(5, 6, boundary=boundary)
    sparse = square_lattice(5, 6, boundary=boundary, sparse=True)
    assert sparse.graph["name"] == dense.graph["name"]
    assert sparse.graph["boundary"] == boundary
    A = sparse.adjacency.toarray()
    assert _edges(dense) == sorted(zip(*np.nonzero(np.triu(A)), strict=True))
    if boundary == "fixed":
        np.testing.assert_array_equal(sparse.node_wall, [dense.nodes[v]["wall"] for v in dense])
    else:
        assert sparse.node_wall is None


def test_sparse_graph_checks_its_walls():
    with pytest.raises(InvalidParameterError, match=r"wall must have shape \(4,\)"):
        faultnet.SparseGraph(np.eye(4)[[1, 0, 3, 2]], wall=[1, 2])
    with pytest.raises(InvalidParameterError, match="wall .* at node 1"):
        faultnet.SparseGraph(np.eye(4)[[1, 0, 3, 2]], wall=[0, -1, 0, 0])


def test_percolation_keeps_the_frame_of_its_lattice():
    G = faultnet.graphs.site_percolation(square_lattice(10, 10, boundary="fixed"), 0.8, rng=3)
    assert G.graph["boundary"] == "fixed"
    assert all(G.nodes[v]["wall"] == (v // 10 in (0, 9)) + (v % 10 in (0, 9)) for v in G)


@pytest.mark.parametrize(
    "spec, canonical, name",
    [
        ("square:8x6:fixed", "square:8x6:fixed", "square_lattice(8, 6, boundary='fixed')"),
        ("square:8:free", "square:8x8", "square_lattice(8, 8)"),
        ("square:8:open", "square:8x8", "square_lattice(8, 8)"),
        (
            "triangular:4x6:fixed",
            "triangular:4x6:fixed",
            "triangular_lattice(4, 6, boundary='fixed')",
        ),
        ("square:5:periodic", "square:5x5:periodic", "square_lattice(5, 5, periodic=True)"),
    ],
)
def test_graph_specs_name_the_boundary(spec, canonical, name):
    gs = parse_graph_spec(spec)
    assert gs.canonical == canonical
    G = build_graph(spec)
    assert G.graph["name"] == name and G.graph["spec"] == canonical
    assert parse_graph_spec(canonical) == gs


def test_percolation_specs_take_a_fixed_boundary():
    gs = parse_graph_spec("percolation:square:12x12:fixed:p=0.9:seed=2")
    assert gs.boundary == "fixed" and gs.canonical.startswith("percolation:square:12x12:fixed:")
    assert "boundary='fixed'" in build_graph(gs).graph["name"]
    with pytest.raises(GraphSpecError, match="allowed: periodic, fixed, free, open"):
        parse_graph_spec("square:8x8:closed")
