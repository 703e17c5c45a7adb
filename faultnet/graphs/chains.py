"""Chains and rings of blocks, with long-range springs (Xia, Gould, Klein and Rundle, PRL 2005).

With ``reach=R`` each block is linked to its ``R`` nearest neighbours on each side, and with
``k_c`` every spring gets the edge attribute ``k = k_c / (2 R)`` (``q = 2R`` neighbours, each
with ``k_c / q``).  Both builders are also in :mod:`faultnet.graphs.builders`.
"""

from __future__ import annotations

import math
import numbers

import networkx as nx
import numpy as np

from faultnet._validate import check_int, check_positive
from faultnet.exceptions import InvalidParameterError

__all__ = ["chain", "ring"]


def _format_number(value):
    """``value`` as it reads in a graph's name: ``100`` for 100.0, else the float's repr."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def _long_range(kind, n, reach, k_c):
    """``(reach, k_c, name)``: checked long-range arguments of ``chain`` / ``ring`` of ``n``
    blocks, and the graph's name (today's ``"ring(n)"`` when both are the defaults)."""
    if kind == "ring":
        limit = (n - 1) // 2
        rule = (
            f"1 <= reach <= (n - 1) // 2 = {limit} for ring({n}), so that no two blocks "
            "get two springs"
        )
    else:
        limit = max(n - 1, 1)
        rule = f"1 <= reach <= max(n - 1, 1) = {limit} for chain({n})"
    bad_type = isinstance(reach, bool | np.bool_) or not isinstance(reach, numbers.Integral)
    if bad_type or not 1 <= reach <= limit:
        raise InvalidParameterError(f"reach must be an integer with {rule}; got reach={reach!r}")
    reach = int(reach)
    if k_c is not None:
        try:
            k_c = check_positive("k_c", k_c)
        except InvalidParameterError:
            raise InvalidParameterError(
                f"k_c must be None (no edge attribute k) or a finite real number > 0; "
                f"got k_c={k_c!r}"
            ) from None
    extra = "" if reach == 1 else f", reach={reach}"
    if k_c is not None:
        extra += f", k_c={_format_number(k_c)}"
    return reach, k_c, f"{kind}({n}{extra})"


def _add_long_range_edges(G, n, reach, k_c, wrap):
    """Link block ``i`` to ``i + 1 .. i + reach`` (mod ``n`` if ``wrap``), with ``k = k_c / (2
    reach)`` on every edge when ``k_c`` is given."""
    attrs = {} if k_c is None else {"k": k_c / (2 * reach)}
    for i in range(n):
        for d in range(1, reach + 1):
            if wrap or i + d < n:
                G.add_edge(i, (i + d) % n, **attrs)


def chain(n, *, reach=1, k_c=None):
    """Open chain of ``n`` blocks, each linked to its ``reach`` nearest neighbours on each side.

    With ``reach=1`` (the default) it is a path; with ``reach=R`` and ``k_c`` it is the
    long-range chain of Xia, Gould, Klein and Rundle (PRL 2005): every block coupled to
    its ``q = 2R`` nearest neighbours by springs of ``k_c / q``.

    Parameters
    ----------
    n : int
        Number of blocks, ``n >= 1``.
    reach : int, optional, keyword-only
        ``R``: block ``i`` is linked to ``i - R .. i + R``, truncated at the ends of the
        chain; ``1 <= R <= n - 1`` (``R = 1`` for a single block).
    k_c : float, optional, keyword-only
        Total coupling of an interior block (finite, > 0).  Every edge gets the edge
        attribute ``k = k_c / (2 R)``: the same on every spring, also at the ends of the
        chain, where a block has fewer than ``2 R`` springs and so less than ``k_c`` in
        all.  None (the default) sets no edge attribute, so the model's ``k`` applies.

    Returns
    -------
    networkx.Graph
        Nodes ``0 .. n-1``, edges ``(i, i + d)`` for ``1 <= d <= R`` and
        ``pos = (float(i), 0.0)``.  ``G.graph["name"]`` is ``"chain(n)"``, with
        ``reach`` and ``k_c`` appended when not the defaults.

    Raises
    ------
    InvalidParameterError
        For ``n < 1``, a ``reach`` that is not an integer in ``[1, n - 1]``, or a
        ``k_c`` that is not None or a finite number > 0.

    Examples
    --------
    >>> from faultnet.graphs.builders import chain
    >>> G = chain(4)
    >>> G.number_of_edges(), G.nodes[3]["pos"], G.graph["name"]
    (3, (3.0, 0.0), 'chain(4)')
    >>> L = chain(6, reach=2, k_c=8)
    >>> [L.degree(i) for i in range(6)], L.edges[0, 2]["k"], L.graph["name"]
    ([2, 3, 4, 4, 3, 2], 2.0, 'chain(6, reach=2, k_c=8)')
    """
    n = check_int("n", n)
    reach, k_c, name = _long_range("chain", n, reach, k_c)
    G = nx.Graph(name=name)
    G.add_nodes_from((i, {"pos": (float(i), 0.0)}) for i in range(n))
    _add_long_range_edges(G, n, reach, k_c, wrap=False)
    return G


def ring(n, *, reach=1, k_c=None):
    """Periodic ring of ``n`` blocks, each linked to its ``reach`` nearest neighbours on each
    side.

    With ``reach=R`` and ``k_c`` it is the long-range ring of Xia, Gould, Klein and Rundle
    (PRL 2005): every block coupled to its ``q = 2R`` nearest neighbours by springs of
    ``k_c / q``, so ``CarlsonLanger(ring(2000, reach=10, k_c=100))`` is their setting.

    Parameters
    ----------
    n : int
        Number of blocks, ``n >= 3``.  A ring of two blocks would couple them
        twice (a doubled spring), so use ``chain(2)`` instead.
    reach : int, optional, keyword-only
        ``R``: block ``i`` is linked to ``i - R .. i + R`` (mod ``n``), so every block
        has degree ``2 R``; ``1 <= R <= (n - 1) // 2``, so that no two blocks get two
        springs.
    k_c : float, optional, keyword-only
        Total coupling of a block (finite, > 0).  Every edge gets the edge attribute
        ``k = k_c / (2 R)``, so each block's springs add up to ``k_c``.  None (the
        default) sets no edge attribute, so the model's ``k`` applies.

    Returns
    -------
    networkx.Graph
        Nodes ``0 .. n-1`` and ``R n`` edges ``(i, (i + d) % n)`` for ``1 <= d <= R``.
        Positions lie on a circle of radius ``n / (2 pi)`` so neighbours are about 1
        apart.  ``G.graph["name"]`` is ``"ring(n)"``, with ``reach`` and ``k_c``
        appended when not the defaults.

    Raises
    ------
    InvalidParameterError
        For ``n < 3``, a ``reach`` that is not an integer in ``[1, (n - 1) // 2]``, or a
        ``k_c`` that is not None or a finite number > 0.

    Examples
    --------
    >>> from faultnet.graphs.builders import ring
    >>> G = ring(6)
    >>> G.number_of_edges(), sorted(G[0]), G.graph["name"]
    (6, [1, 5], 'ring(6)')
    >>> X = ring(2000, reach=10, k_c=100)
    >>> X.degree(0), X.edges[0, 1990]["k"], X.graph["name"]
    (20, 5.0, 'ring(2000, reach=10, k_c=100)')
    """
    n = check_int("n", n)
    if n < 3:
        raise InvalidParameterError(
            f"ring needs n >= 3, got n={n}: ring({n}) would double the spring between "
            f"its blocks (or make a self-loop); use chain({n}) instead"
        )
    reach, k_c, name = _long_range("ring", n, reach, k_c)
    radius = n / (2.0 * math.pi)
    G = nx.Graph(name=name)
    for i in range(n):
        theta = 2.0 * math.pi * i / n
        G.add_node(i, pos=(radius * math.cos(theta), radius * math.sin(theta)))
    _add_long_range_edges(G, n, reach, k_c, wrap=True)
    return G
