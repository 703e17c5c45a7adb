"""Graph constructors for block-spring fault networks.

Every constructor returns a :class:`networkx.Graph` whose nodes are blocks and
whose edges are the coupling springs between neighbouring blocks.  Lattice
constructors attach a ``pos`` node attribute (an ``(x, y)`` tuple of floats,
in units of the lattice spacing) and set ``G.graph["name"]`` to a readable
description such as ``"square_lattice(150, 150, periodic=True)"``.

:func:`site_percolation` dilutes any such graph by occupying each node
independently with probability ``p``; :func:`percolation_threshold` gives the
site-percolation thresholds of the two supported lattices.
"""

from __future__ import annotations

import math
import numbers

import networkx as nx
import numpy as np

from faultnet._validate import check_int, generator_and_seed
from faultnet.exceptions import InvalidParameterError

__all__ = [
    "chain",
    "ring",
    "square_lattice",
    "triangular_lattice",
    "site_percolation",
    "percolation_threshold",
]

_THRESHOLDS = {"square": 0.592746, "triangular": 0.5}
_KEEP_VALUES = ("largest", "all")


def chain(n):
    """Open chain (path) of ``n`` blocks.

    Parameters
    ----------
    n : int
        Number of blocks, ``n >= 1``.

    Returns
    -------
    networkx.Graph
        Nodes ``0 .. n-1``, edges ``(i, i + 1)`` and ``pos = (float(i), 0.0)``.

    Examples
    --------
    >>> from faultnet.graphs.builders import chain
    >>> G = chain(4)
    >>> G.number_of_edges(), G.nodes[3]["pos"], G.graph["name"]
    (3, (3.0, 0.0), 'chain(4)')
    """
    n = check_int("n", n)
    G = nx.Graph(name=f"chain({n})")
    G.add_nodes_from((i, {"pos": (float(i), 0.0)}) for i in range(n))
    G.add_edges_from((i, i + 1) for i in range(n - 1))
    return G


def ring(n):
    """Periodic ring of ``n`` blocks.

    Parameters
    ----------
    n : int
        Number of blocks, ``n >= 3``.  A ring of two blocks would couple them
        twice (a doubled spring), so use ``chain(2)`` instead.

    Returns
    -------
    networkx.Graph
        Nodes ``0 .. n-1`` and ``n`` edges ``(i, (i + 1) % n)``.  Positions lie
        on a circle of radius ``n / (2 pi)`` so neighbours are about 1 apart.

    Examples
    --------
    >>> from faultnet.graphs.builders import ring
    >>> G = ring(6)
    >>> G.number_of_edges(), sorted(G[0]), G.graph["name"]
    (6, [1, 5], 'ring(6)')
    """
    n = check_int("n", n)
    if n < 3:
        raise InvalidParameterError(
            f"ring needs n >= 3, got n={n}: ring({n}) would double the spring between "
            f"its blocks (or make a self-loop); use chain({n}) instead"
        )
    radius = n / (2.0 * math.pi)
    G = nx.Graph(name=f"ring({n})")
    for i in range(n):
        theta = 2.0 * math.pi * i / n
        G.add_node(i, pos=(radius * math.cos(theta), radius * math.sin(theta)))
    G.add_edges_from((i, (i + 1) % n) for i in range(n))
    return G


def _lattice_name(kind, rows, cols, periodic):
    suffix = ", periodic=True" if periodic else ""
    return f"{kind}({rows}, {cols}{suffix})"


def square_lattice(rows, cols, periodic=False, sparse=False):
    """Square lattice of ``rows x cols`` blocks with 4-neighbour springs.

    Parameters
    ----------
    rows, cols : int
        Lattice size, each ``>= 1`` (``>= 3`` when ``periodic``).
    periodic : bool, optional
        Wrap both directions (a torus).  Every node then has degree 4.
    sparse : bool, optional
        Return a :class:`faultnet.SparseGraph` (the adjacency only, built with
        numpy in well under a second for 10^6 blocks and ~50 MB) instead of a
        networkx graph (~1 GB and ~10 s at that size).  Same node numbering.

    Returns
    -------
    networkx.Graph or SparseGraph
        Node ``r * cols + c`` sits at ``pos = (float(c), float(r))``.  The open
        lattice has ``2*rows*cols - rows - cols`` edges, the periodic one
        ``2*rows*cols``.

    Examples
    --------
    >>> from faultnet.graphs.builders import square_lattice
    >>> G = square_lattice(2, 3)
    >>> G.number_of_nodes(), G.number_of_edges(), G.nodes[4]["pos"]
    (6, 7, (1.0, 1.0))
    >>> square_lattice(3, 3, periodic=True).number_of_edges()
    18
    """
    rows = check_int("rows", rows)
    cols = check_int("cols", cols)
    periodic = bool(periodic)
    if periodic and (rows < 3 or cols < 3):
        raise InvalidParameterError(
            f"periodic square_lattice needs rows >= 3 and cols >= 3, got rows={rows}, "
            f"cols={cols}: wrapping would create duplicate edges or self-loops"
        )
    name = _lattice_name("square_lattice", rows, cols, periodic)
    if sparse:
        return _square_sparse(rows, cols, periodic, name)
    G = nx.Graph(name=name)
    for r in range(rows):
        for c in range(cols):
            G.add_node(r * cols + c, pos=(float(c), float(r)))
    for r in range(rows):
        for c in range(cols):
            node = r * cols + c
            if c + 1 < cols or periodic:
                G.add_edge(node, r * cols + (c + 1) % cols)
            if r + 1 < rows or periodic:
                G.add_edge(node, ((r + 1) % rows) * cols + c)
    return G


