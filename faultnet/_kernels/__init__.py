"""Numba kernels of faultnet (imports only numpy, numba and math).

The Python layer (:mod:`faultnet.engine`) validates input, allocates every
array, calls these kernels and turns their status codes into exceptions.

The kernels are imported on first use of a name below, so that importing
:mod:`faultnet._kernels.layout` (the named layouts of the packed arrays) does
not import numba.
"""

import importlib

_NAMES = {
    "LOC_SIZE": "context",
    "N_IWORK": "integrate",
    "N_WORK": "integrate",
    "STATUS_EVENT_TOO_LONG": "crossing",
    "STATUS_NONFINITE": "crossing",
    "STATUS_OK": "crossing",
    "STATUS_RUNAWAY": "crossing",
    "STATUS_SLIPS_FULL": "crossing",
    "empty_tree": "tree",
    "is_cold": "cache",
    "run_events_dopri5": "events",
    "run_events_dopri5_interpolated": "events",
    "run_events_dopri5_local": "events",
    "run_events_rk4": "events",
}

__all__ = sorted(_NAMES)


def __getattr__(name):
    if name in _NAMES:
        value = getattr(importlib.import_module(f"{__name__}.{_NAMES[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
