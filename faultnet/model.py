"""The Carlson-Langer model on a graph: validated parameters and sparse operators."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import networkx as nx
import numpy as np
import scipy.sparse as sp

from faultnet.exceptions import InvalidParameterError

__all__ = ["CarlsonLanger"]


def _check_sigma(value, where):
    if not (math.isfinite(value) and 0.0 < value < 1.0):
        raise InvalidParameterError(
            f"sigma must lie in the open interval (0, 1); got {value!r}{where}"
        )


def _check_alpha(value, where):
    if not (math.isfinite(value) and value >= 0.0):
        raise InvalidParameterError(f"alpha must be finite and >= 0; got {value!r}{where}")


def _check_k(value, where):
    if not (math.isfinite(value) and value > 0.0):
        raise InvalidParameterError(
            f"spring constant k must be finite and > 0; got {value!r}{where}"
        )


def _as_float(value, name, where=""):
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InvalidParameterError(f"{name} must be a real number; got {value!r}{where}")
    return float(value)


@dataclass(frozen=True, eq=False)
class CarlsonLanger:
    """Carlson-Langer block-spring model on a networkx graph.

    Blocks of unit mass sit on the nodes; every edge is a spring of constant
    ``k`` (edge attribute ``k`` overrides it), every block is tied to the
    loading plate ``u`` by a unit spring, and slips against the
    velocity-weakening friction ``phi(v) = (1 - sigma) / (1 + 2 alpha v / (1 - sigma))``
    (node attributes ``sigma`` and ``alpha`` override the scalars).  The
    force on block ``i`` is ``F_i = sum_j k_ij (x_j - x_i) + (u - x_i)``.

    Parameters
    ----------
    graph : networkx.Graph
        Undirected simple graph without self-loops.  Any hashable node labels.
    k, sigma, alpha : float
        Default spring constant (> 0), friction drop (in (0, 1)) and velocity
        weakening rate (>= 0) for edges and nodes without attributes.

    Attributes
    ----------
    nodes : list
        Node labels in the order used by every array (``x``, slips, ...).
    adjacency : scipy.sparse.csr_matrix
        Symmetric matrix of spring constants ``k_ij`` (zero diagonal).
    laplacian : scipy.sparse.csr_matrix
        Weighted graph Laplacian ``diag(sum_j k_ij) - K``.
    sigma_values, alpha_values : numpy.ndarray
        Per-block friction parameters in node order.

    Examples
    --------
    >>> import faultnet
    >>> model = faultnet.CarlsonLanger(faultnet.graphs.ring(5), k=16, sigma=0.01, alpha=1.5)
    >>> model.n, float(model.laplacian.diagonal()[0])
    (5, 32.0)
    >>> model.with_params(alpha=2.0).alpha
    2.0
    """

    graph: nx.Graph
    k: float = 16.0
    sigma: float = 0.01
    alpha: float = 1.0
    nodes: list = field(init=False, repr=False)
    adjacency: sp.csr_matrix = field(init=False, repr=False)
    sigma_values: np.ndarray = field(init=False, repr=False)
    alpha_values: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        g = self.graph
        if not isinstance(g, nx.Graph):
            raise InvalidParameterError(f"graph must be a networkx.Graph; got {type(g).__name__}")
        if g.is_directed() or g.is_multigraph():
            raise InvalidParameterError(
                "graph must be an undirected simple nx.Graph (springs are symmetric); "
                f"got a {type(g).__name__}"
            )
        if g.number_of_nodes() == 0:
            raise InvalidParameterError("graph is empty: it has no blocks (nodes)")
        loops = list(nx.selfloop_edges(g))
        if loops:
            raise InvalidParameterError(
                f"graph has self-loops (a spring from a block to itself): {loops[:5]}"
            )
        set_ = object.__setattr__
        set_(self, "k", _as_float(self.k, "k"))
        set_(self, "sigma", _as_float(self.sigma, "sigma"))
        set_(self, "alpha", _as_float(self.alpha, "alpha"))
        _check_k(self.k, "")
        _check_sigma(self.sigma, "")
        _check_alpha(self.alpha, "")
        nodes = list(g.nodes)
        index = {node: i for i, node in enumerate(nodes)}
        set_(self, "nodes", nodes)
        set_(self, "adjacency", self._build_adjacency(g, index))
        set_(self, "sigma_values", self._node_values(g, "sigma", self.sigma, _check_sigma))
        set_(self, "alpha_values", self._node_values(g, "alpha", self.alpha, _check_alpha))

    def _build_adjacency(self, g, index):
        m = g.number_of_edges()
        rows = np.empty(m, dtype=np.int64)
        cols = np.empty(m, dtype=np.int64)
        vals = np.empty(m, dtype=np.float64)
        for e, (a, b, data) in enumerate(g.edges(data=True)):
            where = f" on edge ({a!r}, {b!r})"
            kv = _as_float(data.get("k", self.k), "k", where)
            _check_k(kv, where)
            rows[e], cols[e], vals[e] = index[a], index[b], kv
        n = len(index)
        mat = sp.coo_matrix(
            (
                np.concatenate([vals, vals]),
                (np.concatenate([rows, cols]), np.concatenate([cols, rows])),
            ),
            shape=(n, n),
        ).tocsr()
        mat.sort_indices()
        return mat

    def _node_values(self, g, name, default, check):
        out = np.empty(g.number_of_nodes(), dtype=np.float64)
        for i, (node, data) in enumerate(g.nodes(data=True)):
            where = f" at node {node!r}"
            value = _as_float(data.get(name, default), name, where)
            check(value, where)
            out[i] = value
        return out

    @property
    def n(self) -> int:
        """Number of blocks."""
        return len(self.nodes)

    @property
    def laplacian(self) -> sp.csr_matrix:
        """Weighted graph Laplacian ``L = diag(K 1) - K`` (CSR)."""
        deg = np.asarray(self.adjacency.sum(axis=1)).ravel()
        return (sp.diags(deg) - self.adjacency).tocsr()

    @property
    def stiffness(self) -> np.ndarray:
        """Total stiffness seen by each block when its neighbours are held: ``1 + sum_j k_ij``."""
        return 1.0 + np.asarray(self.adjacency.sum(axis=1)).ravel()

    def forces(self, x, u=0.0) -> np.ndarray:
        """Spring force ``F_i = sum_j k_ij (x_j - x_i) + (u - x_i)`` on every block."""
        x = np.asarray(x, dtype=np.float64)
        return -(self.laplacian @ x) + (u - x)

    def with_params(self, *, k=None, sigma=None, alpha=None) -> CarlsonLanger:
        """A model on the same graph with some scalar parameters replaced.

        Per-edge and per-node attributes of the graph still take precedence.
        """
        return CarlsonLanger(
            self.graph,
            k=self.k if k is None else k,
            sigma=self.sigma if sigma is None else sigma,
            alpha=self.alpha if alpha is None else alpha,
        )

    @property
    def params(self) -> dict:
        """Scalar parameters and a description of the graph, for metadata."""
        return {
            "graph": self.graph.graph.get("name", f"{type(self.graph).__name__}({self.n} nodes)"),
            "n_blocks": self.n,
            "n_springs": int(self.adjacency.nnz // 2),
            "k": self.k,
            "sigma": self.sigma,
            "alpha": self.alpha,
            "heterogeneous": bool(
                np.any(self.sigma_values != self.sigma)
                or np.any(self.alpha_values != self.alpha)
                or np.any(self.adjacency.data != self.k)
            ),
        }

    def __repr__(self):
        p = self.params
        return (
            f"CarlsonLanger(graph={p['graph']!r}, n={p['n_blocks']}, k={self.k}, "
            f"sigma={self.sigma}, alpha={self.alpha})"
        )
