"""Statistical seismology of synthetic catalogs: waiting times, recurrence, Omori decay,
mainshock stacks, quiescence, sliding b-values, and the bridge to SeismoStats and QuakeML.

Every function takes an events DataFrame (``result.events``) and, for spatial questions, the graph.
"""

from faultnet.seismicity.ecosystem import compare_b, to_quakeml, to_seismostats
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
    "b_series",
    "compare_b",
    "distance_profile",
    "fit_omori",
    "interevent_times",
    "recurrence",
    "sample_omori",
    "stack_mainshocks",
    "to_quakeml",
    "to_seismostats",
]
