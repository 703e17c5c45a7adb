"""Numba kernels of faultnet (imports only numpy, numba and math).

The public Python layer (:mod:`faultnet.simulate`) validates input, allocates
every array, calls these kernels and turns their status codes into exceptions.
"""

from faultnet._kernels.context import LOC_SIZE
from faultnet._kernels.crossing import (
    STATUS_EVENT_TOO_LONG,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_RUNAWAY,
    STATUS_SLIPS_FULL,
)
from faultnet._kernels.dopri import N_WORK_DOPRI
from faultnet._kernels.events import run_events_dopri5, run_events_rk4
from faultnet._kernels.integrate import N_IWORK
from faultnet._kernels.tree import build_keys_and_tree, empty_tree

__all__ = [
    "LOC_SIZE",
    "N_IWORK",
    "N_WORK_DOPRI",
    "STATUS_EVENT_TOO_LONG",
    "STATUS_NONFINITE",
    "STATUS_OK",
    "STATUS_RUNAWAY",
    "STATUS_SLIPS_FULL",
    "build_keys_and_tree",
    "empty_tree",
    "run_events_dopri5",
    "run_events_rk4",
]
