"""Site percolation: dilute a graph by occupying each node independently with probability ``p``.

:func:`site_percolation` keeps the largest cluster (or every occupied node) of any graph, the
lattices of :mod:`faultnet.graphs.builders` among them; :func:`percolation_threshold` gives the
site-percolation thresholds of the two supported lattices.  Both are re-exported by
:mod:`faultnet.graphs.builders` and :mod:`faultnet.graphs`.
"""

from __future__ import annotations

import numbers

import networkx as nx
import numpy as np

from faultnet._validate import generator_and_seed
from faultnet.exceptions import InvalidParameterError

__all__ = ["percolation_threshold", "site_percolation"]

_THRESHOLDS = {"square": 0.592746, "triangular": 0.5}
_KEEP_VALUES = ("largest", "all")


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
