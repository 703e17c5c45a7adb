"""The arrays a run hands to the entry kernel, allocated once per :class:`~faultnet.Simulator`.

:class:`KernelArrays` holds the topology (CSR), the per-block parameters, the
state (``z``, ``scal``, failure keys and their tree), the work space and the
recording buffers, and calls the entry kernel of the run's scheme with them in the
bundles of :mod:`faultnet.solver._kernels.bundles`.  The small packed arrays (``ctrl``, ``scal``,
``cnt``, ``out``) and the catalog and trace columns are read and written through the names
of :mod:`faultnet.solver._kernels.layout`.
"""

from __future__ import annotations

import contextlib
import gc
import os

import numpy as np

from faultnet._validate import generator_and_seed
from faultnet.exceptions import InvalidParameterError
from faultnet.model.state import State
from faultnet.solver._kernels.bundles import (
    Records,
    Work,
    graph_bundle,
    padded_neighbours,
    work_array,
)
from faultnet.solver._kernels.bundles import State as KernelState
from faultnet.solver._kernels.layout import (
    CNT_EVENTS,
    CNT_SIZE,
    CNT_SLIP_ROWS,
    CNT_TRACE_FULL,
    CNT_TRACE_ROWS,
    CTRL_DT,
    CTRL_MAX_DURATION,
    CTRL_MAX_VELOCITY,
    CTRL_REBUILD,
    CTRL_SIZE,
    CTRL_SOLO_CACHE,
    OUT_SIZE,
    SCAL_OFFSET,
    SCAL_SIZE,
    SCAL_W,
    TRACE_X,
)
from faultnet.solver.interrupts import stoppable
from faultnet.solver.result import SimulationResult
from faultnet.solver.solo_cache import solo_table

__all__ = [
    "MAX_OFFSET",
    "SLIP_RESOLUTION",
    "X0_AMPLITUDE",
    "KernelArrays",
    "catalog_state",
    "initial_state",
    "position_limit",
    "trace_indices",
]

#: initial displacements are drawn uniformly from [0, X0_AMPLITUDE)
X0_AMPLITUDE = 0.01
#: float64 spacing of a position may be at most this fraction of the smallest slip scale
SLIP_RESOLUTION = 1e-6
#: the frame offset is a whole number moved in whole units: exact below 2**52
MAX_OFFSET = float(2**52)


def position_limit(model) -> float:
    """Largest ``|x - offset|`` (positions relative to the frame) that float64 resolves.

    The slips of a model range from about ``sigma_i / (1 + sum_j k_ij)`` (a
    block slipping alone) to O(1).  A position ``x`` is stored with spacing
    ``ulp(x) ~ |x| * eps`` (``eps = 2.2e-16``); requiring that spacing to be at
    most :data:`SLIP_RESOLUTION` (1e-6) of the smallest slip scale ``s`` gives
    ``|x| <= 1e-6 * s / eps``: 1.4e6 for a ring with k=16 and sigma=0.01.
    Beyond it the slips lose digits (at 1e16 one-block slips come out 6000
    times too small; from about 1e20 the positions no longer change).  Long
    runs are unaffected: positions are kept relative to an integer frame
    offset that follows the plate (:class:`~faultnet.State`).

    >>> import faultnet
    >>> f"{position_limit(faultnet.CarlsonLanger(faultnet.graphs.ring(10))):.3g}"
    '1.36e+06'
    """
    scale = float(np.min(model.sigma_values / model.stiffness))
    return SLIP_RESOLUTION * scale / np.finfo(np.float64).eps


def _real_array(name, value):
    """``value`` as a float64 array, refusing strings, complex numbers, bools and objects."""
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise InvalidParameterError(
            f"{name} must hold real numbers, one per block; {exc}"
        ) from None
    if arr.dtype.kind not in "iuf":
        kind = {"U": "str", "S": "bytes", "c": "complex", "b": "bool", "O": "object"}.get(
            arr.dtype.kind, str(arr.dtype)
        )
        raise InvalidParameterError(
            f"{name} must hold real numbers (int or float), one per block; got an array of {kind}"
        )
    return arr.astype(np.float64)


