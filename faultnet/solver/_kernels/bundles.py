"""The named bundles in which the kernels' arrays travel.

The Python layer (:class:`faultnet.solver.arrays.KernelArrays`) builds one of each and hands
them to an entry kernel (:mod:`.carlson_langer.events`); inner kernels take the bundles they
need and read their fields by name (``g.indptr``).  Each bundle is a ``namedtuple``, which
Numba types as a tuple: a field is read at no cost, and a kernel called with a bundle
compiles for the field types only (one signature per bundle).

The hot inner kernels (the stage passes of :func:`~.carlson_langer.dopri.dopri_step`, the force
and acceleration of :mod:`~.carlson_langer.physics` and the crossing scan of
:mod:`~.carlson_langer.crossing`) take the arrays themselves, unpacked once by their caller.
"""

from collections import namedtuple

import numpy as np

__all__ = [
    "BLOCK_SIZE",
    "CFR",
    "DIAG",
    "ETA_SUM",
    "FRAME",
    "OMS",
    "Graph",
    "KelvinGraph",
    "OFCGraph",
    "OFCRecords",
    "OFCState",
    "OFCWork",
    "Records",
    "State",
    "Work",
    "empty_tree",
    "graph_bundle",
    "kelvin",
    "ofc_neighbours",
    "ofc_tree",
    "ofc_work",
    "padded_neighbours",
    "tree_size",
    "work_array",
]

#: Columns of ``Graph.block`` (float64[N, BLOCK_SIZE]), one row of parameters per block:
#: ``DIAG`` its total stiffness (1 + the sum of its springs and its frame springs), ``OMS``
#: 1 - sigma (the dynamic friction at rest), ``CFR`` 2 alpha / (1 - sigma) (the friction's
#: velocity weakening), ``FRAME`` its frame springs' stiffness (``k wall``, part of
#: ``DIAG``, which tie it to a frame at rest at x = 0; 0.0 without walls) and ``ETA_SUM``
#: the sum of its springs' viscous couplings.
DIAG, OMS, CFR, FRAME, ETA_SUM = 0, 1, 2, 3, 4
BLOCK_SIZE = 5

#: Topology and per-block parameters (read-only in the kernels).
#:
#: - ``indptr``, ``indices`` (int64[N + 1], int64[nnz]): the graph in CSR form, block i's
#:   neighbours ``indices[indptr[i]:indptr[i + 1]]``;
#: - ``kval`` (float64[nnz]): the spring constant of each CSR entry;
#: - ``block`` (float64[N, BLOCK_SIZE]): each block's parameters, columns ``DIAG``, ``OMS``,
#:   ``CFR``, ``FRAME`` and ``ETA_SUM`` (above).  One array rather than one per parameter:
#:   a kernel call passes each array of a bundle as seven values (its data pointer, shape,
#:   strides, ...), and with six more 1-D arrays in this bundle a lattice's cold compile
#:   spent 0.5 s longer in Numba's lowering and LLVM's passes (the calls' arguments taken
#:   apart and put together again); a block's parameters are also read together;
#: - ``k_uniform`` (float): the spring constant when every spring has it and ``nbr`` holds
#:   every neighbour, else 0.0 (the DP5 stages and the join scan then sum the neighbours'
#:   positions over ``nbr`` and multiply once);
#: - ``nbr`` (uint64[N, width]): each block's neighbours in CSR order, padded with the ghost
#:   row of ``W`` (index 2 N, always 0) to the largest degree; width 0 on a graph with hubs
#:   (:func:`padded_neighbours`).  Unsigned, so that Numba indexes ``W`` with them without
#:   its negative-index wrap-around (2-6% more events/s on W1 and W6);
#: - ``fault`` (int64[N]): each block's fault, numbered from 0 (all 0 on a graph without
#:   fault labels), so that an event counts the faults it ruptured;
#: - ``nu`` (float): the plate's velocity during events (0.0: frozen, the plate moves between
#:   events only);
#: - ``eta`` (float64[nnz]): the viscous (Kelvin) coupling of each CSR entry (each block's
#:   total is ``block[:, ETA_SUM]``); ``viscous`` (bool): whether any is nonzero (else the
#:   force skips the viscous term); ``eta_uniform`` (float): the dashpots' constant where
#:   every spring has one, the same, and ``k_uniform`` is set, else 0.0 (the hot force then
#:   sums the neighbours' velocities in the pass over ``nbr`` that sums their positions).
Graph = namedtuple(
    "Graph",
    [
        "indptr",
        "indices",
        "kval",
        "block",
        "k_uniform",
        "nbr",
        "fault",
        "nu",
        "eta",
        "viscous",
        "eta_uniform",
    ],
)

