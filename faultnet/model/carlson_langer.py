"""The Carlson-Langer model on a graph: validated parameters and sparse operators."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import networkx as nx
import numpy as np

from faultnet.exceptions import InvalidParameterError
from faultnet.model.faults import fault_numbers
from faultnet.model.sparse_graph import SparseGraph
from faultnet.model.springs import (
    as_float,
    check_eta,
    check_graph,
    check_k,
    check_wall,
    edge_values,
    node_values,
    spring_matrix,
)

if TYPE_CHECKING:  # scipy.sparse is imported where used: 0.2 s off `import faultnet`
    import scipy.sparse as sp

__all__ = ["CarlsonLanger"]  # SparseGraph (imported here too) lives in model.sparse_graph


def _check_sigma(value, where):
    if not (math.isfinite(value) and 0.0 < value < 1.0):
        raise InvalidParameterError(
            f"sigma must lie in the open interval (0, 1); got {value!r}{where}"
        )


def _check_alpha(value, where):
    if not (math.isfinite(value) and value >= 0.0):
        raise InvalidParameterError(f"alpha must be finite and >= 0; got {value!r}{where}")


def _check_nu(value, where):
    if not (math.isfinite(value) and value >= 0.0):
        raise InvalidParameterError(f"nu must be finite and >= 0; got {value!r}{where}")


@dataclass(frozen=True, eq=False)
class CarlsonLanger:
    """Carlson-Langer block-spring model on a networkx graph.

    Blocks of unit mass sit on the nodes; every edge is a spring of constant
    ``k`` (edge attribute ``k`` overrides it), every block is tied to the
    loading plate ``u`` by a unit spring, and slips against the
    velocity-weakening friction ``phi(v) = (1 - sigma) / (1 + 2 alpha v / (1 - sigma))``
    (node attributes ``sigma`` and ``alpha`` override the scalars).  The
    force on block ``i`` is ``F_i = sum_j k_ij (x_j - x_i) + (u - x_i) - k wall_i x_i``:
    a block with the node attribute ``wall`` (a lattice with ``boundary="fixed"``) is
    tied by ``wall_i`` frame springs of constant ``k`` to a rigid frame at rest at
    ``x = 0``, where the plate starts (``u = 0``).

    As Carlson and Langer wrote the model, the plate also moves during slip events, at
    velocity ``nu`` (``du/dt = nu``), and every spring carries a Kelvin dashpot ``eta_ij``
    (edge attribute ``eta`` overrides the scalar ``eta``): a slipping block obeys
    ``x_i'' = F_i + sum_j eta_ij (v_j - v_i) - phi(v_i)``.  ``nu = 0`` and ``eta = 0`` (the
    defaults) give the plate at rest during events and springs without viscosity.

    Parameters
    ----------
    graph : networkx.Graph or SparseGraph
        Undirected simple graph without self-loops.  Any hashable node labels.
        For lattices of ~10^5 blocks and more, a :class:`SparseGraph` (e.g.
        ``graphs.square_lattice(..., sparse=True)``) saves the memory and the
        build time of networkx.
    k, sigma, alpha : float
        Default spring constant (> 0), friction drop (in (0, 1)) and velocity
        weakening rate (>= 0) for edges and nodes without attributes.
    nu : float
        Velocity of the loading plate during slip events (finite, >= 0; default 0: the
        plate stands still while blocks slip).
    eta : float
        Default viscous coupling of the springs (finite, >= 0; default 0) for edges without
        the attribute ``eta``; on a :class:`SparseGraph`, for every spring unless the graph
        has its own ``eta`` matrix.

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
    wall_values : numpy.ndarray
        Frame springs per block (node attribute ``wall``, 0 where unset), node order.
    eta_values : numpy.ndarray
        The viscous coupling ``eta_ij`` of every stored entry of ``adjacency``, laid out as
        ``adjacency.data`` (the same ``indices`` and ``indptr``; symmetric, float64).
    faults : list or None
        The fault labels of a network of faults (node attribute ``fault``, set on every
        block or on none), in order of first appearance; None without them.
    fault_number : numpy.ndarray or None
        Each block's index into ``faults`` (int64, node order).

    Examples
    --------
    >>> import faultnet
    >>> model = faultnet.CarlsonLanger(faultnet.graphs.ring(5), k=16, sigma=0.01, alpha=1.5)
    >>> model.n, float(model.laplacian.diagonal()[0])
    (5, 32.0)
    >>> model.with_params(alpha=2.0).alpha
    2.0

    The plate moving during events and viscous springs:

    >>> model = faultnet.CarlsonLanger(faultnet.graphs.ring(5), nu=0.01, eta=0.1)
    >>> model.nu, model.eta
    (0.01, 0.1)
    >>> model.viscous, model.eta_values.shape == model.adjacency.data.shape
    (True, True)
    """

    graph: nx.Graph
    k: float = 16.0
    sigma: float = 0.01
    alpha: float = 1.0
    nu: float = 0.0
    eta: float = 0.0
    nodes: list = field(init=False, repr=False)
    adjacency: sp.csr_matrix = field(init=False, repr=False)
    sigma_values: np.ndarray = field(init=False, repr=False)
    alpha_values: np.ndarray = field(init=False, repr=False)
    wall_values: np.ndarray = field(init=False, repr=False)
    eta_values: np.ndarray = field(init=False, repr=False)
    faults: list | None = field(init=False, repr=False, default=None)
    fault_number: np.ndarray | None = field(init=False, repr=False, default=None)

    def __post_init__(self):
        g = self.graph
        set_ = object.__setattr__
        set_(self, "k", as_float(self.k, "k"))
        set_(self, "sigma", as_float(self.sigma, "sigma"))
        set_(self, "alpha", as_float(self.alpha, "alpha"))
        set_(self, "nu", as_float(self.nu, "nu"))
        set_(self, "eta", as_float(self.eta, "eta"))
        check_k(self.k, "")
        _check_sigma(self.sigma, "")
        _check_alpha(self.alpha, "")
        _check_nu(self.nu, "")
        check_eta(self.eta, "")
        if isinstance(g, SparseGraph):
            self._init_sparse(g)
            return
        check_graph(g)
        nodes = list(g.nodes)
        index = {node: i for i, node in enumerate(nodes)}
        set_(self, "nodes", nodes)
        set_(self, "adjacency", spring_matrix(g, index, self.k))
        set_(self, "eta_values", edge_values(g, index, self.adjacency, "eta", self.eta, check_eta))
        set_(self, "sigma_values", node_values(g, "sigma", self.sigma, _check_sigma))
        set_(self, "alpha_values", node_values(g, "alpha", self.alpha, _check_alpha))
        set_(self, "wall_values", node_values(g, "wall", 0.0, check_wall))
        faults, number = fault_numbers(g)
        set_(self, "faults", faults)
        set_(self, "fault_number", number)

    def _init_sparse(self, g):
        set_ = object.__setattr__
        n = g.number_of_nodes()
        set_(self, "nodes", range(n))
        set_(self, "adjacency", g.adjacency * self.k)
        for name, default, values, valid, check in (
            ("sigma", self.sigma, g.node_sigma, lambda v: (v > 0) & (v < 1), _check_sigma),
            ("alpha", self.alpha, g.node_alpha, lambda v: v >= 0, _check_alpha),
        ):
            arr = np.full(n, default) if values is None else values.copy()
            bad = np.flatnonzero(~(np.isfinite(arr) & valid(arr)))
            if bad.size:
                check(float(arr[bad[0]]), f" at node {int(bad[0])}")
            set_(self, f"{name}_values", arr)
        wall = np.zeros(n) if g.node_wall is None else g.node_wall.copy()
        set_(self, "wall_values", wall)
        nnz = self.adjacency.nnz
        eta = np.full(nnz, self.eta) if g.edge_eta is None else g.edge_eta.copy()
        set_(self, "eta_values", eta)

    @property
    def n(self) -> int:
        """Number of blocks."""
        return len(self.nodes)

    @cached_property
    def viscous(self) -> bool:
        """True when some spring has a viscous coupling (an ``eta`` value > 0).  Computed once."""
        return bool(np.any(self.eta_values > 0.0))

    def _viscosity(self):
        """The matrix of the ``eta_ij`` (CSR, the pattern of ``adjacency``) and its row sums."""
        import scipy.sparse as sp

        adj = self.adjacency
        eta = sp.csr_matrix((self.eta_values, adj.indices, adj.indptr), shape=adj.shape)
        return eta, np.asarray(eta.sum(axis=1)).ravel()

    @property
    def laplacian(self) -> sp.csr_matrix:
        """Weighted graph Laplacian ``L = diag(K 1) - K`` (CSR)."""
        import scipy.sparse as sp

        deg = np.asarray(self.adjacency.sum(axis=1)).ravel()
        return (sp.diags(deg) - self.adjacency).tocsr()

    @property
    def frame(self) -> np.ndarray:
        """Stiffness of each block's frame springs, ``k * wall_i`` (zeros without walls)."""
        return self.k * self.wall_values

    @property
    def stiffness(self) -> np.ndarray:
        """Total stiffness seen by each block when its neighbours are held:
        ``1 + sum_j k_ij + k wall_i``."""
        base = 1.0 + np.asarray(self.adjacency.sum(axis=1)).ravel()
        return base + self.frame if np.any(self.wall_values) else base

    @cached_property
    def top_stiffness(self) -> float:
        """Largest eigenvalue of the stiffness matrix ``I + L`` (plus the frame springs,
        ``diag(k wall)``), estimated from above.

        It sets the scale of the step inside events (see :mod:`faultnet.model.spectrum`).
        Computed once.

        >>> import faultnet
        >>> faultnet.CarlsonLanger(faultnet.graphs.ring(100), k=16).top_stiffness
        65.0
        """
        from faultnet.model.spectrum import top_stiffness

        return top_stiffness(self.adjacency, self.frame if np.any(self.wall_values) else None)

    @cached_property
    def block_classes(self) -> np.ndarray:
        """Class index per block: blocks with equal stiffness, sigma and alpha (and, with
        viscous springs, equal total ``eta``, the sum over the block's springs) share one.

        A block slipping alone moves the same way in every block of its class
        (the simulator caches that solo slip per class).  Computed once.
        """
        cols = (self.stiffness, self.sigma_values, self.alpha_values)
        if self.viscous:
            cols += (self._viscosity()[1],)
        if all(np.all(c == c[0]) for c in cols):
            return np.zeros(self.n, dtype=np.int64)
        _, inv = np.unique(np.column_stack(cols), axis=0, return_inverse=True)
        return inv.astype(np.int64).ravel()

    def forces(self, x, u=0.0, v=None) -> np.ndarray:
        """Spring force ``F_i = sum_j k_ij (x_j - x_i) + (u - x_i) - k wall_i x_i`` on every
        block; with the velocities ``v``, plus the viscous force
        ``sum_j eta_ij (v_j - v_i)`` of the dashpots (none without viscous springs).

        >>> import faultnet
        >>> m = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=1.0, eta=0.5)
        >>> m.forces([0.0, 0.0], u=1.0, v=[0.0, 2.0]).tolist()
        [2.0, 0.0]
        """
        x = np.asarray(x, dtype=np.float64)
        force = -(self.laplacian @ x) + (u - x) - self.frame * x
        if v is not None and self.viscous:
            v = np.asarray(v, dtype=np.float64)
            eta, total = self._viscosity()
            force += eta @ v - total * v
        return force

    def with_params(self, *, k=None, sigma=None, alpha=None, nu=None, eta=None) -> CarlsonLanger:
        """A model on the same graph with some scalar parameters replaced.

        Per-edge and per-node attributes of the graph still take precedence.
        """
        return CarlsonLanger(
            self.graph,
            k=self.k if k is None else k,
            sigma=self.sigma if sigma is None else sigma,
            alpha=self.alpha if alpha is None else alpha,
            nu=self.nu if nu is None else nu,
            eta=self.eta if eta is None else eta,
        )

    @property
    def params(self) -> dict:
        """Scalar parameters and a description of the graph, for metadata."""
        heterogeneous, frame_springs, eta_heterogeneous = self._array_summary
        params = {
            "graph": self.graph.graph.get("name", f"{type(self.graph).__name__}({self.n} nodes)"),
            "n_blocks": self.n,
            "n_springs": int(self.adjacency.nnz // 2),
            "k": self.k,
            "sigma": self.sigma,
            "alpha": self.alpha,
            "heterogeneous": heterogeneous,
        }
        if frame_springs:  # only then: the metadata of other runs stays as it was
            params["frame_springs"] = frame_springs
        # nu and eta likewise only where they are not 0
        if self.nu:
            params["nu"] = self.nu
        if self.eta or self.viscous:
            params["eta"] = self.eta
            params["eta_heterogeneous"] = eta_heterogeneous
        return params

    @cached_property
    def _array_summary(self) -> tuple:
        """What :attr:`params` reads from the per-block and per-spring arrays, computed once
        (every chunk of a run records it: 7 ms a chunk on a 1024^2 lattice): whether the
        parameters vary, the frame springs' total and whether the ``eta`` values vary."""
        heterogeneous = bool(
            np.any(self.sigma_values != self.sigma)
            or np.any(self.alpha_values != self.alpha)
            or np.any(self.adjacency.data != self.k)
        )
        frame_springs = float(self.wall_values.sum()) if np.any(self.wall_values) else 0.0
        return heterogeneous, frame_springs, bool(np.any(self.eta_values != self.eta))

    def __repr__(self):
        p = self.params
        kelvin = "".join(f", {name}={p[name]}" for name in ("nu", "eta") if name in p)
        return (
            f"CarlsonLanger(graph={p['graph']!r}, n={p['n_blocks']}, k={self.k}, "
            f"sigma={self.sigma}, alpha={self.alpha}{kelvin})"
        )
