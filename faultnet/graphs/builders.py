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

import networkx as nx
import numpy as np

from faultnet._validate import check_int
from faultnet.exceptions import InvalidParameterError
from faultnet.graphs.chains import chain, ring
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
