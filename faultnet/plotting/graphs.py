"""Matplotlib views of graphs: springs and blocks, and networks of faults coloured by fault.

Every function draws on ``ax`` (a new figure when None) and returns the Axes.
Matplotlib is imported inside the functions, so ``import faultnet`` never pulls it in.
"""

from __future__ import annotations

import numpy as np

from faultnet.exceptions import InvalidParameterError
from faultnet.plotting.figures import _axes

__all__ = ["plot_faults", "plot_graph"]


def _positions(graph, nodes):
    pos = [graph.nodes[v].get("pos") for v in nodes]
    if any(p is None for p in pos):
        import networkx as nx

        layout = nx.spring_layout(graph, seed=0)
        pos = [layout[v] for v in nodes]
    return np.asarray(pos, dtype=np.float64).reshape(len(nodes), 2)


def _nx_graph(graph):
    """The networkx graph of ``graph`` (a graph or a CarlsonLanger on one)."""
    import networkx as nx

    from faultnet.model.carlson_langer import CarlsonLanger, SparseGraph

    if isinstance(graph, CarlsonLanger):
        graph = graph.graph
    if not isinstance(graph, nx.Graph):
        what = (
            "a SparseGraph, which has no node positions"
            if isinstance(graph, SparseGraph)
            else type(graph).__name__
        )
        raise TypeError(f"graph must be a networkx.Graph or a CarlsonLanger of one; got {what}")
    return graph


def _springs(graph, max_edge_length):
    """``(index, xy, edges, segments)``: node positions and the springs drawn.

    Springs longer than ``max_edge_length`` are hidden, and so are those that wrap
    across a periodic direction of ``graph.graph["period"]`` (longer than half the
    period along it); without a period, a ``"periodic=True"`` name hides springs
    longer than 1.5 by default.
    """
    index = {v: i for i, v in enumerate(graph.nodes)}
    xy = _positions(graph, list(index))
    edges = np.array([(index[a], index[b]) for a, b in graph.edges], dtype=np.int64).reshape(-1, 2)
    segments = xy[edges]  # (E, 2, 2)
    period = graph.graph.get("period")
    if max_edge_length is None and period is None:
        if "periodic=True" in str(graph.graph.get("name", "")):
            max_edge_length = 1.5
    keep = np.ones(len(edges), dtype=bool)
    if max_edge_length is not None:
        keep &= np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1) <= max_edge_length
    for axis, length in enumerate(period or ()):
        if length:
            keep &= np.abs(segments[:, 1, axis] - segments[:, 0, axis]) <= 0.5 * length
    return index, xy, edges[keep], segments[keep]


def _frame(ax, xy):
    ax.update_datalim(xy)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_axis_off()
    return ax


def plot_graph(graph, ax=None, color_by=None, linewidth=0.5, max_edge_length=None, cmap=None):
    """Draw a graph's springs as line segments (fast for 150 x 150 lattices).

    Parameters
    ----------
    graph : networkx.Graph or CarlsonLanger
        Node attribute ``pos`` gives positions (lattices from
        :mod:`faultnet.graphs.builders` have it); otherwise a spring layout is used.
    ax : matplotlib.axes.Axes, optional
    color_by : None, "component" or array_like, optional
        None: one colour.  ``"component"``: each connected cluster its own
        colour (isolated blocks as dots), as in percolation pictures.  An
        array with one value per node (node order): nodes drawn as coloured
        dots with a colour bar.
    linewidth : float, optional
    max_edge_length : float, optional
        Hide longer bonds.  Default: 1.5 lattice spacings for periodic
        lattices (``"periodic=True"`` in the graph name, so wrap-around bonds
        do not cross the picture), otherwise show all.  Bonds that wrap across
        a periodic direction of ``graph.graph["period"]`` are always hidden.
    cmap : str, optional
        Colour map for ``color_by`` (default ``tab10`` / ``viridis``).

    Returns
    -------
    matplotlib.axes.Axes
    """
    import networkx as nx
    from matplotlib import colormaps
    from matplotlib.collections import LineCollection

    graph = _nx_graph(graph)
    ax = _axes(ax)
    index, xy, edges, segments = _springs(graph, max_edge_length)
    colors = "0.2"
    if isinstance(color_by, str):
        if color_by != "component":
            raise InvalidParameterError(
                f"color_by must be None, 'component' or an array; got {color_by!r}"
            )
        label = np.empty(len(index), dtype=np.int64)
        comps = sorted(nx.connected_components(graph), key=len, reverse=True)
        for c, comp in enumerate(comps):
            label[[index[v] for v in comp]] = c
        palette = colormaps[cmap or "tab10"]
        node_colors = np.asarray(palette(label % palette.N))
        colors = node_colors[edges[:, 0]] if len(edges) else "0.2"
        lonely = np.array([graph.degree(v) == 0 for v in index], dtype=bool)
        if lonely.any():
            ax.scatter(xy[lonely, 0], xy[lonely, 1], s=2, c=node_colors[lonely], linewidths=0)
    ax.add_collection(LineCollection(segments, colors=colors, linewidths=linewidth))
    if color_by is not None and not isinstance(color_by, str):
        values = np.asarray(color_by, dtype=np.float64)
        if values.shape != (len(index),):
            raise InvalidParameterError(
                f"color_by needs one value per node ({len(index)}); got {values.shape}"
            )
        dots = ax.scatter(xy[:, 0], xy[:, 1], c=values, s=8, cmap=cmap or "viridis", zorder=3)
        ax.figure.colorbar(dots, ax=ax)
    return _frame(ax, xy)