#: The :data:`Graph` of a model whose plate moves during events or whose blocks are viscously
#: coupled (the same fields): a Numba type of its own, so that the kernels compile the
#: plate's and the viscous terms for such models only (:func:`kelvin`).
KelvinGraph = namedtuple("KelvinGraph", Graph._fields)


def kelvin(graph):
    """Whether ``graph`` is a :data:`KelvinGraph`; a compile-time constant in the kernels.

    A kernel guards the plate's and the viscous terms with it, so that a plain model runs
    the kernels it ran before these terms existed: with the terms behind run-time branches
    (``graph.nu > 0``, ``graph.viscous``) the plain ring ran 10-15% fewer events/s.  The
    guarded code is still typed and lowered for a plain :data:`Graph` (LLVM drops it), so
    longer terms are kernels of their own that a plain model never compiles
    (:func:`~faultnet.solver._kernels.jit.kelvin_kernel`).  Its compiled form is an
    ``overload`` in :mod:`~faultnet.solver._kernels.jit`.
    """
    return isinstance(graph, KelvinGraph)


#: The model's state between events (:mod:`.carlson_langer.tree`).
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
#: - ``W`` (float64[2 N + 2, N_WORK], :func:`work_array`): float work, block-major: row i for
#:   block i (columns named in :mod:`.carlson_langer.work`), row N + q the DP5 stage
#:   derivatives of the block at active position q (:func:`.carlson_langer.tableau.stage_rows`,
#:   columns ``KV``, ``KA``), row 2 N the ghost, never written, which padded neighbours
#:   read (``Graph.nbr``), and row 2 N + 1 the plate's advance during the event
#:   (``carlson_langer.work.PLATE``, its last);
#: - ``IW`` (int64[N_IWORK, N]): int work, rows named in :mod:`.carlson_langer.work`;
#: - ``loc`` (float64[LOC_SIZE]): the crossings a step listed (:mod:`.carlson_langer.work`);
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


#: The OFC automaton's springs (:mod:`.ofc`), read-only (:func:`ofc_neighbours`).
#:
#: - ``indptr`` (int64[N + 1]): the springs in CSR form, as in :data:`Graph`;
#: - ``nbr`` (int32[N * width], or int32[nnz] where ``width`` is 0): each block's neighbours,
#:   ``width`` to a row padded with -1 (the neighbours of block i at ``[i * width, (i + 1) *
#:   width)``), or in CSR order (``[indptr[i], indptr[i + 1])``) on a graph with hubs;
#: - ``kval`` (float64, the layout of ``nbr``): the spring constant of each entry;
#: - ``width`` (int): the padded rows' length, 0 for the CSR layout;
#: - ``stiff`` (float64[N]): each block's ``K_i = sum_j k_ij + k wall_i + 1``;
#: - ``k_uniform`` (float): the spring constant when every spring has it, else 0.0;
#: - ``fault`` (int64[N]): each block's fault, as in :data:`Graph`.
OFCGraph = namedtuple("OFCGraph", ["indptr", "nbr", "kval", "width", "stiff", "k_uniform", "fault"])

#: The OFC automaton's state between avalanches.
#:
#: - ``keys`` (float64[N]): the drive (relative to the offset) at which each block reaches the
#:   threshold 1: its force is ``1 + w - key``;
#: - ``scal`` (float64[SCAL_SIZE]): the offset and the drive relative to it, ``w``
#:   (``layout.SCAL_*``);
#: - ``tv``, ``ti`` (float64 and int64[2 * leaves], :func:`ofc_tree`): the tournament tree of
#:   the smallest key and its block over chunks of ``2**OFC_CHUNK_SHIFT`` consecutive blocks
#:   (leaf ``leaves + c`` holds chunk c's; ``ti`` -1 where a chunk is empty, -2 where its
#:   smallest key is to be found again).
OFCState = namedtuple("OFCState", ["keys", "scal", "tv", "ti"])