def _check_frame(model, state, name, z_name):
    """Finite, float64-resolvable state: |z|, |w| within :func:`position_limit`, offset whole."""
    limit = position_limit(model)
    z = np.asarray(state.z, dtype=np.float64)
    for part, vals in ((z_name, z), (f"{name}.w", [state.w])):
        vals = np.asarray(vals, dtype=np.float64)
        bad = np.flatnonzero(~np.isfinite(vals))
        if bad.size:
            raise InvalidParameterError(
                f"{part} has non-finite entries at positions {bad[:5].tolist()}: "
                f"{vals[bad[:5]].tolist()}; give finite displacements"
            )
        big = float(np.max(np.abs(vals))) if vals.size else 0.0
        if big > limit:
            raise InvalidParameterError(
                f"{part} holds |x| = {big:.3g} (relative to the plate frame): beyond "
                f"{limit:.3g}, float64 cannot resolve this model's slips (smallest slip "
                f"scale sigma/(1+sum k) = {limit * np.finfo(np.float64).eps / SLIP_RESOLUTION:.3g}"
                f"); give positions within {limit:.3g} of the plate"
            )
    off = state.offset
    if not (np.isfinite(off) and float(off) == np.floor(off) and abs(off) <= MAX_OFFSET):
        raise InvalidParameterError(
            f"{name}.offset must be a whole number with |offset| <= 2**52 = {MAX_OFFSET:.4g} "
            f"(the plate frame moves in whole units); got {off!r}"
        )


@contextlib.contextmanager
def collector_paused():
    """Python's cyclic garbage collector paused for one kernel call.

    A running kernel creates no Python objects, so the pause costs nothing then.  The first
    call of a kernel in a process compiles it, and Numba's compiler creates and drops
    millions of objects: the collector's 1,800 passes over them took 1.5-1.8 s of a
    17-19 s cold compile (and the garbage left, about 125 MB, is collected afterwards in
    about 0.6 s).  The collector is left as it was found: a caller that disabled it keeps
    it disabled.
    """
    if not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


def _kernels():
    from faultnet.solver import _kernels

    return _kernels


def catalog_state(model, x0):
    """The final state of a catalog (a path or a read catalog) run on ``model``'s graph."""
    from faultnet.io.catalog_file import read_metadata, read_state
    from faultnet.model.identity import graph_hash

    path = os.fspath(x0 if isinstance(x0, (str, os.PathLike)) else x0.path)
    state, stored = read_state(path), read_metadata(path).get("graph_hash")
    if stored is not None and stored != graph_hash(model):
        raise InvalidParameterError(
            f"x0: catalog {path} was run on another graph or other parameters (graph hash "
            f"{stored[:12]}..., this model's {graph_hash(model)[:12]}...); continue it with "
            "the model it was run on"
        )
    return state


def initial_state(model, x0, rng):
    """``(State, SeedSequence or None)`` from ``x0`` (array, State, result, catalog or its
    path) or from ``rng``."""
    if isinstance(x0, SimulationResult):
        x0 = x0.state
    elif isinstance(x0, (str, os.PathLike)) or (hasattr(x0, "path") and hasattr(x0, "events")):
        x0 = catalog_state(model, x0)
    if isinstance(x0, State):
        z = _real_array("x0.z", x0.z)
        if z.shape != (model.n,):
            raise InvalidParameterError(f"x0 state has {z.size} blocks but the model has {model.n}")
        _check_frame(model, x0, "x0", "x0.z")
        return x0.copy(), None
    if x0 is None:
        gen, seq = generator_and_seed(rng)
        return State.from_x(gen.uniform(0.0, X0_AMPLITUDE, model.n)), seq
    x = _real_array("x0", x0)
    if x.shape != (model.n,):
        raise InvalidParameterError(
            f"x0 must have one entry per block: expected shape ({model.n},), got {x.shape}"
        )
    bad = np.flatnonzero(~np.isfinite(x))
    if bad.size:
        raise InvalidParameterError(
            f"x0 has non-finite entries at positions {bad[:5].tolist()}: {x[bad[:5]].tolist()}"
        )
    state = State.from_x(x)
    _check_frame(model, state, "x0", "x0")
    return state, None


