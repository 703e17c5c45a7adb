"""Where blocks are: node coordinates, periodic boxes and distances for catalog analyses.

Periodicity is read from the graph: ``G.graph["period"]`` when set (a pair of
box lengths, ``None`` for an open direction), else the constructor name that
:mod:`faultnet.graphs.builders` records, also inside a ``site_percolation(...)`` name:
``ring(n)`` (arc length along the circle, period ``n``),
``square_lattice(r, c, periodic=True)`` (box ``c x r``) and
``triangular_lattice(r, c, periodic=True)`` (box ``c x r sqrt(3)/2``).
"""

from __future__ import annotations

import math
import re

import networkx as nx
import numpy as np

from faultnet.exceptions import InvalidParameterError

__all__ = ["Geometry", "geometry"]

_RING = re.compile(r"(?<![a-z_])ring\((\d+)\)")
_LATTICE = re.compile(r"(square|triangular)_lattice\((\d+), (\d+), periodic=True\)")
_SQUARE_ANY = re.compile(r"^square_lattice\((\d+), (\d+)(, periodic=True)?\)$")
METRICS = ("euclidean", "graph")


class Geometry:
    """Node order, coordinates, periods and adjacency of a graph, for distances."""

    def __init__(self, nodes, coords, period, adjacency):
        self.nodes = nodes
        self.index = {node: i for i, node in enumerate(nodes)}
        self.coords = coords
        self.period = period
        self.adjacency = adjacency
        self._hops = {}

    def indices(self, labels):
        """Positions (node order) of node labels; an unknown label raises."""
        try:
            return np.fromiter((self.index[v] for v in labels), dtype=np.int64, count=len(labels))
        except KeyError as exc:
            raise InvalidParameterError(
                f"hypocenter {exc.args[0]!r} is not a node of the graph: pass the graph "
                "(or model / result) the catalog was simulated on"
            ) from None

    def distances(self, source, metric="euclidean"):
        """Distances from node position ``source`` to every node (node order)."""
        if metric == "graph":
            if source not in self._hops:
                from scipy.sparse.csgraph import shortest_path

                d = shortest_path(self.adjacency, unweighted=True, indices=source)
                self._hops[source] = d
            return self._hops[source]
        if self.coords is None:
            raise InvalidParameterError(
                "the graph has no node positions ('pos'): use metric='graph'"
            )
        delta = np.abs(self.coords - self.coords[source])
        for axis, length in enumerate(self.period):
            if length:
                delta[:, axis] = np.minimum(delta[:, axis], length - delta[:, axis])
        return np.hypot(delta[:, 0], delta[:, 1])


def _unwrap(obj):
    """A graph from a graph, model or simulation result."""
    if hasattr(obj, "model") and hasattr(obj, "events"):
        obj = obj.model
    if not isinstance(obj, nx.Graph) and hasattr(obj, "graph") and hasattr(obj, "nodes"):
        return obj.graph, obj.adjacency, list(obj.nodes)
    return obj, None, None


def geometry(obj):
    """:class:`Geometry` of a networkx graph, SparseGraph, CarlsonLanger or SimulationResult."""
    graph, adjacency, nodes = _unwrap(obj)
    attrs = getattr(graph, "graph", None)
    if not isinstance(attrs, dict):
        raise InvalidParameterError(
            "graph must be a networkx.Graph, a faultnet.SparseGraph, a CarlsonLanger or a "
            f"SimulationResult; got {type(obj).__name__}"
        )
    name = str(attrs.get("name") or "")
    if isinstance(graph, nx.Graph):
        nodes = list(graph.nodes) if nodes is None else nodes
        if adjacency is None:
            adjacency = nx.to_scipy_sparse_array(graph, nodelist=nodes, format="csr")
            if adjacency.nnz < 2**31:  # int32 indices: SciPy's graph routines before 1.15
                adjacency.indices = adjacency.indices.astype(np.int32)
                adjacency.indptr = adjacency.indptr.astype(np.int32)
        pos = [graph.nodes[v].get("pos") for v in nodes]
        coords = None if any(p is None for p in pos) else np.asarray(pos, dtype=np.float64)
    else:  # SparseGraph: blocks 0..n-1, positions only for the square lattice
        adjacency = graph.adjacency if adjacency is None else adjacency
        n = adjacency.shape[0]
        nodes = list(range(n)) if nodes is None else nodes
        coords = None
        match = _SQUARE_ANY.match(name)
        if match:
            cols = int(match.group(2))
            idx = np.arange(n)
            coords = np.column_stack([idx % cols, idx // cols]).astype(np.float64)
    period = [None, None]
    if "period" in attrs:
        period = list(attrs["period"])
    elif coords is not None and (ring := _RING.search(name)):
        n_ring = int(ring.group(1))
        radius = n_ring / (2.0 * math.pi)
        theta = np.mod(np.arctan2(coords[:, 1], coords[:, 0]), 2.0 * math.pi)
        coords = np.column_stack([radius * theta, np.zeros(len(coords))])
        period = [float(n_ring), None]
    elif lattice := _LATTICE.search(name):
        rows, cols = int(lattice.group(2)), int(lattice.group(3))
        height = 1.0 if lattice.group(1) == "square" else math.sqrt(3.0) / 2.0
        period = [float(cols), rows * height]
    return Geometry(nodes, coords, period, adjacency)