#: The OFC automaton's work space (:func:`ofc_work`).
#:
#: - ``cur``, ``nxt`` (int64[N + 64]): the blocks toppling in this generation and the next
#:   (``nxt`` also serves as the stack of the search for the blocks at the threshold);
#: - ``amount`` (float64[N + 64]): the force, then the slip, of each block of ``cur``;
#: - ``mark`` (int64[N]): the generation in whose ``nxt`` a block was put;
#: - ``seen`` (int64[N]): the avalanche in which a block last toppled;
#: - ``fseen`` (int64[n_faults]): the avalanche in which a fault last had a toppling;
#: - ``cmark``, ``clist`` (int64[chunks]): the avalanche in which a chunk's smallest key
#:   changed, and the list of those chunks;
#: - ``cnt`` (int64[OFC_CNT_SIZE]): counters (``layout.OFC_CNT_*``).
OFCWork = namedtuple(
    "OFCWork", ["cur", "nxt", "amount", "mark", "seen", "fseen", "cmark", "clist", "cnt"]
)

#: What the OFC entry records: ``cat_f`` (float64[n_req, OFC_CAT_F_SIZE]) and ``cat_i``
#: (int64[n_req, OFC_CAT_I_SIZE]), one row per avalanche (``layout.OFC_CAT_*``).
OFCRecords = namedtuple("OFCRecords", ["cat_f", "cat_i"])


def ofc_neighbours(indptr, indices, kval):
    """``(nbr, kval, width)`` of :data:`OFCGraph` from the CSR arrays.

    Rows padded with -1 to the largest degree: a block's neighbours are read from one short
    row, without ``indptr`` (on the 256^2 lattice 15-25% more topplings/s than CSR).  A graph
    whose largest degree exceeds twice its mean degree plus 8 (a graph with hubs) keeps the
    CSR layout (width 0), as :func:`padded_neighbours` does.

    >>> nbr, k, width = ofc_neighbours(np.array([0, 1, 3, 4]), np.array([1, 0, 2, 1]), np.ones(4))
    >>> nbr.tolist(), width
    ([1, -1, 0, 2, 1, -1], 2)
    """
    indptr = np.asarray(indptr, dtype=np.int64)
    n = indptr.shape[0] - 1
    if n >= 2**31 - 1:
        raise ValueError(f"the OFC kernel numbers blocks in int32: {n} blocks are too many")
    deg = np.diff(indptr)
    dmax = int(deg.max(initial=0))
    if dmax == 0 or dmax > 2 * indices.shape[0] / max(n, 1) + 8:
        return indices.astype(np.int32), np.asarray(kval, dtype=np.float64), 0
    nbr = np.full((n, dmax), -1, dtype=np.int32)
    kpad = np.zeros((n, dmax), dtype=np.float64)
    for c in range(dmax):
        has = deg > c
        nbr[has, c] = indices[indptr[:-1][has] + c]
        kpad[has, c] = kval[indptr[:-1][has] + c]
    return nbr.ravel(), kpad.ravel(), dmax


def ofc_tree(n, shift):
    """The (empty) ``tv``, ``ti`` of :data:`OFCState` for ``n`` blocks in chunks of
    ``2**shift``."""
    size = tree_size(max(1, -(-n >> shift)))
    return np.full(size, np.inf), np.full(size, -1, dtype=np.int64)


def ofc_work(n, n_faults, shift, cnt_size):
    """The :data:`OFCWork` of an automaton of ``n`` blocks on ``n_faults`` faults (zeros)."""
    room = n + 64
    chunks = max(1, -(-n >> shift))
    return OFCWork(
        cur=np.zeros(room, dtype=np.int64),
        nxt=np.zeros(room, dtype=np.int64),
        amount=np.zeros(room, dtype=np.float64),
        mark=np.zeros(n, dtype=np.int64),
        seen=np.zeros(n, dtype=np.int64),
        fseen=np.zeros(max(n_faults, 1), dtype=np.int64),
        cmark=np.zeros(chunks, dtype=np.int64),
        clist=np.zeros(chunks, dtype=np.int64),
        cnt=np.zeros(cnt_size, dtype=np.int64),
    )


