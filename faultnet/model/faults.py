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

FAULT_LABEL_RULE = "a str, an int or a tuple of those"


def fault_label_ok(value) -> bool:
    """True if ``value`` is a fault label: :data:`FAULT_LABEL_RULE`.

    >>> fault_label_ok("A"), fault_label_ok(("A", 2)), fault_label_ok(1.5), fault_label_ok(())
    (True, True, False, False)
    """

    def atom(v):
        return isinstance(v, str) or (isinstance(v, numbers.Integral) and not isinstance(v, bool))

    return atom(value) or (isinstance(value, tuple) and len(value) > 0 and all(map(atom, value)))


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
