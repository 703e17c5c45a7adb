"""The Olami-Feder-Christensen automaton on a graph: validated springs and forces.

The OFC automaton (Olami, Feder and Christensen, PRL 68, 1244, 1992) is the quasi-static
limit of the block-spring network of :class:`~faultnet.CarlsonLanger`: the same blocks,
springs ``k_ij`` (edge attribute ``k``, else the model's ``k``), unit plate springs and frame
springs (node attribute ``wall``, each of the model's ``k``), but only the forces are tracked:

- **drive**: all forces grow together until the largest reaches the threshold 1 (the jump is
  exact);
- **toppling**: a block with ``F_i >= 1`` slips by ``dx_i = F_i / K_i``, with
  ``K_i = sum_j k_ij + k wall_i + 1``, to the residual force 0, and each neighbour ``j``
  gains ``k_ij dx_i``; the frame springs and the plate spring take the rest;
- **update** (``update="synchronous"``, as in OFC 1992): every block at or over the threshold
  at the start of a generation topples in that generation, with the force it has then.

On a lattice of coordination ``q`` (degree plus walls, the same for every block: a periodic
or a ``boundary="fixed"`` lattice) with uniform ``k``, a toppling block passes the fraction
``alpha = k / (q k + 1)`` of its force to each neighbour: OFC's conservation parameter,
``alpha = 0.2`` for ``k = 1`` on the square lattice.  ``alpha < 1/q`` always (the plate
spring dissipates), and :meth:`OFC.from_alpha` refuses ``alpha >= 1/q``.

The state between avalanches is a :class:`~faultnet.State` whose ``z`` are the blocks'
*keys*: the drive (relative to ``offset``) at which each block reaches the threshold, so the
force on block ``i`` is ``F_i = 1 + w - z_i`` (:meth:`OFC.forces`), ``offset + w`` the total
drive so far.

>>> import faultnet
>>> model = faultnet.OFC(faultnet.graphs.square_lattice(5, 5, boundary="fixed"), k=1.0)
>>> model.alpha, float(model.stiffness[0])
(0.2, 5.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from faultnet.exceptions import InvalidParameterError
from faultnet.model.carlson_langer import SparseGraph
from faultnet.model.faults import fault_numbers
from faultnet.model.springs import (
    as_float,
    check_graph,
    check_k,
    check_wall,
    node_values,
    spring_matrix,
)

if TYPE_CHECKING:
    import networkx as nx
    import scipy.sparse as sp

__all__ = ["OFC", "UPDATES"]

#: the update rules of an avalanche
UPDATES = ("synchronous",)


def _coordination(model):
    """Each block's springs: its degree plus its frame springs."""
    return np.diff(model.adjacency.indptr) + model.wall_values


def _k_for_alpha(alpha, q):
    """The ``k`` nearest ``alpha / (1 - q alpha)`` for which ``k / (q k + 1)`` gives ``alpha``
    back in float64, preferring the shortest decimal (``k = 1`` for 0.2 on the square
    lattice, not 1.0000000000000002)."""
    k0 = alpha / (1.0 - q * alpha)
    candidates = [round(k0, d) for d in (6, 9, 12)]
    candidates += [k0, np.nextafter(k0, 0.0), np.nextafter(k0, np.inf)]
    for k in candidates:
        if k > 0.0 and k / (q * k + 1.0) == alpha:
            return float(k)
    return float(k0)