def _fault_codes(graph, index):
    """``(names, code)``: the faults in order of first appearance, each block's position there."""
    faults = [graph.nodes[v].get("fault") for v in index]
    missing = [v for v, f in zip(index, faults, strict=True) if f is None]
    if missing:
        raise InvalidParameterError(
            f"graph must give every block a 'fault' attribute (the fault builders of "
            f"faultnet.graphs set it); block {missing[0]!r} has none"
        )
    names = list(dict.fromkeys(faults))
    order = {name: c for c, name in enumerate(names)}
    return names, np.array([order[f] for f in faults], dtype=np.int64)


def plot_faults(graph, ax=None, *, linewidth=1.0, node_size=12.0, cmap="tab10", legend=True):
    """Draw a network of faults: blocks coloured by their ``fault``, coupling springs dashed.

    Parameters
    ----------
    graph : networkx.Graph or CarlsonLanger
        Every block has the node attribute ``fault`` (the fault builders of
        :mod:`faultnet.graphs` set it); ``pos`` gives positions, otherwise a spring
        layout is used.
    ax : matplotlib.axes.Axes, optional
    linewidth : float, optional
    node_size : float, optional
        Marker area of the blocks in points squared (0: springs only).
    cmap : str, optional
        Colour map: one colour per fault, in the order the faults first appear.
    legend : bool, optional
        A legend of the faults and the coupling springs.

    Returns
    -------
    matplotlib.axes.Axes
        The springs inside the faults in their colours (one ``LineCollection``), the
        coupling springs between two faults dashed in dark grey (a second one, when
        there are any; wrap-around springs hidden as in :func:`plot_graph`), the blocks
        as dots.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from faultnet import graphs, plotting
    >>> ax = plotting.plot_faults(graphs.step_over(12, overlap=4, gap=1.0, k_coupling=2.0))
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['A', 'B', 'coupling']
    """
    from matplotlib import colormaps
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D

    graph = _nx_graph(graph)
    ax = _axes(ax)
    index, xy, edges, segments = _springs(graph, None)
    names, code = _fault_codes(graph, index)
    palette = colormaps[cmap]
    colors = np.asarray(palette(np.arange(len(names)) % palette.N)).reshape(-1, 4)
    inside = code[edges[:, 0]] == code[edges[:, 1]]
    ax.add_collection(
        LineCollection(
            segments[inside], colors=colors[code[edges[inside, 0]]], linewidths=linewidth
        )
    )
    handles = [
        Line2D([], [], color=colors[c], marker="o", label=str(name)) for c, name in enumerate(names)
    ]
    if not inside.all():
        style = {"colors": "0.25", "linestyles": "--", "linewidths": linewidth}
        ax.add_collection(LineCollection(segments[~inside], **style))
        handles.append(Line2D([], [], color="0.25", linestyle="--", label="coupling"))
    if node_size:
        ax.scatter(xy[:, 0], xy[:, 1], s=node_size, c=colors[code], linewidths=0, zorder=3)
    _frame(ax, xy).set_aspect("equal", adjustable="datalim")  # room for the legend
    if legend:
        ax.legend(handles=handles, title="fault", fontsize="small")
    return ax