def _square_sparse(rows, cols, periodic, name):
    import scipy.sparse as sp  # here, not at import: 0.2 s off `import faultnet`

    from faultnet.model.carlson_langer import SparseGraph

    node = np.arange(rows * cols, dtype=np.int64).reshape(rows, cols)
    right = np.roll(node, -1, axis=1) if periodic else node[:, 1:]
    down = np.roll(node, -1, axis=0) if periodic else node[1:, :]
    a = np.concatenate(
        [(node if periodic else node[:, :-1]).ravel(), (node if periodic else node[:-1, :]).ravel()]
    )
    b = np.concatenate([right.ravel(), down.ravel()])
    n = rows * cols
    ones = np.ones(2 * a.size)
    adj = sp.csr_matrix((ones, (np.concatenate([a, b]), np.concatenate([b, a]))), shape=(n, n))
    return SparseGraph(adj, name=name)


def triangular_lattice(rows, cols, periodic=False):
    """Triangular lattice of ``rows x cols`` blocks with 6-neighbour springs.

    Rows are offset by half a spacing ("odd-r" layout): odd rows are shifted
    right by 0.5, so every bond has Euclidean length 1 and each interior node
    has exactly six neighbours.

    Parameters
    ----------
    rows, cols : int
        Lattice size, each ``>= 1``.  When ``periodic``, ``rows`` must be even
        and ``>= 4`` (so the row offsets match across the seam and the rows
        above and below a node differ) and ``cols >= 3``.
    periodic : bool, optional
        Wrap both directions.  Every node then has degree 6 and there are
        ``3 * rows * cols`` edges.

    Returns
    -------
    networkx.Graph
        Node ``r * cols + c`` sits at ``pos = (c + 0.5 * (r % 2), r * sqrt(3) / 2)``.

    Examples
    --------
    >>> from faultnet.graphs.builders import triangular_lattice
    >>> G = triangular_lattice(3, 3)
    >>> G.degree(4), G.nodes[4]["pos"][0]
    (6, 1.5)
    >>> H = triangular_lattice(4, 3, periodic=True)
    >>> H.number_of_edges(), {d for _, d in H.degree()}
    (36, {6})
    """
    rows = check_int("rows", rows)
    cols = check_int("cols", cols)
    periodic = bool(periodic)
    if periodic and (rows < 4 or rows % 2 or cols < 3):
        raise InvalidParameterError(
            f"periodic triangular_lattice needs an even rows >= 4 and cols >= 3, got "
            f"rows={rows}, cols={cols}: an odd row count breaks the row offsets across "
            f"the seam, and smaller sizes would create duplicate edges"
        )
    height = math.sqrt(3.0) / 2.0
    G = nx.Graph(name=_lattice_name("triangular_lattice", rows, cols, periodic))
    for r in range(rows):
        for c in range(cols):
            G.add_node(r * cols + c, pos=(c + 0.5 * (r % 2), r * height))
    for r in range(rows):
        # Neighbours in the next row: columns (c-1, c) from an even row,
        # (c, c+1) from an odd (shifted) row.
        up_offsets = (-1, 0) if r % 2 == 0 else (0, 1)
        for c in range(cols):
            node = r * cols + c
            if c + 1 < cols or periodic:
                G.add_edge(node, r * cols + (c + 1) % cols)
            if r + 1 >= rows and not periodic:
                continue
            r_up = (r + 1) % rows
            for dc in up_offsets:
                c_up = c + dc
                if 0 <= c_up < cols or periodic:
                    G.add_edge(node, r_up * cols + c_up % cols)
    return G


def percolation_threshold(kind):
    """Site-percolation threshold of a two-dimensional lattice.

    Parameters
    ----------
    kind : {"square", "triangular"}
        Lattice type.

    Returns
    -------
    float
        ``0.592746`` for the square lattice, ``0.5`` for the triangular one.

    Examples
    --------
    >>> from faultnet.graphs.builders import percolation_threshold
    >>> percolation_threshold("square"), percolation_threshold("triangular")
    (0.592746, 0.5)
    """
    try:
        return _THRESHOLDS[kind]
    except (KeyError, TypeError):
        allowed = ", ".join(repr(k) for k in _THRESHOLDS)
        raise InvalidParameterError(
            f"unknown lattice kind {kind!r}; expected one of {allowed}"
        ) from None


