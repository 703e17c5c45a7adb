"""Layout of ``loc``, the local-region context shared by the step kernels.

``loc`` (float64[LOC_SIZE], allocated once per run) holds, for the step being
handled in local regions (:mod:`faultnet._kernels.local`):

- ``loc[LOC_BND_START]``, ``loc[LOC_BND_END]``: the current region's boundary list
  ``IW[BND, loc[LOC_BND_START]:loc[LOC_BND_END]]`` (empty outside a region);
- ``loc[LOC_REGION_T]``: the start of the current region step, as a fraction of the outer step;
- ``loc[LOC_OUTER_H]``: the outer step's length;
- ``loc[LOC_NSAVED]``: the number of blocks saved for a fallback (``IW[SLIST]``);
- ``loc[LOC_STEP_ID]``: the outer step's id (tags the saves of ``IW[SAVE]``);
- ``loc[LOC_NCAND]``: the crossings listed by the outer step's scan (-1: too many);
- ``loc[LOC_MOVED]``: with interpolated crossings, the summed moves of the blocks' end
  positions (``P2``) since the step's scan (``faultnet._kernels.late_joins``);
- from ``LOC_CACHE``: the dense-output coefficients of boundary blocks (five each);
- from ``LOC_THETA``: where the outer step put each listed crossing.
"""

__all__ = [
    "BOUNDARY_CACHE",
    "LOC_BND_END",
    "LOC_BND_START",
    "LOC_CACHE",
    "LOC_MOVED",
    "LOC_NCAND",
    "LOC_NSAVED",
    "LOC_OUTER_H",
    "LOC_REGION_T",
    "LOC_SIZE",
    "LOC_STEP_ID",
    "LOC_THETA",
    "THETA_CACHE",
]

#: start of the current region's boundary list in ``IW[BND]``
LOC_BND_START = 0
#: end of the current region's boundary list (equal to the start: no region)
LOC_BND_END = 1
#: start of the current region step, as a fraction of the outer step
LOC_REGION_T = 2
#: length of the outer step
LOC_OUTER_H = 3
#: blocks saved for a fallback, listed in ``IW[SLIST]``
LOC_NSAVED = 4
#: id of the outer step, which tags the saves kept in ``IW[SAVE]``
LOC_STEP_ID = 5

#: number of crossings the outer step's scan listed in ``IW[CAND]``
LOC_NCAND = 6
#: interpolated crossings: summed |moves| of end positions since the step's scan
LOC_MOVED = 7
#: ``loc[:LOC_CACHE]`` is the step context; then the dense coefficients of boundary blocks
LOC_CACHE = 8
#: boundary blocks whose coefficients are kept (more are evaluated from their stages)
BOUNDARY_CACHE = 4096
#: ``loc[LOC_THETA + k]``: where the outer step put crossing candidate k (2.0: not located)
LOC_THETA = LOC_CACHE + 5 * BOUNDARY_CACHE
#: candidates whose crossing is kept (the others count as not located)
THETA_CACHE = 4096
#: length of ``loc``
LOC_SIZE = LOC_THETA + THETA_CACHE
