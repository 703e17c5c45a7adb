"""Numba kernels of faultnet (imports only numpy, numba and math).

The Python layer (:mod:`faultnet.solver.engine`) validates input, allocates every
array, calls these kernels and turns their status codes into exceptions.

- :mod:`.carlson_langer`: the Carlson-Langer engine's kernels, and only kernels (its physics
  in :mod:`.carlson_langer.physics`);
- :mod:`.ofc`: the Olami-Feder-Christensen automaton (drive, avalanches);
- :mod:`.jit`: the decorators every kernel is compiled with (Numba's ``njit``);
- :mod:`.cache`: the on-disk cache of the kernels, stamped with all their sources and sealed;
- :mod:`.layout`, :mod:`.bundles`: the named layouts of the arrays the kernels share with
  Python, and the bundles they travel in.

The kernels are imported on first use of a name below, so that importing
:mod:`faultnet.solver._kernels.layout` (the named layouts of the packed arrays) does
not import numba.
"""

import importlib

_NAMES = {
    "LOC_SIZE": "carlson_langer.work",
    "N_IWORK": "carlson_langer.work",
    "N_WORK": "carlson_langer.work",
    "OFC_RECENTRE_AT": "ofc",
    "OFC_STATUS_OK": "ofc",
    "OFC_STATUS_TOO_MANY_TOPPLINGS": "ofc",
    "STATUS_EVENT_TOO_LONG": "carlson_langer.crossing",
    "STATUS_INTERRUPTED": "carlson_langer.crossing",
    "STATUS_NONFINITE": "carlson_langer.crossing",
    "STATUS_OK": "carlson_langer.crossing",
    "STATUS_RUNAWAY": "carlson_langer.crossing",
    "STATUS_SLIPS_FULL": "carlson_langer.crossing",
    "empty_tree": "bundles",
    "is_cold": "cache",
    "run_events_dopri5": "carlson_langer.events",
    "run_events_dopri5_interpolated": "carlson_langer.events",
    "run_ofc": "ofc",
}

__all__ = sorted(_NAMES)


def __getattr__(name):
    if name in _NAMES:
        value = getattr(importlib.import_module(f"{__name__}.{_NAMES[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
