"""The springs of a network of blocks, read from a graph once for every model.

A model on a networkx graph takes its springs from the edges (attribute ``k``, else the
model's ``k``) and its per-block values from node attributes; the checks here name the edge
or the node of a bad value.  :class:`~faultnet.model.carlson_langer.CarlsonLanger` and
:class:`~faultnet.model.ofc.OFC` read their graphs through these functions, so that the same
graph gives both models the same springs and frame springs (node attribute ``wall``).

>>> import networkx as nx
>>> g = nx.path_graph(3)
>>> g.edges[0, 1]["k"] = 2.0
>>> spring_matrix(g, {0: 0, 1: 1, 2: 2}, 5.0).toarray().tolist()
[[0.0, 2.0, 0.0], [2.0, 0.0, 5.0], [0.0, 5.0, 0.0]]
"""

from __future__ import annotations

import math

import networkx as nx
import numpy as np

from faultnet.exceptions import InvalidParameterError

__all__ = [
    "as_float",
    "check_eta",
    "check_graph",
    "check_k",
    "check_wall",
    "edge_values",
    "node_values",
    "pattern_values",
    "spring_matrix",
]


def check_k(value, where):
    """Refuse a spring constant that is not finite and > 0 (``where``: the edge, or "")."""
    if not (math.isfinite(value) and value > 0.0):
        raise InvalidParameterError(
            f"spring constant k must be finite and > 0; got {value!r}{where}"
        )


def check_eta(value, where):
    """Refuse a viscous coupling ``eta`` that is not finite and >= 0 (``where``: the edge, or
    "")."""
    if not (math.isfinite(value) and value >= 0.0):
        raise InvalidParameterError(f"eta must be finite and >= 0; got {value!r}{where}")


def check_wall(value, where):
    """Refuse a count of frame springs (node attribute ``wall``) that is not finite and >= 0."""
    if not (math.isfinite(value) and value >= 0.0):
        raise InvalidParameterError(
            f"wall (the frame springs of a block) must be finite and >= 0; got {value!r}{where}"
        )


def as_float(value, name, where=""):
    """``value`` as a float; refuse bools, strings and other non-numbers, naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InvalidParameterError(f"{name} must be a real number; got {value!r}{where}")
    return float(value)


def check_graph(g):
    """Refuse anything but a non-empty undirected simple networkx graph without self-loops."""
    if not isinstance(g, nx.Graph):
        raise InvalidParameterError(
            f"graph must be a networkx.Graph or a faultnet.SparseGraph; got {type(g).__name__}"
        )
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


def _edge_attribute(g, index, name, default, check):
    """(rows, cols, values) of the edge attribute ``name`` (``default`` where unset), one entry
    per edge, each value checked by ``check`` (its error names the edge)."""
    m = g.number_of_edges()
    rows = np.empty(m, dtype=np.int64)
    cols = np.empty(m, dtype=np.int64)
    vals = np.empty(m, dtype=np.float64)
    for e, (a, b, data) in enumerate(g.edges(data=True)):
        where = f" on edge ({a!r}, {b!r})"
        value = as_float(data.get(name, default), name, where)
        check(value, where)
        rows[e], cols[e], vals[e] = index[a], index[b], value
    return rows, cols, vals


def spring_matrix(g, index, k):
    """Symmetric CSR matrix of the spring constants ``k_ij`` (edge attribute ``k``, else ``k``),
    rows in the order of ``index`` (node -> row), indices sorted."""
    import scipy.sparse as sp  # here, not at import: 0.2 s off `import faultnet`

    rows, cols, vals = _edge_attribute(g, index, "k", k, check_k)
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


def pattern_values(adjacency, rows, cols, values, fill=0.0):
    """``values`` at the entries ``(rows, cols)`` laid out as ``adjacency.data``: one value per
    stored entry of ``adjacency``, in its CSR order (``fill`` where none is given).

    Every ``(row, col)`` must be a stored entry of ``adjacency`` (a spring); the first that is
    not is refused.  Give both directions of a symmetric value.

    >>> import scipy.sparse as sp
    >>> A = sp.csr_matrix([[0.0, 1.0, 1.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    >>> pattern_values(A, [0, 1], [1, 0], [0.5, 0.5]).tolist()
    [0.5, 0.0, 0.5, 0.0]
    """
    n = adjacency.shape[0]
    row_of = np.repeat(np.arange(n, dtype=np.int64), np.diff(adjacency.indptr))
    stored = row_of * n + adjacency.indices.astype(np.int64)
    order = np.argsort(stored, kind="stable")
    keys = np.asarray(rows, dtype=np.int64) * n + np.asarray(cols, dtype=np.int64)
    at = np.searchsorted(stored[order], keys)
    found = at < stored.size
    found[found] = stored[order][at[found]] == keys[found]
    if not np.all(found):
        bad = int(np.flatnonzero(~found)[0])
        raise InvalidParameterError(
            f"a value is given between blocks {int(np.asarray(rows)[bad])} and "
            f"{int(np.asarray(cols)[bad])}, which no spring links"
        )
    out = np.full(stored.size, float(fill), dtype=np.float64)
    out[order[at]] = np.asarray(values, dtype=np.float64)
    return out


def edge_values(g, index, adjacency, name, default, check):
    """Edge attribute ``name`` of every spring (``default`` where unset), checked by ``check``
    and laid out as ``adjacency.data`` (both directions of each edge, see
    :func:`pattern_values`); ``adjacency`` is :func:`spring_matrix` of the same graph."""
    if not any(name in data for _, _, data in g.edges(data=True)):
        return np.full(adjacency.nnz, float(default))
    rows, cols, vals = _edge_attribute(g, index, name, default, check)
    return pattern_values(
        adjacency,
        np.concatenate([rows, cols]),
        np.concatenate([cols, rows]),
        np.concatenate([vals, vals]),
    )


def node_values(g, name, default, check):
    """Node attribute ``name`` of every block (``default`` where unset), checked by ``check``."""
    out = np.empty(g.number_of_nodes(), dtype=np.float64)
    for i, (node, data) in enumerate(g.nodes(data=True)):
        where = f" at node {node!r}"
        value = as_float(data.get(name, default), name, where)
        check(value, where)
        out[i] = value
    return out
