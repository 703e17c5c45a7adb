"""Fault labels: the node attribute ``fault`` that names the segment a block belongs to.

A fault label is a str, an int or a tuple of those (the types a catalog file
gives back as they were).  A graph labels every block or none; a model numbers
its faults in the order they first appear among its nodes.
"""

from __future__ import annotations

import numbers

import numpy as np

from faultnet.exceptions import InvalidParameterError

__all__ = ["FAULT_LABEL_RULE", "fault_label_ok", "fault_numbers"]

FAULT_LABEL_RULE = "a str, an int or a tuple of those (nested allowed)"


def fault_label_ok(value) -> bool:
    """True if ``value`` is a fault label: :data:`FAULT_LABEL_RULE`, the labels a catalog
    file gives back with their type (NumPy integers count as ints, bools do not).

    >>> [fault_label_ok(v) for v in ("A", ("A", (2, "b")), 1.5, (), True)]
    [True, True, False, False, False]
    """
    if isinstance(value, tuple):
        return len(value) > 0 and all(map(fault_label_ok, value))
    if isinstance(value, bool | np.bool_):
        return False
    return isinstance(value, str | numbers.Integral)


def fault_numbers(graph):
    """``(faults, number)`` of a networkx graph: its distinct fault labels in order of first
    appearance, and each block's fault number (int64, node order); ``(None, None)`` for a
    graph without the ``fault`` attribute.

    >>> import networkx as nx
    >>> g = nx.path_graph(3)
    >>> nx.set_node_attributes(g, {0: "A", 1: "B", 2: "A"}, "fault")
    >>> fault_numbers(g)
    (['A', 'B'], array([0, 1, 0]))
    """
    labels = [data.get("fault") for _, data in graph.nodes(data=True)]
    given = sum(label is not None for label in labels)
    if given == 0:
        return None, None
    if given < len(labels):
        missing = next(
            node for node, label in zip(graph.nodes, labels, strict=True) if label is None
        )
        raise InvalidParameterError(
            f"the node attribute 'fault' is set on {given} of {len(labels)} blocks (not on "
            f"{missing!r}): set it on every block or on none"
        )
    faults, number = {}, np.empty(len(labels), dtype=np.int64)
    for i, (node, label) in enumerate(zip(graph.nodes, labels, strict=True)):
        if not fault_label_ok(label):
            raise InvalidParameterError(
                f"the fault of node {node!r} must be {FAULT_LABEL_RULE}; got {label!r} "
                f"({type(label).__name__})"
            )
        number[i] = faults.setdefault(label, len(faults))
    return list(faults), number
