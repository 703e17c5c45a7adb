"""Event catalogs: pandas DataFrames built from the kernel's raw arrays."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from faultnet.model.state import State
from faultnet.solver._kernels.layout import (
    CAT_BLOCKS,
    CAT_DURATION,
    CAT_FAULTS,
    CAT_HYPOCENTER,
    CAT_S,
    CAT_STEPS,
    CAT_T,
    TRACE_EVENT,
    TRACE_TIME,
    TRACE_X,
)

__all__ = [
    "SimulationResult",
    "events_frame",
    "fault_slips_frame",
    "label_array",
    "slips_frame",
    "traces_frame",
]

EVENT_COLUMNS = ["event", "t", "duration", "n_blocks", "S", "M", "hypocenter", "n_steps"]
#: the columns a network of faults adds (a graph whose blocks carry ``fault``)
FAULT_COLUMNS = ["fault", "n_faults"]


def label_array(labels):
    """``labels`` (a model's nodes, or its faults) as what :func:`node_labels` indexes: an int64
    array where every label is an int, else an object array (tuple labels stay tuples), a
    ``range`` as it is (None, a model without faults, too).  O(N): a simulator makes it once,
    not for every chunk's frames (on a 1024^2 lattice it takes 0.13 s)."""
    if labels is None or isinstance(labels, range | np.ndarray):  # range: a SparseGraph's
        return labels
    if all(isinstance(n, (int, np.integer)) and not isinstance(n, bool) for n in labels):
        return np.asarray(labels, dtype=np.int64)
    out = np.empty(len(labels), dtype=object)
    out[:] = list(labels)  # element-wise: tuple labels stay tuples
    return out


def node_labels(nodes, idx):
    """Map block indices to graph node labels (integer dtype when labels are ints); ``nodes``
    the labels or their :func:`label_array`."""
    idx = np.asarray(idx, dtype=np.int64)
    nodes = label_array(nodes)
    if isinstance(nodes, range):
        return nodes.start + nodes.step * idx
    return nodes[idx]


def events_frame(ev0, cat_f, cat_i, nodes, faults=None, fault_number=None):
    """One row per event: event, t, duration, n_blocks, S, M, hypocenter, n_steps; on a network
    of faults (``faults``: the labels, ``fault_number``: each block's index into them) also
    fault (the hypocentre's) and n_faults (the faults among the blocks that slipped).  The
    labels may be given as their :func:`label_array`."""
    n = cat_f.shape[0]
    S = cat_f[:, CAT_S]
    with np.errstate(divide="ignore"):
        M = np.log(S)
    hypocenter = cat_i[:, CAT_HYPOCENTER]
    columns = {
        "event": np.arange(ev0, ev0 + n, dtype=np.int64),
        "t": cat_f[:, CAT_T],
        "duration": cat_f[:, CAT_DURATION],
        "n_blocks": cat_i[:, CAT_BLOCKS],
        "S": S,
        "M": M,
        "hypocenter": node_labels(nodes, hypocenter),
        "n_steps": cat_i[:, CAT_STEPS],
    }
    if faults is not None:
        columns["fault"] = node_labels(faults, fault_number[hypocenter])
        columns["n_faults"] = cat_i[:, CAT_FAULTS]
    return pd.DataFrame(columns)


def slips_frame(event, node, slip, nodes):
    """Per-block slips in long format: event, node, slip."""
    return pd.DataFrame(
        {"event": event.astype(np.int64), "node": node_labels(nodes, node), "slip": slip}
    )


def fault_slips_frame(event, fault, slip, faults):
    """Per-fault slips in long format: event, fault, slip (``fault``: numbers into the
    labels ``faults``)."""
    return pd.DataFrame(
        {"event": event.astype(np.int64), "fault": node_labels(faults, fault), "slip": slip}
    )


def traces_frame(buf, trace_idx, nodes):
    """Trajectories inside events in long format: event, time, node, x, v."""
    m = len(trace_idx)
    rows = buf.shape[0]
    return pd.DataFrame(
        {
            "event": np.repeat(buf[:, TRACE_EVENT].astype(np.int64), m),
            "time": np.repeat(buf[:, TRACE_TIME], m),
            "node": np.tile(node_labels(nodes, trace_idx), rows),
            "x": buf[:, TRACE_X : TRACE_X + m].reshape(-1),
            "v": buf[:, TRACE_X + m : TRACE_X + 2 * m].reshape(-1),
        }
    )


@dataclass
class SimulationResult:
    """What :func:`faultnet.simulate` returns.

    Attributes
    ----------
    events : pandas.DataFrame
        One row per event: ``event`` (running number), ``t`` (plate
        displacement at the start = time in units of 1/v0), ``duration``,
        ``n_blocks`` (distinct blocks that slipped), ``S`` (total slip),
        ``M = ln S``, ``hypocenter`` (graph node that failed first) and
        ``n_steps`` (integration steps; for a free single-block slip, the steps
        of the block's cached solo slip, see ``RunOptions.solo_cache``).
    state : State
        Final state; pass it as ``x0`` to continue the run exactly.
    slips : pandas.DataFrame or None
        Per-block slips (``event``, ``node``, ``slip``) if recorded.
    fault_slips : pandas.DataFrame or None
        On a network of faults (blocks with the node attribute ``fault``), each event's slip
        summed per fault: ``event``, ``fault``, ``slip``, one row per fault that slipped, by
        event and then by the faults' order in the graph.  ``n_faults`` counts these rows.
    profiles : numpy.ndarray or None
        Displacements after each event, shape (n_events, n_blocks), if recorded.
    traces : pandas.DataFrame or None
        ``x`` and ``v`` of the traced blocks at every step inside events
        (``event``, ``time`` since the event start, ``node``, ``x``, ``v``).
    metadata : dict
        Parameters, dt, seed (SeedSequence entropy and spawn key), versions,
        wall time and work counters: ``n_steps`` and ``block_steps`` (work
        actually done in this call), ``solo_events`` (events taken from a
        cached solo slip, which cost no integration), the part of
        ``block_steps`` spent in partial steps to crossings and their polish
        (``partial_block_steps``), ``interpolated_crossings`` (stops and
        joins placed on a step's dense output), ``revealed_joins`` (joins that
        those crossings pushed over the threshold, counted in every take of a
        step) and ``retaken_steps`` (steps
        taken again at half their length: a block stopped and started again
        within them, or they held more crossings than their list).
    """

    events: pd.DataFrame
    state: State
    model: object = field(repr=False)
    dt: float
    metadata: dict = field(default_factory=dict)
    slips: pd.DataFrame | None = None
    profiles: np.ndarray | None = None
    traces: pd.DataFrame | None = None
    fault_slips: pd.DataFrame | None = None

    @property
    def x(self) -> np.ndarray:
        """Final block displacements (node order of the model)."""
        return self.state.x

    @property
    def u(self) -> float:
        """Final plate position."""
        return self.state.u

    @property
    def seed(self):
        """Entropy of the SeedSequence that drew the initial state (None if x0 was given)."""
        return self.metadata.get("seed_entropy")

    def summary(self) -> str:
        """A few lines describing the run."""
        ev = self.events
        md = self.metadata
        lines = [
            f"{md.get('graph')}: {len(ev)} events, k={md.get('k')}, sigma={md.get('sigma')}, "
            f"alpha={md.get('alpha')}, dt={self.dt:.3g}",
            f"plate time {ev['t'].iloc[0]:.4g} .. {ev['t'].iloc[-1]:.4g}; "
            f"M = ln S in [{ev['M'].min():.3f}, {ev['M'].max():.3f}]; "
            f"largest event {int(ev['n_blocks'].max())} blocks",
        ]
        if md.get("wall_time_s"):
            lines.append(
                f"wall time {md['wall_time_s']:.2f} s = {len(ev) / md['wall_time_s']:,.0f} events/s"
            )
        return "\n".join(lines)
