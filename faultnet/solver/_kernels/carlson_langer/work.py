"""Names of the event's work space: the columns of ``W``, the rows of ``IW`` and ``loc``.

Only *active* (slipping) blocks are integrated.  Positions are displacements ``delta`` since
the start of the event, so round-off does not grow with the plate position.  Float work lives
in the columns of ``W`` (shape (2 N + 2, N_WORK), block-major so one block's values share
cache lines), int work in the rows of ``IW`` (shape (N_IWORK, N); the active list
``IW[ACT, :nact]`` is contiguous); the column and row names are the constants below.  All
kernels are compiled without the Numba runtime (``_nrt=False``): they never allocate, and
array arguments then cost no atomic reference counting at call boundaries.

Invariants kept by every kernel:
- ``W[j, P] == W[j, P2] == W[j, D]`` for every block that is not active
  (neighbours read P and P2, the two stage-position buffers);
- ``W[j, V] == W[j, VN] == 0`` for every block that is not active, and in viscous models
  ``W[j, Q] == W[j, Q2] == 0`` too;
- the *plate row* ``W[PLATE]``, the last (``W[2 N + 1]``), holds, in each position column, the
  plate's advance ``nu t`` since the event's start at that column's instant; all zeros
  where the plate is frozen during events (``nu = 0``);
- every neighbour of an active block is *touched* (``IW[FLAG, j] != UNTOUCHED``)
  and has its starting force in ``W[j, F0]``;
- the ghost row ``W[2 N]``, which pads the neighbour table ``graph.nbr``, is all zeros.

``loc`` (float64[LOC_SIZE]) holds the crossings a step's scan listed: their number
``loc[LOC_NCAND]`` (-1: too many for ``IW[CAND]``), the summed moves of the end positions since
the scan ``loc[LOC_MOVED]`` (:mod:`.late_joins`) and, from ``LOC_THETA``, where the scan put
each listed crossing.
"""

import numpy as np

from faultnet.solver._kernels.jit import inline_kernel, kernel
from faultnet.solver._kernels.layout import CNT_STAMPS

__all__ = [
    "A",
    "ACT",
    "ACTIVE",
    "AN",
    "APOS",
    "CAND",
    "D",
    "DN",
    "F0",
    "FLAG",
    "FSEEN",
    "FRONTIER",
    "JOINING",
    "LOC_MOVED",
    "LOC_NCAND",
    "LOC_SIZE",
    "LOC_THETA",
    "MARK",
    "N_IWORK",
    "N_WORK",
    "P",
    "P2",
    "Q",
    "Q2",
    "SA",
    "STOPPING",
    "STUCK",
    "SV",
    "THETA_CACHE",
    "TOUCH",
    "UNTOUCHED",
    "V",
    "VN",
    "VS",
    "new_id",
    "PLATE",
    "velocities",
]

# float work columns of W: the committed state (D, V, A), the step's end (DN, VN, AN), the
# stage positions (P, P2), the force at the start of the event (F0); the interpolated
# crossings keep a crossing's fraction of the step in VS, a join's path end in SV and SA, a
# stop's position in SV (:mod:`.interp`).  Viscous models keep the stage velocities of P and
# P2 in Q and Q2, the same columns as SV and SA: they take the exact crossings, which never
# use SV and SA (two more columns cost the lattices 20% of their events/s: a block's row
# stays 96 bytes).
# The velocities at the instant of a position column (D with V, P with Q, P2 with Q2, DN with
# VN) are what the viscous force reads (:func:`velocities`); the columns keep the order the
# stage passes were measured with (``benchmarks/README.md``).
# (NumPy integers, not Python ints: Numba types them int64, not as literals, so a kernel
# that takes a column compiles one signature for all of them)
D, P, V, A, DN, VN, AN, SV, SA, VS, P2, F0 = (np.int64(c) for c in range(12))
Q, Q2 = SV, SA
N_WORK = 12
#: the plate row of W: its last, the plate's advance per position column (an int64, as the
#: columns; Numba's index wrap-around reads it as row 2 N + 1)
PLATE = np.int64(-1)
# int work rows: the block flags, the active list and each block's position in it, the
# touched list, the tags of the stuck blocks a step's scan has evaluated (fresh ids from
# :func:`new_id`), the crossings a step's scan listed; and by fault number, the event (plus 1)
# that last counted the fault
FLAG, ACT, TOUCH, APOS, MARK, CAND, FSEEN = range(7)
N_IWORK = 7
# block flags during an event
UNTOUCHED, ACTIVE, STUCK, FRONTIER = 0, 1, 2, 3
# interpolated crossings (:mod:`.interp`), within one step: a stuck block that joins inside
# it, a slipping block that stops inside it (while the crossings are located)
JOINING, STOPPING = 4, 5

#: number of crossings the step's scan listed in ``IW[CAND]`` (-1: too many)
LOC_NCAND = 0
#: summed |moves| of the end positions (``P2``) since the step's scan
LOC_MOVED = 1
#: ``loc[LOC_THETA + k]``: where the step put crossing candidate k (2.0: not located)
LOC_THETA = 2
#: candidates whose crossing is kept (the others count as not located)
THETA_CACHE = 4096
#: length of ``loc``
LOC_SIZE = LOC_THETA + THETA_CACHE


@inline_kernel
def new_id(cnt):
    """A fresh tag (``IW[MARK]``) from the counter ``cnt[CNT_STAMPS]``, never reset.

    ``cnt``: the counters (``layout.CNT_*``).  A tag never repeats for the life of the work
    arrays.
    """
    cnt[CNT_STAMPS] += 1
    return cnt[CNT_STAMPS]


@kernel
def velocities(pos):
    """The column of the velocities at the instant of position column ``pos`` (D, P, P2, DN)."""
    if pos == D:
        return V
    if pos == DN:
        return VN
    if pos == P:
        return Q
    return Q2