def _generator_and_record(rng):
    """``(generator, seed)``: SPEC 7 ``rng`` and the seed recorded in ``G.graph["seed"]``.

    The record is the int seed or the SeedSequence entropy; None for a Generator.
    """
    generator, seq = generator_and_seed(rng)
    return generator, None if isinstance(rng, np.random.Generator) else seq.entropy


def _smallest_label_key(component, order):
    """Sort key for tie-breaking: smallest label, else earliest in node order."""
    try:
        return (0, min(component))
    except TypeError:
        return (1, min(order[node] for node in component))


def _induced_copy(graph, kept):
    """New ``nx.Graph`` induced on ``kept`` (in that order), copying attributes."""
    kept_set = set(kept)
    result = nx.Graph()
    result.graph.update(graph.graph)
    result.add_nodes_from((node, dict(graph.nodes[node])) for node in kept)
    result.add_edges_from(
        (u, v, dict(data)) for u in kept for v, data in graph.adj[u].items() if v in kept_set
    )
    return result


def site_percolation(graph, p, rng=None, keep="largest", prune_isolated=False):
    """Site-diluted copy of ``graph``: each node is kept with probability ``p``.

    Parameters
    ----------
    graph : networkx.Graph
        Undirected parent graph (for example a lattice from this module).
    p : float
        Occupation probability, ``0 <= p <= 1``.
    rng : None, int, numpy.random.SeedSequence or numpy.random.Generator, optional
        Source of randomness (SPEC 7).  One uniform number is drawn per node,
        in the order of ``list(graph.nodes)``, so a fixed seed is reproducible.
    keep : {"largest", "all"}, optional
        ``"largest"`` keeps only the largest connected cluster (ties go to the
        cluster holding the smallest node label); ``"all"`` keeps every
        occupied node.
    prune_isolated : bool, optional
        Drop occupied nodes of degree 0.

    Returns
    -------
    networkx.Graph
        A new graph induced on the kept nodes, with the parent's node labels
        and node/edge attributes (including ``pos``).  ``G.graph`` records
        ``"name"``, ``"p"``, ``"keep"``, ``"prune_isolated"`` and ``"seed"``
        (the int seed, the SeedSequence entropy, or None for a Generator).

    Raises
    ------
    InvalidParameterError
        If ``graph`` is not an undirected networkx graph, ``p`` is outside
        ``[0, 1]``, ``keep`` is unknown, or no node remains.

    Examples
    --------
    >>> from faultnet.graphs.builders import site_percolation, square_lattice
    >>> L = square_lattice(20, 20)
    >>> G = site_percolation(L, 0.8, rng=1)
    >>> import networkx as nx
    >>> nx.is_connected(G), G.graph["seed"], set(G) <= set(L)
    (True, 1, True)
    >>> G.graph["name"]
    "site_percolation(square_lattice(20, 20), p=0.8, keep='largest')"
    """
    if not isinstance(graph, nx.Graph) or graph.is_directed():
        raise InvalidParameterError(
            f"graph must be an undirected networkx.Graph, got {type(graph).__name__}"
        )
    if isinstance(p, bool | np.bool_) or not isinstance(p, numbers.Real):
        raise InvalidParameterError(f"p must be a real number in [0, 1], got p={p!r}")
    p = float(p)
    if not 0.0 <= p <= 1.0:
        raise InvalidParameterError(f"p must lie in [0, 1], got p={p!r}")
    if keep not in _KEEP_VALUES:
        allowed = ", ".join(repr(k) for k in _KEEP_VALUES)
        raise InvalidParameterError(f"keep must be one of {allowed}, got keep={keep!r}")
    prune_isolated = bool(prune_isolated)
    generator, seed = _generator_and_record(rng)

    nodes = list(graph.nodes)
    draws = generator.random(len(nodes))
    occupied = [node for node, u in zip(nodes, draws, strict=True) if u < p]
    n_total = len(nodes)
    if not occupied:
        raise InvalidParameterError(
            f"no site occupied at p={p!r} on a {n_total}-node graph; increase p"
        )

    sub = graph.subgraph(occupied)
    if keep == "largest":
        order = {node: i for i, node in enumerate(nodes)}
        components = list(nx.connected_components(sub))
        biggest = max(len(comp) for comp in components)
        ties = [comp for comp in components if len(comp) == biggest]
        chosen = min(ties, key=lambda comp: _smallest_label_key(comp, order))
        sub = graph.subgraph(chosen)
    if prune_isolated:
        sub = graph.subgraph(node for node in sub if sub.degree(node) > 0)
        if sub.number_of_nodes() == 0:
            raise InvalidParameterError(
                f"only isolated sites occupied at p={p!r} on a {n_total}-node graph "
                f"(prune_isolated=True left nothing); increase p"
            )

    result = _induced_copy(graph, [node for node in nodes if node in sub])
    parent = graph.graph.get("name") or f"graph({n_total} nodes)"
    extra = ", prune_isolated=True" if prune_isolated else ""
    result.graph["name"] = f"site_percolation({parent}, p={p!r}, keep={keep!r}{extra})"
    result.graph["p"] = p
    result.graph["keep"] = keep
    result.graph["prune_isolated"] = prune_isolated
    result.graph["seed"] = seed
    return result
