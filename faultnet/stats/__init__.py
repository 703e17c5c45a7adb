"""Event statistics: magnitude distributions, b-value fits, spatial irregularity.

:mod:`faultnet.stats.magnitudes` holds P(M) and the b fits (and the conventions
for ``b``); :mod:`faultnet.stats.irregularity` the roughness of slip profiles.
"""

from faultnet.stats.irregularity import irregularity
from faultnet.stats.magnitudes import (
    BFit,  # noqa: F401 (reachable as faultnet.stats.BFit)
    fit_b_lsq,
    fit_b_mle,
    format_pm,
    magnitude_distribution,
)

# BFit, the fits' result, is documented at the top level (faultnet.BFit)
__all__ = [
    "fit_b_lsq",
    "fit_b_mle",
    "format_pm",
    "irregularity",
    "magnitude_distribution",
]