def padded_neighbours(indptr, indices):
    """The neighbour table ``nbr`` of :data:`Graph`, from the CSR arrays (int64).

    Row i lists block i's neighbours in CSR order, then the ghost row of ``W`` (index 2 N, all
    zeros) up to the largest degree, so that a force sum runs the same number of times for
    every block.  Its loop exit is then predicted: on the percolation clusters, whose degrees
    vary from block to block, a mispredicted exit at every force evaluation cost 12-15% of the
    events/s.  The sums keep the CSR order and add exact zeros: forces are bit-identical.
    The entries are unsigned (see :data:`Graph`).

    A graph whose largest degree exceeds twice its mean degree plus 8 (a graph with hubs) gets
    an empty table (width 0) rather than one as wide as its largest hub for every block; its
    force sums read the CSR arrays.

    >>> nbr = padded_neighbours(np.array([0, 1, 3, 4]), np.array([1, 0, 2, 1]))
    >>> nbr.tolist()
    [[1, 6], [0, 2], [1, 6]]
    """
    n = indptr.shape[0] - 1
    deg = np.diff(indptr)
    dmax = int(deg.max(initial=0))
    width = dmax if dmax <= 2 * indices.shape[0] / max(n, 1) + 8 else 0
    nbr = np.full((n, width), 2 * n, dtype=np.uint64)
    if width and deg.min() == width:  # every block has the same degree (a lattice, a ring)
        nbr[:] = indices.reshape(n, width)
        return nbr
    for c in range(width):
        has = deg > c
        nbr[has, c] = indices[indptr[:-1][has] + c]
    return nbr


def graph_bundle(
    indptr, indices, kval, diag, oms, cfr, nbr=None, fault=None, frame=None, nu=0.0, eta=None
):
    """The :data:`Graph` of CSR arrays and per-block parameters (float64 ``kval``, ``diag``, ...).

    ``nbr``: the graph's :func:`padded_neighbours`, built here if not given (it depends on the
    topology only, so a simulation builds it once for every set of parameters).
    ``fault``: each block's fault number (None: every block on fault 0).
    ``frame``: the frame springs' stiffness per block, ``k wall`` (None: no frame springs).
    ``nu``: the plate's velocity during events; ``eta``: the viscous coupling of each CSR
    entry (None: none).
    ``k_uniform`` is the springs' constant where all are equal and positive and the neighbour
    table holds every neighbour, else 0.0.
    """
    indptr = np.asarray(indptr, dtype=np.int64)
    indices = np.asarray(indices, dtype=np.int64)
    kval = np.asarray(kval, dtype=np.float64)
    eta = np.zeros(kval.shape) if eta is None else np.asarray(eta, dtype=np.float64)
    if nbr is None:
        nbr = padded_neighbours(indptr, indices)
    hubs = nbr.shape[1] < int(np.diff(indptr).max(initial=0))
    uniform = not hubs and kval.size > 0 and kval[0] > 0.0 and bool(np.all(kval == kval[0]))
    viscous = bool(np.any(eta > 0.0))
    n = indptr.shape[0] - 1
    block = np.empty((n, BLOCK_SIZE), dtype=np.float64)
    block[:, DIAG] = diag
    block[:, OMS] = oms
    block[:, CFR] = cfr
    block[:, FRAME] = 0.0 if frame is None else frame
    block[:, ETA_SUM] = np.bincount(
        np.repeat(np.arange(n), np.diff(indptr)), weights=eta, minlength=n
    )
    return (KelvinGraph if nu > 0.0 or viscous else Graph)(
        indptr=indptr,
        indices=indices,
        kval=kval,
        block=block,
        k_uniform=float(kval[0]) if uniform else 0.0,
        nbr=nbr,
        fault=np.zeros(n, np.int64) if fault is None else fault,
        nu=float(nu),
        eta=eta,
        viscous=viscous,
        eta_uniform=float(eta[0]) if uniform and viscous and bool(np.all(eta == eta[0])) else 0.0,
    )


def work_array(n, columns):
    """The float work array ``W`` of :data:`Work` for n blocks: 2 n + 2 rows of zeros."""
    return np.zeros((2 * n + 2, columns), dtype=np.float64)


def tree_size(n):
    """Length of the failure tree (``State.tree``) for ``n`` leaves (a power of two, doubled)."""
    leaves = 1
    while leaves < n:
        leaves *= 2
    return 2 * leaves


def empty_tree(n):
    """Allocate the failure tree of ``n`` blocks."""
    return np.full(tree_size(n), -1, dtype=np.int64)
