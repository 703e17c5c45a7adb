"""Statistical seismology of synthetic catalogs: waiting times, recurrence, Omori decay,
mainshock stacks, quiescence, sliding b-values, networks of faults, SeismoStats and QuakeML.

Every function takes an events DataFrame (``result.events``) and, for spatial questions, the graph.
"""

from faultnet.seismicity.ecosystem import compare_b, to_quakeml, to_seismostats
from faultnet.seismicity.faults import (
    b_per_fault,
    fault_magnitudes,
    fault_triggering,
    multi_fault_fraction,
)
from faultnet.seismicity.geometry import Geometry, geometry
from faultnet.seismicity.mainshocks import (
    aftershock_times,
    b_around_mainshocks,
    distance_profile,
    stack_mainshocks,
)
from faultnet.seismicity.omori import OmoriFit, fit_omori, sample_omori
from faultnet.seismicity.timing import Recurrence, b_series, interevent_times, recurrence

__all__ = [
    "Geometry",
    "geometry",
    "OmoriFit",
    "Recurrence",
    "aftershock_times",
    "b_around_mainshocks",
    "b_per_fault",
    "b_series",
    "compare_b",
    "distance_profile",
    "fault_magnitudes",
    "fault_triggering",
    "fit_omori",
    "interevent_times",
    "multi_fault_fraction",
    "recurrence",
    "sample_omori",
    "stack_mainshocks",
    "to_quakeml",
    "to_seismostats",
]
