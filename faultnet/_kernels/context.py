"""Layout of ``loc``, the local-region context shared by the step kernels.

``loc`` (float64[LOC_SIZE], allocated once per run) holds, for the step being
handled in local regions (:mod:`faultnet._kernels.local`):

- ``loc[0]``, ``loc[1]``: the current region's boundary list ``IW[BND, loc[0]:loc[1]]``;
- ``loc[2]``: the start of the current region step, as a fraction of the outer step;
- ``loc[3]``: the outer step's length;
- ``loc[4]``: the number of blocks saved for a fallback;
- ``loc[5]``: the step's id;
- ``loc[LOC_NCAND]``: the crossings listed by the outer step's scan (-1: too many);
- from ``LOC_CACHE``: the dense-output coefficients of boundary blocks (five each);
- from ``LOC_THETA``: where the outer step put each listed crossing.
"""

__all__ = ["BOUNDARY_CACHE", "LOC_CACHE", "LOC_NCAND", "LOC_SIZE", "LOC_THETA", "THETA_CACHE"]

#: number of crossings the outer step's scan listed in ``IW[CAND]``
LOC_NCAND = 6
#: ``loc[:LOC_CACHE]`` is the region context; then the dense coefficients of boundary blocks
LOC_CACHE = 7
#: boundary blocks whose coefficients are kept (more are evaluated from their stages)
BOUNDARY_CACHE = 4096
#: ``loc[LOC_THETA + k]``: where the outer step put crossing candidate k (2.0: not located)
LOC_THETA = LOC_CACHE + 5 * BOUNDARY_CACHE
#: candidates whose crossing is kept (the others count as not located)
THETA_CACHE = 4096
#: length of ``loc``
LOC_SIZE = LOC_THETA + THETA_CACHE
