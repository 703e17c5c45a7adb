"""From the kernel's raw output to a :class:`~faultnet.SimulationResult`.

One metadata builder (:func:`run_metadata`) serves in-memory results and
Parquet catalogs alike; :func:`raise_status` turns the kernel's status codes
into the domain errors of :mod:`faultnet.exceptions`.
"""

from __future__ import annotations

import warnings

import numpy as np

from faultnet._version import __version__
from faultnet.exceptions import EventTooLongError, NumericalInstabilityError
from faultnet.solver._kernels.layout import (
    CNT_INTERPOLATED_CROSSINGS,
    CNT_PARTIAL_BLOCK_STEPS,
    CNT_RETAKEN_STEPS,
    CNT_REVEALED_JOINS,
    CNT_SOLO_EVENTS,
    CNT_TRACE_FULL,
    CNT_TRACE_ROWS,
    CTRL_MAX_DURATION,
    CTRL_MAX_VELOCITY,
    OUT_HYPOCENTER,
)
from faultnet.solver.result import (
    SimulationResult,
    fault_slips_frame,
    slips_frame,
    traces_frame,
)

__all__ = ["raise_status", "run_metadata", "wrap_result"]

#: error class and message per kernel status (by name: the codes live in the kernels)
_STATUS_MESSAGES = {
    "STATUS_NONFINITE": (
        NumericalInstabilityError,
        "a velocity became NaN at block {node!r} in event {event}; reduce dt (now {dt:g})",
    ),
    "STATUS_RUNAWAY": (
        NumericalInstabilityError,
        "runaway velocity (> {vmax:g}) at block {node!r} in event {event}; the integration "
        "is unstable: reduce dt (now {dt:g}) or check k, sigma and alpha",
    ),
    "STATUS_EVENT_TOO_LONG": (
        EventTooLongError,
        "event {event} was still running after {maxd:g} time units; raise "
        "max_event_duration if such long events are expected, else reduce dt (now {dt:g})",
    ),
}

#: work counters reported in the metadata of every chunk
_COUNTERS = {
    "solo_events": CNT_SOLO_EVENTS,
    "partial_block_steps": CNT_PARTIAL_BLOCK_STEPS,
    "interpolated_crossings": CNT_INTERPOLATED_CROSSINGS,
    "revealed_joins": CNT_REVEALED_JOINS,
    "retaken_steps": CNT_RETAKEN_STEPS,
}


def run_metadata(model, options, dt, seq, solo_cache=True) -> dict:
    """What defines a run: model parameters, options, the step, the seed and the version."""
    md = dict(model.params)
    md.update(
        dt=dt,
        method=options.method,
        crossings=options.treatment(model),
        options=options.to_dict(),
        solo_cache=bool(solo_cache),
        faultnet_version=__version__,
        seed_entropy=None if seq is None else seq.entropy,
        seed_spawn_key=None if seq is None else tuple(seq.spawn_key),
    )
    return md


def raise_status(K, status, arrays, model, event, dt):
    """Raise the domain error of a kernel ``status`` (not OK, not slips-full)."""
    cls, template = next(v for name, v in _STATUS_MESSAGES.items() if getattr(K, name) == status)
    bad = int(arrays.out[OUT_HYPOCENTER]) if status == K.STATUS_EVENT_TOO_LONG else None
    node = model.nodes[bad] if bad is not None else "?"
    message = template.format(
        node=node,
        event=event,
        dt=dt,
        vmax=arrays.ctrl[CTRL_MAX_VELOCITY],
        maxd=arrays.ctrl[CTRL_MAX_DURATION],
    )
    nu = model.params.get("nu") if status == K.STATUS_EVENT_TOO_LONG else None
    if nu:  # the usual cause with a moving plate (a ring of 500 at nu = 0.01 never stops)
        message += (
            f"; with nu = {nu:g} the plate drives the blocks during the event, and at such a "
            "plate velocity they can go on slipping without end: a smaller nu gives events "
            "that end"
        )
    raise cls(message)


def _slips(nodes, arrays):
    parts = arrays.slip_parts or [(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0))]
    event, node, slip = (np.concatenate([p[c] for p in parts]) for c in range(3))
    slips = slips_frame(event, node, slip, nodes)
    slips.attrs["truncated"] = arrays.slips_truncated
    if arrays.slips_truncated:
        warnings.warn(
            f"per-block slips were recorded for the first {len(slips):,} rows only "
            "(max_slip_rows); the event catalog is complete",
            stacklevel=4,
        )
    return slips


def _fault_slips(faults, arrays):
    parts = arrays.fault_parts or [(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0))]
    event, fault, slip = (np.concatenate([p[c] for p in parts]) for c in range(3))
    return fault_slips_frame(event, fault, slip, faults)


def wrap_result(model, arrays, state, dt, events, md, record_profiles, labels) -> SimulationResult:
    """The chunk's :class:`SimulationResult`, with the work counters added to ``md``;
    ``labels``: the model's nodes and faults (None without), or their
    :func:`~faultnet.solver.result.label_array`."""
    nodes, faults = labels
    md.update({name: int(arrays.cnt[i]) for name, i in _COUNTERS.items()})
    arrays.cnt[list(_COUNTERS.values())] = 0
    traces = None
    if arrays.trace_idx.size:
        rows = int(arrays.cnt[CNT_TRACE_ROWS])
        traces = traces_frame(arrays.trace[:rows], arrays.trace_idx, nodes)
        traces.attrs["truncated"] = bool(arrays.cnt[CNT_TRACE_FULL])
    return SimulationResult(
        events=events,
        state=state,
        model=model,
        dt=dt,
        metadata=md,
        slips=_slips(nodes, arrays) if arrays.record_slips else None,
        profiles=arrays.profiles if record_profiles else None,
        traces=traces,
        fault_slips=_fault_slips(faults, arrays) if faults is not None else None,
    )
