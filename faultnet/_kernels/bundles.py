"""The named bundles in which the kernels' arrays travel.

The Python layer (:class:`faultnet.kernel_arrays.KernelArrays`) builds one of each and hands
them to an entry kernel (:mod:`faultnet._kernels.events`); inner kernels take the bundles they
need and read their fields by name (``g.indptr``).  Each bundle is a ``namedtuple``, which
Numba types as a tuple: a field is read at no cost, and a kernel called with a bundle
compiles for the field types only (one signature per bundle).

The hot inner kernels (the stage passes of :func:`faultnet._kernels.dopri.dopri_step` and
:func:`faultnet._kernels.integrate.rk4_step`, :func:`~faultnet._kernels.integrate.force`,
:func:`~faultnet._kernels.integrate.accel` and the crossing scan of
:mod:`faultnet._kernels.crossing`) take the arrays themselves, unpacked once by their caller.
"""

from collections import namedtuple

__all__ = ["Graph", "Records", "State", "Work"]

#: Topology and per-block parameters (read-only in the kernels).
#:
#: - ``indptr``, ``indices`` (int64[N + 1], int64[nnz]): the graph in CSR form, block i's
#:   neighbours ``indices[indptr[i]:indptr[i + 1]]``;
#: - ``kval`` (float64[nnz]): the spring constant of each CSR entry;
#: - ``diag`` (float64[N]): a block's total stiffness, 1 + sum of its springs;
#: - ``oms`` (float64[N]): 1 - sigma, the dynamic friction at rest;
#: - ``cfr`` (float64[N]): 2 alpha / (1 - sigma), the velocity weakening of the friction;
#: - ``k_uniform`` (float): the spring constant when every spring has it, else 0.0 (the DP5
#:   stages and the join scan then sum the neighbours' positions and multiply once).
Graph = namedtuple("Graph", ["indptr", "indices", "kval", "diag", "oms", "cfr", "k_uniform"])

#: The model's state between events (:mod:`faultnet._kernels.tree`).
#:
#: - ``z`` (float64[N]): block displacements minus the frame offset;
#: - ``scal`` (float64[SCAL_SIZE]): the frame offset and the plate position relative to it
#:   (``layout.SCAL_*``);
#: - ``keys`` (float64[N]): each block's failure key, the plate position at which it fails;
#: - ``tree`` (int64[2 * leaves]): the tournament tree over the keys (its root, ``tree[1]``,
#:   the next block to fail).
State = namedtuple("State", ["z", "scal", "keys", "tree"])

#: The event's work space and the counters of the current call.
#:
#: - ``W`` (float64[2 N, N_WORK]): float work, block-major: row i for block i (columns named in
#:   :mod:`faultnet._kernels.integrate`), row N + q the DP5 stage derivatives of the block at
#:   active position q (:func:`faultnet._kernels.tableau.stage_rows`, columns ``KV``, ``KA``);
#: - ``IW`` (int64[N_IWORK, N]): int work, rows named in :mod:`faultnet._kernels.integrate`;
#: - ``loc`` (float64[LOC_SIZE]): the local-region context of a step
#:   (:mod:`faultnet._kernels.context`);
#: - ``cnt`` (int64[CNT_SIZE]): counters (``layout.CNT_*``).
Work = namedtuple("Work", ["W", "IW", "loc", "cnt"])

#: What a call records.  Buffers of length 0 record nothing.
#:
#: - ``cat_f`` (float64[n_req, CAT_F_SIZE]), ``cat_i`` (int64[n_req, CAT_I_SIZE]): the event
#:   catalog, one row per event (``layout.CAT_*``);
#: - ``slip_event``, ``slip_node`` (int64[rows]), ``slip_val`` (float64[rows]): per-block slips,
#:   one row per block and event (rows used: ``cnt[CNT_SLIP_ROWS]``);
#: - ``trace_nodes`` (int64[m]): the traced blocks;
#: - ``trace_buf`` (float64[rows, TRACE_X + 2 m]): their positions and velocities at every
#:   step inside events (``layout.TRACE_*``; rows used: ``cnt[CNT_TRACE_ROWS]``);
#: - ``profiles`` (float64[n_req, N] or [0, 0]): the displacements after each event;
#: - ``out`` (float64[OUT_SIZE]): the last event's catalog row (``layout.OUT_*``), also when
#:   it failed.
Records = namedtuple(
    "Records",
    [
        "cat_f",
        "cat_i",
        "slip_event",
        "slip_node",
        "slip_val",
        "trace_nodes",
        "trace_buf",
        "profiles",
        "out",
    ],
)
