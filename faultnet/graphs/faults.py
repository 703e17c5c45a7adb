"""Networks of faults: blocks grouped into named fault segments joined by coupling springs.

Every block carries the node attribute ``fault``, the name of its segment (a str,
an int or a tuple of those), and ``pos = (x, y)``; node labels are tuples
``(fault, index)``.  Springs inside a fault carry no ``k`` (they take the model's
``k``); a coupling spring between two faults carries its own ``k``, which the
model reads per edge.  :func:`compose` joins any graphs this way; the other
builders lay out common geometries with it: :func:`parallel_faults`,
:func:`step_over` and :func:`branch`.  Along a fault, neighbouring blocks are
one unit apart.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import networkx as nx

from faultnet._validate import check_finite, check_int, check_positive
from faultnet.exceptions import InvalidParameterError
from faultnet.model.faults import FAULT_LABEL_RULE, fault_label_ok

__all__ = ["branch", "compose", "parallel_faults", "step_over"]


def _check_names(names, count):
    """``names`` as a tuple of ``count`` distinct fault names."""
    ok = isinstance(names, list | tuple) and len(names) == count
    if not (ok and all(map(fault_label_ok, names)) and len(set(names)) == count):
        raise InvalidParameterError(
            f"names must be {count} distinct fault names ({FAULT_LABEL_RULE}); got {names!r}"
        )
    return tuple(names)


def _check_coupling(k_coupling):
    """``k_coupling`` as a float >= 0 (0: the faults are left uncoupled)."""
    value = check_finite("k_coupling", k_coupling)
    if value < 0.0:
        raise InvalidParameterError(
            f"k_coupling must be finite and >= 0 (0 leaves the faults uncoupled); "
            f"got {k_coupling!r}"
        )
    return value


def _trace(n, start, step, closed=False):
    """A chain of ``n`` blocks at ``start + i * step`` (a ring when ``closed``)."""
    G = nx.Graph()
    for i in range(n):
        G.add_node(i, pos=(float(start[0] + i * step[0]), float(start[1] + i * step[1])))
    G.add_edges_from((i, i + 1) for i in range(n - 1))
    if closed:
        G.add_edge(n - 1, 0)
    return G


def _check_coupling_item(i, item, graphs):
    """``(a, node_a, b, node_b, k)`` of ``couplings[i]``, checked against ``graphs``."""
    where = f"couplings[{i}]"
    if not isinstance(item, list | tuple) or len(item) != 5:
        raise InvalidParameterError(
            f"{where} must be a tuple (fault_a, node_a, fault_b, node_b, k); got {item!r}"
        )
    a, node_a, b, node_b, k = item
    for fault, node in ((a, node_a), (b, node_b)):
        if not fault_label_ok(fault) or fault not in graphs:
            raise InvalidParameterError(
                f"{where} names the fault {fault!r}, which is not a key of graphs ({list(graphs)})"
            )
        if node not in graphs[fault]:
            raise InvalidParameterError(
                f"{where} names the block {node!r}, which is not a node of graphs[{fault!r}]"
            )
    if a == b:
        raise InvalidParameterError(
            f"{where} joins two blocks of the fault {a!r}: couplings join two different "
            "faults (add a spring inside a fault to its graph)"
        )
    if k is not None:
        k = check_positive(f"the k of {where}", k)
    return (a, node_a), (b, node_b), k


def compose(graphs, couplings=()):
    """Join the graphs of several faults into one network with coupling springs.

    Parameters
    ----------
    graphs : dict
        ``{fault name: networkx.Graph}``; a fault name is a str, an int or a tuple of
        those.  Node and edge attributes are copied (``pos`` included, so pass the
        graphs already placed where they belong).
    couplings : sequence of tuple, optional
        ``(fault_a, node_a, fault_b, node_b, k)``: a spring of constant ``k`` between
        block ``node_a`` of fault ``fault_a`` (its label in ``graphs[fault_a]``) and
        block ``node_b`` of another fault.  ``k`` is finite and > 0, or None for a
        spring that takes the model's ``k``.

    Returns
    -------
    networkx.Graph
        Nodes ``(fault, label)`` with the attribute ``fault`` set to the fault's name,
        in the order of ``graphs``; the faults' own springs, then the couplings (with
        the attribute ``k`` unless it is None).

    Raises
    ------
    InvalidParameterError
        If a fault name or graph is not valid, or a coupling names an unknown fault
        or block, joins a fault to itself, repeats a spring or has a ``k`` <= 0.

    Examples
    --------
    >>> import faultnet
    >>> from faultnet.graphs import chain, compose
    >>> G = compose({"A": chain(5), "B": chain(3)}, [("A", 4, "B", 0, 2.5)])
    >>> list(G)[-3:], G.nodes["B", 0]["fault"], G.edges[("A", 4), ("B", 0)]
    ([('B', 0), ('B', 1), ('B', 2)], 'B', {'k': 2.5})
    >>> model = faultnet.CarlsonLanger(G, k=16, sigma=0.01, alpha=1.0)
    >>> len(faultnet.simulate(model, 200, rng=1, progress=False).events)
    200
    """
    if not isinstance(graphs, Mapping) or not graphs:
        raise InvalidParameterError(
            f"graphs must be a non-empty dict {{fault name: networkx.Graph}}; got {graphs!r}"
        )
    G = nx.Graph()
    for name, g in graphs.items():
        if not fault_label_ok(name):
            raise InvalidParameterError(
                f"graphs must have fault names ({FAULT_LABEL_RULE}) as keys; got {name!r}"
            )
        if not isinstance(g, nx.Graph) or g.is_directed() or g.is_multigraph():
            raise InvalidParameterError(
                f"graphs[{name!r}] must be an undirected simple networkx.Graph; "
                f"got {type(g).__name__}"
            )
        G.add_nodes_from(((name, v), {**data, "fault": name}) for v, data in g.nodes(data=True))
        G.add_edges_from(((name, u), (name, v), dict(data)) for u, v, data in g.edges(data=True))
    if isinstance(couplings, str | bytes) or not hasattr(couplings, "__iter__"):
        raise InvalidParameterError(
            f"couplings must be a list of (fault_a, node_a, fault_b, node_b, k); got {couplings!r}"
        )
    for i, item in enumerate(couplings):
        u, v, k = _check_coupling_item(i, item, graphs)
        if G.has_edge(u, v):
            raise InvalidParameterError(f"couplings[{i}] repeats the spring between {u} and {v}")
        G.add_edge(u, v, **({} if k is None else {"k": k}))
    G.graph["name"] = f"compose({', '.join(map(repr, graphs))})"
    return G


def parallel_faults(n_faults, n_blocks, *, k_coupling, spacing=1.0, periodic=False, names=None):
    """Parallel faults side by side, each block coupled to its neighbours across the faults.

    Parameters
    ----------
    n_faults : int
        Number of faults, ``>= 1``.
    n_blocks : int
        Blocks per fault, ``>= 1`` (``>= 3`` when ``periodic``).
    k_coupling : float
        Spring constant, ``>= 0``, between block ``i`` of a fault and block ``i`` of
        the next one.  0 adds no coupling springs (independent faults: the model takes
        no spring of zero stiffness).
    spacing : float, optional
        Distance between neighbouring fault traces, ``> 0``.
    periodic : bool, optional
        Close every fault into a ring.  Positions stay on straight traces and
        ``G.graph["period"] = (n_blocks, None)`` tells the distance measures (and the
        plots) that the along-strike direction wraps.
    names : sequence, optional
        The faults' names, ``n_faults`` distinct ones (default ``0 .. n_faults - 1``).

    Returns
    -------
    networkx.Graph
        Nodes ``(name, i)`` at ``pos = (i, a * spacing)`` for the ``a``-th fault.

    Examples
    --------
    >>> import faultnet
    >>> from faultnet.graphs import parallel_faults
    >>> G = parallel_faults(2, 10, k_coupling=4.0)
    >>> G.number_of_nodes(), G.number_of_edges(), G.nodes[1, 3]
    (20, 28, {'pos': (3.0, 1.0), 'fault': 1})
    >>> G.edges[(0, 3), (1, 3)], G.graph["name"]
    ({'k': 4.0}, 'parallel_faults(2, 10, k_coupling=4.0, spacing=1.0)')
    >>> model = faultnet.CarlsonLanger(G, k=16, sigma=0.01, alpha=1.0)
    >>> len(faultnet.simulate(model, 200, rng=1, progress=False).events)
    200
    """
    n_faults = check_int("n_faults", n_faults)
    periodic = bool(periodic)
    n_blocks = check_int("n_blocks", n_blocks)
    if periodic and n_blocks < 3:
        raise InvalidParameterError(
            f"periodic parallel_faults needs n_blocks >= 3, got n_blocks={n_blocks}: a "
            "ring of fewer blocks would double a spring (or make a self-loop)"
        )
    k_coupling = _check_coupling(k_coupling)
    spacing = check_positive("spacing", spacing)
    names = tuple(range(n_faults)) if names is None else _check_names(names, n_faults)
    graphs = {
        name: _trace(n_blocks, (0.0, a * spacing), (1.0, 0.0), closed=periodic)
        for a, name in enumerate(names)
    }
    couplings = [
        (names[a], i, names[a + 1], i, k_coupling)
        for a in range(n_faults - 1)
        for i in range(n_blocks)
        if k_coupling > 0.0
    ]
    G = compose(graphs, couplings)
    tail = ", periodic=True" if periodic else ""
    G.graph["name"] = (
        f"parallel_faults({n_faults}, {n_blocks}, k_coupling={k_coupling!r}, "
        f"spacing={spacing!r}{tail})"
    )
    if periodic:
        G.graph["period"] = (float(n_blocks), None)
    return G


def step_over(n_blocks, *, overlap, gap, k_coupling, names=("A", "B")):
    """Two faults offset along strike, the end of one facing the start of the other.

    Parameters
    ----------
    n_blocks : int
        Blocks per fault, ``>= 1``.
    overlap : int
        How many blocks the faults overlap, ``0 <= overlap <= n_blocks``: the last
        ``overlap`` blocks of the first fault face the first ``overlap`` blocks of the
        second, pair by pair.  0 is an end-to-end step: the second fault starts one
        block beyond the end of the first, and one spring joins the two ends.
    gap : float
        Distance between the two fault traces, ``> 0`` (``>= 0`` when ``overlap=0``).
    k_coupling : float
        Constant of every coupling spring, ``>= 0`` (0: no coupling springs).  It does
        not change with ``gap``, which only places the blocks; pass a gap-dependent
        value (for instance ``k0 / gap``) for a coupling that weakens across wider steps.
    names : pair, optional
        The two faults' names.

    Returns
    -------
    networkx.Graph
        The first fault at ``pos = (i, 0)``, the second at
        ``pos = (n_blocks - overlap + i, gap)``.

    Examples
    --------
    >>> import faultnet
    >>> from faultnet.graphs import step_over
    >>> G = step_over(10, overlap=3, gap=0.5, k_coupling=2.0)
    >>> [(u, v) for u, v, k in G.edges(data="k") if k]
    [(('A', 7), ('B', 0)), (('A', 8), ('B', 1)), (('A', 9), ('B', 2))]
    >>> G.nodes["B", 0]["pos"]
    (7.0, 0.5)
    >>> model = faultnet.CarlsonLanger(G, k=16, sigma=0.01, alpha=1.0)
    >>> len(faultnet.simulate(model, 200, rng=1, progress=False).events)
    200
    """
    n_blocks = check_int("n_blocks", n_blocks)
    overlap = check_int("overlap", overlap, minimum=0)
    if overlap > n_blocks:
        raise InvalidParameterError(
            f"overlap must be an integer in [0, n_blocks={n_blocks}]; got {overlap!r}"
        )
    gap = check_finite("gap", gap)
    if gap < 0.0 or (gap == 0.0 and overlap > 0):
        raise InvalidParameterError(
            f"gap must be > 0 (>= 0 when overlap=0: facing blocks would sit on each "
            f"other); got gap={gap!r} with overlap={overlap}"
        )
    k_coupling = _check_coupling(k_coupling)
    a, b = _check_names(names, 2)
    graphs = {
        a: _trace(n_blocks, (0.0, 0.0), (1.0, 0.0)),
        b: _trace(n_blocks, (float(n_blocks - overlap), gap), (1.0, 0.0)),
    }
    pairs = [(n_blocks - overlap + j, j) for j in range(overlap)] or [(n_blocks - 1, 0)]
    couplings = [(a, i, b, j, k_coupling) for i, j in pairs if k_coupling > 0.0]
    G = compose(graphs, couplings)
    G.graph["name"] = (
        f"step_over({n_blocks}, overlap={overlap}, gap={gap!r}, k_coupling={k_coupling!r})"
    )
    return G


def branch(n_main, n_branch, *, at, angle_deg=30, k_coupling=None, names=("main", "branch")):
    """A main fault and a branch that leaves it at one block, at an angle.

    Parameters
    ----------
    n_main, n_branch : int
        Blocks of the main fault and of the branch, each ``>= 1``.
    at : int
        The main fault's block the branch leaves from, ``0 <= at < n_main``.
    angle_deg : float, optional
        Angle between the branch and the main fault in degrees, ``0 < |angle_deg| <
        180`` (positive: the branch goes up, towards ``+y``).
    k_coupling : float or None, optional
        Constant of the spring between the branch's first block and block ``at``:
        None (a spring without ``k`` that takes the model's ``k``, as inside a fault),
        a float > 0, or 0 (no spring: the branch is a separate fault).
    names : pair, optional
        The names of the main fault and of the branch.

    Returns
    -------
    networkx.Graph
        The main fault at ``pos = (i, 0)``; the branch's block ``j`` at
        ``(at, 0) + (j + 1) (cos angle, sin angle)``.

    Examples
    --------
    >>> import faultnet
    >>> from faultnet.graphs import branch
    >>> G = branch(12, 6, at=4, angle_deg=90, k_coupling=8.0)
    >>> G.nodes["branch", 1]["pos"], sorted(G["branch", 0])
    ((4.0, 2.0), [('branch', 1), ('main', 4)])
    >>> model = faultnet.CarlsonLanger(G, k=16, sigma=0.01, alpha=1.0)
    >>> len(faultnet.simulate(model, 200, rng=1, progress=False).events)
    200
    """
    n_main = check_int("n_main", n_main)
    n_branch = check_int("n_branch", n_branch)
    at = check_int("at", at, minimum=0)
    if at >= n_main:
        raise InvalidParameterError(
            f"at must be an integer in [0, n_main - 1 = {n_main - 1}]; got {at!r}"
        )
    angle = check_finite("angle_deg", angle_deg)
    if not 0.0 < abs(angle) < 180.0:
        raise InvalidParameterError(
            f"angle_deg must satisfy 0 < |angle_deg| < 180 (the branch would lie on the "
            f"main fault); got {angle_deg!r}"
        )
    k = None if k_coupling is None else _check_coupling(k_coupling)
    main, side = _check_names(names, 2)
    theta = math.radians(angle)
    step = (math.cos(theta), math.sin(theta))
    graphs = {
        main: _trace(n_main, (0.0, 0.0), (1.0, 0.0)),
        side: _trace(n_branch, (at + step[0], step[1]), step),
    }
    couplings = [] if k == 0.0 else [(main, at, side, 0, k)]
    G = compose(graphs, couplings)
    G.graph["name"] = (
        f"branch({n_main}, {n_branch}, at={at}, angle_deg={angle!r}, k_coupling={k!r})"
    )
    return G
