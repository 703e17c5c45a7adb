"""Graph constructors for block-spring fault networks.

Every constructor returns a :class:`networkx.Graph` whose nodes are blocks and
whose edges are the coupling springs between neighbouring blocks.  Lattice
constructors attach a ``pos`` node attribute (an ``(x, y)`` tuple of floats,
in units of the lattice spacing) and set ``G.graph["name"]`` to a readable
description such as ``"square_lattice(150, 150, periodic=True)"``.

:func:`chain` and :func:`ring` take long-range springs: with ``reach=R`` each block is
linked to its ``R`` nearest neighbours on each side, and with ``k_c`` every spring gets
the edge attribute ``k = k_c / (2 R)`` (the coupling of Xia, Gould, Klein and Rundle,
PRL 2005: ``q = 2R`` neighbours, each with ``k_c / q``).

The lattices take one of three boundaries (``boundary=``, see :data:`BOUNDARIES`):

- ``"periodic"``: both directions wrap (a torus); every block has the full coordination
  (4 on the square lattice, 6 on the triangular one);
- ``"free"`` (the default): the edge blocks have fewer springs;
- ``"fixed"``: the same springs as ``"free"``, and the springs missing at the edge tie the
  edge blocks to a rigid frame.  Every block carries the node attribute ``wall``, the number
  of its frame springs (coordination minus degree: 1 on a side, 2 at a corner of the square
  lattice, 0 inside).  The models give each frame spring their scalar ``k``: a frame spring
  adds ``k`` to its block's stiffness, and the force it takes is lost from the
  network (the "open" boundary of the Olami-Feder-Christensen automaton).

:func:`site_percolation` dilutes any such graph by occupying each node
independently with probability ``p``; :func:`percolation_threshold` gives the
site-percolation thresholds of the two supported lattices (both live in
:mod:`faultnet.graphs.percolation`).
"""

from __future__ import annotations

import math
import numbers

import networkx as nx
import numpy as np

from faultnet._validate import check_int, check_positive
from faultnet.exceptions import InvalidParameterError
from faultnet.graphs.percolation import percolation_threshold, site_percolation

__all__ = [
    "BOUNDARIES",
    "chain",
    "ring",
    "square_lattice",
    "triangular_lattice",
    "site_percolation",
    "percolation_threshold",
]

#: the boundaries a lattice builder takes (``boundary=``)
BOUNDARIES = ("periodic", "free", "fixed")
#: springs of a block inside each lattice (its coordination)
_COORDINATION = {"square_lattice": 4, "triangular_lattice": 6}


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


def _lattice_name(kind, rows, cols, boundary):
    suffix = {"periodic": ", periodic=True", "free": "", "fixed": ", boundary='fixed'"}
    return f"{kind}({rows}, {cols}{suffix[boundary]})"


def _boundary(periodic, boundary):
    """The boundary that ``periodic=`` and ``boundary=`` ask for (one of :data:`BOUNDARIES`)."""
    allowed = ", ".join(repr(b) for b in BOUNDARIES)
    if boundary is not None and (not isinstance(boundary, str) or boundary not in BOUNDARIES):
        raise InvalidParameterError(f"boundary must be one of {allowed}; got boundary={boundary!r}")
    if periodic is None:
        return boundary or "free"
    if not isinstance(periodic, bool | np.bool_):
        raise InvalidParameterError(f"periodic must be True or False; got periodic={periodic!r}")
    wanted = "periodic" if periodic else "free"
    if boundary is None or boundary == wanted or (boundary == "fixed" and not periodic):
        return boundary or wanted
    raise InvalidParameterError(
        f"periodic={bool(periodic)} contradicts boundary={boundary!r}; give boundary= alone "
        f"(one of {allowed})"
    )


def _finish_lattice(G, kind, boundary):
    """Record the boundary; on a fixed one, set every block's ``wall`` (its frame springs)."""
    G.graph["boundary"] = boundary
    if boundary == "fixed":
        q = _COORDINATION[kind]
        nx.set_node_attributes(G, {node: q - d for node, d in G.degree()}, "wall")
    return G