def trace_indices(model, trace_nodes):
    """Block indices of ``trace_nodes`` (graph node labels, or one label alone), checked."""
    if trace_nodes is None:
        return np.zeros(0, dtype=np.int64)
    index = {node: i for i, node in enumerate(model.nodes)}
    try:
        one = trace_nodes in index  # a single label, also a lattice's (i, j)
    except TypeError:  # unhashable: a list or an array of labels
        one = False
    if one:
        trace_nodes = [trace_nodes]
    elif isinstance(trace_nodes, (str, bytes)) or not hasattr(trace_nodes, "__iter__"):
        raise InvalidParameterError(
            f"trace_nodes must be node labels of the graph (one, or a list); got {trace_nodes!r}"
        )
    missing = [n for n in trace_nodes if n not in index]
    if missing:
        raise InvalidParameterError(f"trace_nodes not in the graph: {missing[:5]}")
    return np.array([index[n] for n in trace_nodes], dtype=np.int64)


class KernelArrays:
    """Topology, parameters, state, work space and buffers of one running simulation."""

    def __init__(self, model, state, options, dt, record_slips, trace_idx, max_trace_rows,
                 solo_cache=True):  # fmt: skip
        n = model.n
        K = _kernels()
        adj = model.adjacency
        self.indptr = adj.indptr.astype(np.int64)
        self.indices = adj.indices.astype(np.int64)
        self.nbr = padded_neighbours(self.indptr, self.indices)  # topology: once per simulation
        self.z = np.array(state.z, dtype=np.float64)
        self.scal = np.zeros(SCAL_SIZE, dtype=np.float64)
        self.scal[SCAL_OFFSET], self.scal[SCAL_W] = state.offset, state.w
        self.n_events = state.n_events
        self.keys = np.empty(n, dtype=np.float64)
        self.tree = K.empty_tree(n)
        self.options = options
        # block-major work space: one block's rows share cache lines
        # rows N to 2 N - 1 hold the DP5 stage derivatives by active position (tableau.stage_rows)
        # and row 2 N is the ghost the padded neighbour table points to (bundles.work_array)
        self.W = work_array(n, K.N_WORK)
        self.IW = np.zeros((K.N_IWORK, n), dtype=np.int64)
        self.ctrl = np.zeros(CTRL_SIZE, dtype=np.float64)
        self.ctrl[CTRL_MAX_DURATION] = options.max_event_duration
        self.ctrl[CTRL_MAX_VELOCITY] = options.max_velocity
        self.ctrl[CTRL_SOLO_CACHE] = float(solo_cache)
        self.cnt = np.zeros(CNT_SIZE, dtype=np.int64)
        # the crossings a step lists (carlson_langer.work)
        self.loc = np.zeros(K.LOC_SIZE, dtype=np.float64)
        self.out = np.zeros(OUT_SIZE, dtype=np.float64)
        self.kstate = KernelState(self.z, self.scal, self.keys, self.tree)
        self.work = Work(self.W, self.IW, self.loc, self.cnt)
        self.record_slips = bool(record_slips)
        self.slip_cap = max(4 * n, 1 << 16)
        self._slip_buffers(0)
        self.trace_idx = trace_idx
        rows = max_trace_rows if trace_idx.size else 0
        self.trace = np.zeros((rows, TRACE_X + 2 * trace_idx.size), dtype=np.float64)
        self.profiles = np.zeros((0, 0), dtype=np.float64)
        self.set_parameters(model, dt)

    def _slip_buffers(self, cap):
        self.slip_e = np.zeros(cap, dtype=np.int64)
        self.slip_n = np.zeros(cap, dtype=np.int64)
        self.slip_v = np.zeros(cap, dtype=np.float64)

    def set_parameters(self, model, dt):
        """Per-block parameters of ``model``, a fresh solo cache and keys consistent with z.

        ``dt`` (from :meth:`RunOptions.step`), the crossing treatment and with it the entry
        kernel (:meth:`RunOptions.entry`) may follow the model.
        """
        oms = 1.0 - model.sigma_values
        self.graph = graph_bundle(
            self.indptr,
            self.indices,
            model.adjacency.data.astype(np.float64),
            model.stiffness.astype(np.float64),
            oms,
            2.0 * model.alpha_values / oms,
            self.nbr,
            model.fault_number,
            model.frame,
            nu=model.nu,
            eta=model.eta_values,
        )
        self.ctrl[CTRL_DT] = dt
        if model.nu > 0.0:  # any stuck block can fail while the plate moves: no slip is lone
            self.ctrl[CTRL_SOLO_CACHE] = 0.0
        self.kernel = getattr(_kernels(), self.options.entry(model))
        # a network of faults sums each event's slips per fault from the per-block rows
        self.fault_number = model.fault_number
        # blocks of one class (stiffness, sigma, alpha and the dashpots' total) share a solo slip
        self.cls = model.block_classes
        self.solo = solo_table(model, self.cls)
        self.ctrl[CTRL_REBUILD] = 1.0  # the entry builds the keys and tree before any event

    def state(self) -> State:
        """A copy of the state between events."""
        return State(
            self.z.copy(), float(self.scal[SCAL_OFFSET]), float(self.scal[SCAL_W]), self.n_events
        )

    @property
    def recording(self) -> bool:
        """Whether the kernel writes per-block slip rows: kept (``record_slips``), or summed
        per fault on a network of faults."""
        return self.record_slips or self.fault_number is not None

    def start_chunk(self, profile_rows):
        """Empty the recording buffers for the next :meth:`Simulator.advance`."""
        self.slip_parts, self.slip_rows, self.slips_truncated = [], 0, False
        self.fault_parts = []
        cap = self.slip_cap if self.recording else 0
        if self.slip_v.size != cap:
            self._slip_buffers(cap)
        self.cnt[CNT_SLIP_ROWS] = 0
        self.cnt[CNT_TRACE_ROWS] = self.cnt[CNT_TRACE_FULL] = 0
        n = self.z.shape[0] if profile_rows else 0
        self.profiles = np.zeros((profile_rows, n), dtype=np.float64)

    def call(self, n_req, ev0, cat_f, cat_i, done):
        """One call of the entry kernel: up to ``n_req`` events into the catalog rows.

        SIGINT and SIGTERM stop it at the end of a step (:func:`~.interrupts.stoppable`,
        status ``STATUS_INTERRUPTED``, the event under way undone).  :attr:`n_events` counts
        the events run even where Python's signal handler raises as the kernel returns, so
        that it stays true to the state.
        """
        self.cnt[CNT_EVENTS] = 0
        records = Records(
            cat_f=cat_f,
            cat_i=cat_i,
            slip_event=self.slip_e,
            slip_node=self.slip_n,
            slip_val=self.slip_v,
            trace_nodes=self.trace_idx,
            trace_buf=self.trace,
            profiles=self.profiles[done:] if self.profiles.shape[0] else self.profiles,
            out=self.out,
        )
        args = (n_req, ev0, self.kstate, self.graph, self.ctrl, self.cls, self.solo, self.work)
        with collector_paused(), stoppable(self.ctrl):
            try:
                return self.kernel(*args, records)
            finally:
                self.n_events += int(self.cnt[CNT_EVENTS])

    def take_slips(self, limit):
        """Move the buffered slip rows to ``slip_parts`` (at most ``limit`` rows in all, then
        ``slips_truncated``) and their sums per fault to ``fault_parts``."""
        rows = int(self.cnt[CNT_SLIP_ROWS])
        self.cnt[CNT_SLIP_ROWS] = 0
        if self.fault_number is not None and rows:
            self.fault_parts.append(
                per_fault(
                    self.slip_e[:rows], self.slip_n[:rows], self.slip_v[:rows], self.fault_number
                )  # fmt: skip
            )
        if not self.record_slips:
            return
        m = min(rows, limit - self.slip_rows)
        if m > 0:
            self.slip_parts.append(
                (self.slip_e[:m].copy(), self.slip_n[:m].copy(), self.slip_v[:m].copy())
            )
            self.slip_rows += m
        if rows > m or self.slip_rows >= limit:
            self.slips_truncated = True
            if self.fault_number is None:
                self._slip_buffers(0)  # nothing more to keep: the kernel stops writing rows


def per_fault(event, node, slip, fault_number):
    """Each event's slip summed per fault: ``(event, fault number, slip)``, by event and then
    fault number.  ``event`` is non-decreasing (the kernel writes an event's rows together);
    the sums add the rows in their order, as a loop over the per-block rows would.

    >>> per_fault(np.array([4, 4, 4, 5]), np.array([0, 1, 2, 2]), np.array([1.0, 2.0, 0.5, 3.0]),
    ...           np.array([0, 1, 0]))
    (array([4, 4, 5]), array([0, 1, 0]), array([1.5, 2. , 3. ]))
    """
    n_faults = int(fault_number.max()) + 1
    key = (event - event[0]) * n_faults + fault_number[node]
    keys, inverse = np.unique(key, return_inverse=True)
    sums = np.bincount(inverse, weights=slip, minlength=keys.size)
    return keys // n_faults + event[0], keys % n_faults, sums