@dataclass(frozen=True, eq=False)
class OFC:
    """The Olami-Feder-Christensen automaton on a graph (see the module's text).

    Parameters
    ----------
    graph : networkx.Graph or SparseGraph
        Undirected simple graph without self-loops; node attributes ``wall`` (frame springs,
        e.g. from ``boundary="fixed"``) and ``fault`` (a network of faults: the events get
        ``fault`` and ``n_faults`` columns) as for :class:`~faultnet.CarlsonLanger`, edge
        attribute ``k`` for a spring of its own.
    k : float
        Spring constant (> 0) of the edges without a ``k`` and of every frame spring.
    update : {"synchronous"}
        The toppling rule of an avalanche (see the module's text).

    Attributes
    ----------
    nodes : list
        Node labels in the order of every array.
    adjacency : scipy.sparse.csr_matrix
        Symmetric matrix of spring constants ``k_ij``.
    wall_values : numpy.ndarray
        Frame springs per block (0 where unset).
    faults, fault_number
        The fault labels and each block's index into them (None without faults).

    Raises
    ------
    InvalidParameterError
        For an empty, directed or self-looped graph, ``k`` not finite and > 0, a bad
        edge ``k`` or node ``wall``, or an unknown ``update``.

    Examples
    --------
    >>> import faultnet
    >>> g = faultnet.graphs.square_lattice(32, 32, boundary="fixed")
    >>> model = faultnet.OFC.from_alpha(g, 0.2)
    >>> model.k, model.params["alpha"]
    (1.0, 0.2)
    >>> res = faultnet.simulate(model, 1000, rng=1, progress=False)
    >>> list(res.events.columns)
    ['event', 't', 'n_topplings', 'n_blocks', 'S', 'M', 'hypocenter', 'n_generations']
    """

    graph: nx.Graph
    k: float = 1.0
    update: str = "synchronous"
    nodes: list = field(init=False, repr=False)
    adjacency: sp.csr_matrix = field(init=False, repr=False)
    wall_values: np.ndarray = field(init=False, repr=False)
    faults: list | None = field(init=False, repr=False, default=None)
    fault_number: np.ndarray | None = field(init=False, repr=False, default=None)

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "k", as_float(self.k, "k"))
        check_k(self.k, "")
        if not isinstance(self.update, str) or self.update not in UPDATES:
            allowed = ", ".join(repr(u) for u in UPDATES)
            raise InvalidParameterError(f"update must be one of {allowed}; got {self.update!r}")
        g = self.graph
        if isinstance(g, SparseGraph):
            n = g.number_of_nodes()
            set_(self, "nodes", range(n))
            set_(self, "adjacency", g.adjacency * self.k)
            set_(self, "wall_values", np.zeros(n) if g.node_wall is None else g.node_wall.copy())
            return
        check_graph(g)
        nodes = list(g.nodes)
        set_(self, "nodes", nodes)
        set_(self, "adjacency", spring_matrix(g, {v: i for i, v in enumerate(nodes)}, self.k))
        set_(self, "wall_values", node_values(g, "wall", 0.0, check_wall))
        faults, number = fault_numbers(g)
        set_(self, "faults", faults)
        set_(self, "fault_number", number)

    @classmethod
    def from_alpha(cls, graph, alpha, **kwargs) -> OFC:
        """The automaton of conservation parameter ``alpha`` on a graph of uniform coordination.

        Every block must have the same coordination ``q`` (degree plus ``wall``): a periodic
        lattice, a ``boundary="fixed"`` one, a ring.  Then ``k = alpha / (1 - q alpha)``, so
        that a toppling block passes ``alpha = k / (q k + 1)`` of its force to each
        neighbour.  Every spring gets this ``k`` (edges with their own ``k`` are refused).

        Parameters
        ----------
        graph : networkx.Graph or SparseGraph
        alpha : float
            In ``(0, 1/q)``: at ``alpha >= 1/q`` no force would be dissipated (no steady
            state), and no ``k`` gives it.
        **kwargs
            Passed to :class:`OFC` (``update``).

        Examples
        --------
        >>> import faultnet
        >>> tri = faultnet.graphs.triangular_lattice(8, 8, periodic=True)
        >>> faultnet.OFC.from_alpha(tri, 0.15).k
        1.5
        >>> faultnet.OFC.from_alpha(faultnet.graphs.square_lattice(4, 4), 0.2)
        Traceback (most recent call last):
        ...
        faultnet.exceptions.InvalidParameterError: from_alpha needs every block to have the ...
        """
        alpha = as_float(alpha, "alpha")
        probe = cls(graph, k=1.0, **kwargs)
        if np.any(probe.adjacency.data != 1.0):
            raise InvalidParameterError(
                "from_alpha sets every spring's k, but some edges of this graph carry their own "
                "k; give k to OFC(graph, k=...) instead"
            )
        q = _coordination(probe)
        lo, hi = float(q.min()), float(q.max())
        if lo != hi:
            raise InvalidParameterError(
                f"from_alpha needs every block to have the same coordination q = degree + "
                f"wall; this graph has q from {lo:g} to {hi:g}. Build the lattice with "
                "boundary='fixed' or boundary='periodic', or give k to OFC(graph, k=...)"
            )
        if not (math.isfinite(alpha) and 0.0 < alpha and (hi == 0 or alpha * hi < 1.0)):
            limit = f"1/q = {1.0 / hi:g}" if hi else "infinity"
            raise InvalidParameterError(
                f"alpha must lie in (0, {limit}) on a graph of coordination q = {hi:g}; got "
                f"alpha={alpha!r}: at alpha >= 1/q a toppling block would dissipate nothing "
                "(no steady state, no finite k)"
            )
        return cls(graph, k=_k_for_alpha(alpha, hi), **kwargs)

    @property
    def n(self) -> int:
        """Number of blocks."""
        return len(self.nodes)

    @property
    def frame(self) -> np.ndarray:
        """Stiffness of each block's frame springs, ``k * wall_i``."""
        return self.k * self.wall_values

    @property
    def stiffness(self) -> np.ndarray:
        """``K_i = sum_j k_ij + k wall_i + 1``: a toppling block slips by ``F_i / K_i``.

        A block whose springs all have the model's ``k`` gets ``1 + k q_i`` (``q_i`` its
        degree plus walls), one rounding: blocks of equal coordination get equal ``K``
        whatever the order of their springs.
        """
        adj = self.adjacency
        deg = np.diff(adj.indptr)
        rows = np.repeat(np.arange(self.n), deg)
        plain = np.bincount(rows, weights=adj.data == self.k, minlength=self.n) == deg
        summed = 1.0 + np.asarray(adj.sum(axis=1)).ravel() + self.frame
        return np.where(plain, 1.0 + self.k * (deg + self.wall_values), summed)

    @cached_property
    def alpha(self) -> float | None:
        """OFC's conservation parameter ``k / K``, where every spring has the model's ``k`` and
        every block the same stiffness ``K``; None otherwise.  Computed once."""
        stiff = self.stiffness
        if np.any(self.adjacency.data != self.k) or np.any(stiff != stiff[0]):
            return None
        return self.k / float(stiff[0])

    def forces(self, state) -> np.ndarray:
        """The force on every block in a :class:`~faultnet.State` of this automaton:
        ``F_i = 1 + w - z_i`` (node order)."""
        return 1.0 + state.w - np.asarray(state.z, dtype=np.float64)

    def with_params(self, *, k=None, update=None) -> OFC:
        """The automaton on the same graph with ``k`` or ``update`` replaced."""
        return OFC(
            self.graph,
            k=self.k if k is None else k,
            update=self.update if update is None else update,
        )

    @property
    def params(self) -> dict:
        """Parameters and a description of the graph, for metadata."""
        heterogeneous, frame_springs = self._array_summary
        params = {
            "model": "ofc",
            "graph": self.graph.graph.get("name", f"{type(self.graph).__name__}({self.n} nodes)"),
            "n_blocks": self.n,
            "n_springs": int(self.adjacency.nnz // 2),
            "k": self.k,
            "alpha": self.alpha,
            "update": self.update,
            "heterogeneous": heterogeneous,
        }
        if frame_springs:
            params["frame_springs"] = frame_springs
        return params

    @cached_property
    def _array_summary(self) -> tuple:
        """What :attr:`params` reads from the springs and walls, computed once (every chunk of
        a run records it): whether the springs differ from ``k``, the frame springs' total."""
        frame_springs = float(self.wall_values.sum()) if np.any(self.wall_values) else 0.0
        return bool(np.any(self.adjacency.data != self.k)), frame_springs

    def __repr__(self):
        p = self.params
        return f"OFC(graph={p['graph']!r}, n={p['n_blocks']}, k={self.k}, alpha={p['alpha']})"