def square_lattice(rows, cols, periodic=None, sparse=False, *, boundary=None):
    """Square lattice of ``rows x cols`` blocks with 4-neighbour springs.

    Parameters
    ----------
    rows, cols : int
        Lattice size, each ``>= 1`` (``>= 3`` when periodic).
    periodic : bool, optional
        The older spelling of the boundary: True is ``boundary="periodic"``, False
        ``boundary="free"`` (or ``"fixed"``, if given too).
    sparse : bool, optional
        Return a :class:`faultnet.SparseGraph` (the adjacency only, built with
        numpy in well under a second for 10^6 blocks and ~50 MB) instead of a
        networkx graph (~1 GB and ~10 s at that size).  Same node numbering;
        a fixed boundary's walls are its ``wall`` array.
    boundary : {"free", "periodic", "fixed"}, optional
        ``"free"`` (the default): edge blocks have fewer springs; ``"periodic"``: wrap
        both directions (a torus), every node of degree 4; ``"fixed"``: the free
        lattice, and node attribute ``wall = 4 - degree`` (the frame springs of the
        edge blocks, 0 inside) on every node (see the module's text).

    Returns
    -------
    networkx.Graph or SparseGraph
        Node ``r * cols + c`` sits at ``pos = (float(c), float(r))``.  The free and
        fixed lattices have ``2*rows*cols - rows - cols`` edges, the periodic one
        ``2*rows*cols``.  ``G.graph["boundary"]`` records the boundary.

    Raises
    ------
    InvalidParameterError
        For a size below the minimum, an unknown ``boundary``, or ``periodic`` and
        ``boundary`` that contradict each other.

    Examples
    --------
    >>> from faultnet.graphs.builders import square_lattice
    >>> G = square_lattice(2, 3)
    >>> G.number_of_nodes(), G.number_of_edges(), G.nodes[4]["pos"]
    (6, 7, (1.0, 1.0))
    >>> square_lattice(3, 3, periodic=True).number_of_edges()
    18
    >>> F = square_lattice(3, 3, boundary="fixed")
    >>> [F.nodes[i]["wall"] for i in range(9)], F.graph["name"]
    ([2, 1, 2, 1, 0, 1, 2, 1, 2], "square_lattice(3, 3, boundary='fixed')")
    """
    rows = check_int("rows", rows)
    cols = check_int("cols", cols)
    boundary = _boundary(periodic, boundary)
    periodic = boundary == "periodic"
    if periodic and (rows < 3 or cols < 3):
        raise InvalidParameterError(
            f"periodic square_lattice needs rows >= 3 and cols >= 3, got rows={rows}, "
            f"cols={cols}: wrapping would create duplicate edges or self-loops"
        )
    name = _lattice_name("square_lattice", rows, cols, boundary)
    if sparse:
        return _square_sparse(rows, cols, boundary, name)
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
    return _finish_lattice(G, "square_lattice", boundary)


def _square_sparse(rows, cols, boundary, name):
    import scipy.sparse as sp  # here, not at import: 0.2 s off `import faultnet`

    from faultnet.model.carlson_langer import SparseGraph

    periodic = boundary == "periodic"
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
    wall = None
    if boundary == "fixed":
        wall = 4.0 - np.diff(adj.indptr).astype(np.float64)
    G = SparseGraph(adj, wall=wall, name=name)
    G.graph["boundary"] = boundary
    return G


def triangular_lattice(rows, cols, periodic=None, *, boundary=None):
    """Triangular lattice of ``rows x cols`` blocks with 6-neighbour springs.

    Rows are offset by half a spacing ("odd-r" layout): odd rows are shifted
    right by 0.5, so every bond has Euclidean length 1 and each interior node
    has exactly six neighbours.

    Parameters
    ----------
    rows, cols : int
        Lattice size, each ``>= 1``.  When periodic, ``rows`` must be even
        and ``>= 4`` (so the row offsets match across the seam and the rows
        above and below a node differ) and ``cols >= 3``.
    periodic : bool, optional
        The older spelling of the boundary: True is ``boundary="periodic"``, False
        ``boundary="free"`` (or ``"fixed"``, if given too).
    boundary : {"free", "periodic", "fixed"}, optional
        ``"free"`` (the default); ``"periodic"``: wrap both directions, every node of
        degree 6 and ``3 * rows * cols`` edges; ``"fixed"``: the free lattice and node
        attribute ``wall = 6 - degree`` on every node (see the module's text).

    Returns
    -------
    networkx.Graph
        Node ``r * cols + c`` sits at ``pos = (c + 0.5 * (r % 2), r * sqrt(3) / 2)``;
        ``G.graph["boundary"]`` records the boundary.

    Examples
    --------
    >>> from faultnet.graphs.builders import triangular_lattice
    >>> G = triangular_lattice(3, 3)
    >>> G.degree(4), G.nodes[4]["pos"][0]
    (6, 1.5)
    >>> H = triangular_lattice(4, 3, periodic=True)
    >>> H.number_of_edges(), {d for _, d in H.degree()}
    (36, {6})
    >>> F = triangular_lattice(3, 3, boundary="fixed")
    >>> {d + F.nodes[v]["wall"] for v, d in F.degree()}
    {6}
    """
    rows = check_int("rows", rows)
    cols = check_int("cols", cols)
    boundary = _boundary(periodic, boundary)
    periodic = boundary == "periodic"
    if periodic and (rows < 4 or rows % 2 or cols < 3):
        raise InvalidParameterError(
            f"periodic triangular_lattice needs an even rows >= 4 and cols >= 3, got "
            f"rows={rows}, cols={cols}: an odd row count breaks the row offsets across "
            f"the seam, and smaller sizes would create duplicate edges"
        )
    height = math.sqrt(3.0) / 2.0
    G = nx.Graph(name=_lattice_name("triangular_lattice", rows, cols, boundary))
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
    return _finish_lattice(G, "triangular_lattice", boundary)
