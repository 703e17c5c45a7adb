"""The identity of a model: one hash of its graph and parameters.

A long run records :func:`graph_hash` of its model; a resume, an extension and
``simulate(model, n, x0=catalog)`` compare it before they continue a run.
"""

from __future__ import annotations

import hashlib
import json

import numpy as np

__all__ = ["graph_hash"]


def _label_key(node):
    return f"{type(node).__name__}:{node!r}"


def _update(h, arr, dtype):
    a = np.ascontiguousarray(np.asarray(arr, dtype=dtype))
    h.update(str(a.size).encode() + b"\0")
    h.update(a.tobytes())


def graph_hash(model) -> str:
    """SHA-256 (hex) of a model's graph and parameters, in node order.

    It covers the node labels, the edges with their spring constants, the
    per-block sigma and alpha, the frame springs (``k wall``, only where some block has one,
    so that the hashes of graphs without walls stay what they were), the plate's velocity
    during events ``nu`` and the springs' viscous couplings ``eta_ij`` (each only where it is
    not 0, for the same reason) and, on a network of faults, the blocks' faults, so two models
    hash equal exactly when every run on them is the same.  An
    :class:`~faultnet.model.ofc.OFC` automaton hashes its springs, frame springs, update rule
    and faults under a prefix of its own.

    >>> import faultnet
    >>> m = faultnet.CarlsonLanger(faultnet.graphs.ring(5))
    >>> graph_hash(m) == graph_hash(faultnet.CarlsonLanger(faultnet.graphs.ring(5)))
    True
    >>> graph_hash(m) == graph_hash(m.with_params(alpha=2.0))
    False
    >>> graph_hash(m) == graph_hash(m.with_params(nu=0.0, eta=0.0))
    True
    >>> graph_hash(m) == graph_hash(m.with_params(nu=0.01))
    False
    """
    from faultnet.model.carlson_langer import CarlsonLanger
    from faultnet.model.ofc import OFC

    if not isinstance(model, CarlsonLanger | OFC):
        raise TypeError(
            "graph_hash needs a CarlsonLanger or an OFC (build one from the graph); "
            f"got {type(model).__name__}"
        )
    h = hashlib.sha256()
    ofc = isinstance(model, OFC)
    h.update(
        b"faultnet-ofc-v1\0" + model.update.encode() + b"\0" if ofc else b"faultnet-graph-v1\0"
    )
    h.update(json.dumps([_label_key(n) for n in model.nodes]).encode())
    adj = model.adjacency
    arrays = [(adj.indptr, "<i8"), (adj.indices, "<i8"), (adj.data, "<f8")]
    if not ofc:
        arrays += [(model.sigma_values, "<f8"), (model.alpha_values, "<f8")]
    if np.any(model.wall_values):
        arrays.append((model.frame, "<f8"))
    for arr, dtype in arrays:
        _update(h, arr, dtype)
    if not ofc and model.nu:  # the plate moving during events
        h.update(b"nu\0")
        _update(h, [model.nu], "<f8")
    if not ofc and model.viscous:  # the springs' dashpots, in the order of adjacency.data
        h.update(b"eta\0")
        _update(h, model.eta_values, "<f8")
    if model.faults is not None:  # a network of faults: its catalogs have fault columns
        h.update(json.dumps([_label_key(f) for f in model.faults]).encode())
        h.update(np.ascontiguousarray(model.fault_number, dtype="<i8").tobytes())
    return h.hexdigest()
