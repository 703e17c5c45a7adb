"""A graph given by a sparse matrix: lattices of millions of blocks without networkx."""

from __future__ import annotations

import numpy as np

from faultnet.exceptions import InvalidParameterError
from faultnet.model.springs import check_eta, check_wall, pattern_values

__all__ = ["SparseGraph"]


class SparseGraph:
    """A graph given by a sparse adjacency matrix, for lattices too big for networkx.

    A networkx graph costs about 1 kB per node: a 10^6-block lattice needs over
    1 GB before the simulation starts.  ``SparseGraph`` holds only the CSR
    matrix (about 40 bytes per spring).  Blocks are the integers ``0..n-1``.
    In :class:`~faultnet.CarlsonLanger` the spring between ``i`` and ``j`` is
    ``k * A[i, j]`` (the values are multipliers of the model's ``k``; a 0/1
    pattern gives uniform springs), and the optional per-block ``sigma``,
    ``alpha`` and ``wall`` arrays play the part of node attributes, the optional
    ``eta`` matrix the part of the edge attribute ``eta``.

    Parameters
    ----------
    adjacency : scipy.sparse matrix or array, shape (n, n)
        Symmetric, zero diagonal, finite positive values where there is a spring.
    sigma, alpha : array_like, shape (n,), optional
        Per-block values overriding the model's scalars.
    wall : array_like, shape (n,), optional
        Frame springs per block (finite, >= 0; see ``boundary="fixed"`` in
        :mod:`faultnet.graphs.builders`), each of the model's ``k``.
    eta : scipy.sparse matrix or array, shape (n, n), optional
        The viscous coupling of every spring (symmetric, finite, >= 0), overriding the
        model's scalar ``eta``: entries only where ``adjacency`` has a spring, a spring
        without an entry has ``eta = 0``.  Without it every spring has the model's ``eta``.
    name : str, optional
        Description used in metadata (``graph.graph["name"]``).

    Examples
    --------
    >>> import faultnet
    >>> G = faultnet.graphs.square_lattice(300, 300, periodic=True, sparse=True)
    >>> G.number_of_nodes(), G.number_of_edges()
    (90000, 180000)
    >>> float(faultnet.CarlsonLanger(G, k=16).stiffness[0])
    65.0
    """

    def __init__(self, adjacency, *, sigma=None, alpha=None, wall=None, eta=None, name=None):
        import scipy.sparse as sp

        if not sp.issparse(adjacency):
            adjacency = np.asarray(adjacency, dtype=np.float64)
            if adjacency.ndim != 2:
                raise InvalidParameterError(
                    f"adjacency must be a square matrix; got shape {adjacency.shape}"
                )
        mat = sp.csr_matrix(adjacency, dtype=np.float64)
        mat.sum_duplicates()
        mat.eliminate_zeros()
        n = mat.shape[0]
        if mat.shape != (n, n) or n == 0:
            raise InvalidParameterError(
                f"adjacency must be a non-empty square matrix; got shape {mat.shape}"
            )
        if mat.diagonal().any():
            first = int(np.flatnonzero(mat.diagonal())[0])
            raise InvalidParameterError(
                f"adjacency has a nonzero diagonal (a spring from a block to itself) at {first}"
            )
        if not (np.all(np.isfinite(mat.data)) and np.all(mat.data > 0)):
            raise InvalidParameterError("adjacency values must be finite and > 0")
        if (mat != mat.T).nnz:
            raise InvalidParameterError("adjacency must be symmetric (springs act both ways)")
        mat.sort_indices()
        self.adjacency = mat
        self.node_sigma = self._per_block(sigma, "sigma", n)
        self.node_alpha = self._per_block(alpha, "alpha", n)
        self.node_wall = self._per_block(wall, "wall", n)
        if self.node_wall is not None:
            bad = np.flatnonzero(~(np.isfinite(self.node_wall) & (self.node_wall >= 0)))
            if bad.size:
                check_wall(float(self.node_wall[bad[0]]), f" at node {int(bad[0])}")
        self.edge_eta = None if eta is None else self._per_spring_eta(eta, mat)
        self.graph = {"name": name or f"SparseGraph({n} nodes, {mat.nnz // 2} springs)"}

    @staticmethod
    def _per_block(values, name, n):
        if values is None:
            return None
        arr = np.asarray(values, dtype=np.float64)
        if arr.shape != (n,):
            raise InvalidParameterError(f"{name} must have shape ({n},); got {arr.shape}")
        return arr

    @staticmethod
    def _per_spring_eta(eta, adjacency):
        """The ``eta`` matrix laid out as ``adjacency.data`` (checked: symmetric, finite,
        >= 0, on springs only)."""
        import scipy.sparse as sp

        n = adjacency.shape[0]
        if not sp.issparse(eta):
            eta = np.asarray(eta, dtype=np.float64)
        if eta.shape != (n, n):
            raise InvalidParameterError(f"eta must have shape ({n}, {n}); got {eta.shape}")
        mat = sp.csr_matrix(eta, dtype=np.float64)
        mat.sum_duplicates()
        mat.eliminate_zeros()
        coo = mat.tocoo()
        bad = np.flatnonzero(~(np.isfinite(coo.data) & (coo.data >= 0)))
        if bad.size:
            i, j = int(coo.row[bad[0]]), int(coo.col[bad[0]])
            check_eta(float(coo.data[bad[0]]), f" on edge ({i}, {j})")
        if (mat != mat.T).nnz:
            raise InvalidParameterError("eta must be symmetric (the dashpots act both ways)")
        try:
            return pattern_values(adjacency, coo.row, coo.col, coo.data)
        except InvalidParameterError as exc:
            raise InvalidParameterError(f"eta: {exc}") from None

    def number_of_nodes(self) -> int:
        """Number of blocks."""
        return self.adjacency.shape[0]

    def number_of_edges(self) -> int:
        """Number of springs."""
        return self.adjacency.nnz // 2

    def __repr__(self):
        return f"<SparseGraph {self.graph['name']}>"
