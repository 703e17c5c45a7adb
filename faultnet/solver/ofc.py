"""The OFC automaton's runs: :class:`OFCSimulator` owns one, :func:`simulate_ofc` runs one chunk.

The automaton (:class:`~faultnet.OFC`) is run by one entry kernel
(:func:`faultnet.solver._kernels.ofc.run_ofc`): the drive jumps to the next toppling through a
tournament tree over the blocks' keys (O(log N)), and an avalanche touches only the blocks it
topples and their neighbours.  A simulator allocates the kernel's arrays once; each
:meth:`OFCSimulator.advance` allocates that chunk's catalog only, and continuing from
``sim.state`` in a new simulator gives the same avalanches bit for bit.

The state is a :class:`~faultnet.State` whose ``z`` holds the keys: the force on block
``i`` is ``F_i = 1 + w - z_i`` (:meth:`faultnet.OFC.forces`) and ``offset + w`` is the total
drive, the ``t`` of the catalog.
"""

from __future__ import annotations

import math
import os
import time

import numpy as np
import pandas as pd
from tqdm.auto import tqdm

from faultnet._validate import check_int, check_memory, generator_and_seed
from faultnet._version import __version__
from faultnet.exceptions import EventTooLongError, InvalidParameterError
from faultnet.model.ofc import OFC
from faultnet.model.state import State
from faultnet.solver._kernels.bundles import (
    OFCGraph,
    OFCRecords,
    OFCState,
    ofc_neighbours,
    ofc_tree,
    ofc_work,
)
from faultnet.solver._kernels.layout import (
    OFC_CAT_BLOCKS,
    OFC_CAT_F_SIZE,
    OFC_CAT_FAULTS,
    OFC_CAT_GENERATIONS,
    OFC_CAT_HYPOCENTER,
    OFC_CAT_I_SIZE,
    OFC_CAT_S,
    OFC_CAT_T,
    OFC_CAT_TOPPLINGS,
    OFC_CHUNK_SHIFT,
    OFC_CNT_EVENTS,
    OFC_CNT_GENERATIONS,
    OFC_CNT_SIZE,
    OFC_CNT_TOPPLINGS,
    OFC_CTRL_MAX_TOPPLINGS,
    OFC_CTRL_REBUILD,
    OFC_CTRL_SIZE,
    SCAL_OFFSET,
    SCAL_SIZE,
    SCAL_W,
)
from faultnet.solver.arrays import catalog_state
from faultnet.solver.result import SimulationResult, label_array, node_labels
from faultnet.solver.simulator import next_call_size

__all__ = ["OFC_COLUMNS", "OFCSimulator", "ofc_events_frame", "ofc_metadata", "simulate_ofc"]

#: the columns of an OFC catalog (a network of faults adds ``fault`` and ``n_faults``)
OFC_COLUMNS = ["event", "t", "n_topplings", "n_blocks", "S", "M", "hypocenter", "n_generations"]
#: the progress bar's label while the first run compiles the kernel
COMPILING_LABEL = "faultnet: compiling the OFC kernel (first run only, a few s)"
#: memory of one avalanche in a chunk: the kernel's catalog rows and the frame made of them
_BYTES_PER_EVENT = 8 * (OFC_CAT_F_SIZE + OFC_CAT_I_SIZE) * 2
#: ``max_topplings=None``: no limit (an avalanche always ends: each toppling dissipates at
#: least ``1 / K_max`` of force through the plate spring)
_NO_LIMIT = float(2**62)


def _kernels():
    """The Numba kernels, imported on the first run."""
    from faultnet.solver import _kernels

    return _kernels


def _forces_state(model, forces, name):
    """The state of initial ``forces`` (one per block, in [0, 1)) at drive 0."""
    try:
        arr = np.asarray(forces)
    except (TypeError, ValueError) as exc:
        raise InvalidParameterError(f"{name} must hold one real force per block; {exc}") from None
    if arr.dtype.kind not in "iuf" or arr.shape != (model.n,):
        raise InvalidParameterError(
            f"{name} must hold the initial forces, real numbers in [0, 1), one per block: "
            f"shape ({model.n},); got shape {arr.shape} of {arr.dtype}"
        )
    arr = arr.astype(np.float64)
    bad = np.flatnonzero(~(np.isfinite(arr) & (arr >= 0.0) & (arr < 1.0)))
    if bad.size:
        raise InvalidParameterError(
            f"{name} must hold forces in [0, 1) (the threshold is 1); got {arr[bad[:5]].tolist()} "
            f"at positions {bad[:5].tolist()}"
        )
    return State(z=1.0 - arr, offset=0.0, w=0.0, n_events=0)


def _check_state(model, state):
    z = np.asarray(state.z, dtype=np.float64)
    if z.shape != (model.n,):
        raise InvalidParameterError(f"x0 state has {z.size} blocks but the model has {model.n}")
    w, off = float(state.w), float(state.offset)
    if not (np.all(np.isfinite(z)) and math.isfinite(w)):
        raise InvalidParameterError("x0 state holds non-finite keys or drive; give finite values")
    if not (off == math.floor(off) and abs(off) <= 2.0**52):
        raise InvalidParameterError(
            f"x0.offset must be a whole number with |offset| <= 2**52; got {state.offset!r}"
        )
    over = np.flatnonzero(z <= w)
    if over.size:
        raise InvalidParameterError(
            f"x0 state has blocks at or over the threshold (force 1 + w - z >= 1) at positions "
            f"{over[:5].tolist()}: an OFC state between avalanches has every force below 1"
        )
    return State(z.copy(), off, w, int(state.n_events))


def initial_state(model, x0, rng):
    """``(State, SeedSequence or None, description)`` of an automaton's start (see
    :class:`OFCSimulator`)."""
    if isinstance(x0, SimulationResult):
        if not isinstance(x0.model, OFC):
            raise InvalidParameterError(
                f"x0: a result of a {type(x0.model).__name__} cannot start an OFC automaton; "
                "give an OFC result, its state, or the initial forces"
            )
        x0 = x0.state
    if isinstance(x0, State):
        return _check_state(model, x0), None, "given"
    if x0 is None:
        gen, seq = generator_and_seed(rng)
        return _forces_state(model, gen.random(model.n), "x0"), seq, "random U[0, 1)"
    if isinstance(x0, (str, os.PathLike)) or (hasattr(x0, "path") and hasattr(x0, "events")):
        return _check_state(model, catalog_state(model, x0)), None, "given"
    return _forces_state(model, x0, "x0"), None, "given"


def ofc_events_frame(ev0, cat_f, cat_i, model, labels=None) -> pd.DataFrame:
    """One row per avalanche (:data:`OFC_COLUMNS`), and ``fault`` (the hypocentre's) and
    ``n_faults`` on a network of faults; ``labels``: the model's nodes and faults as their
    :func:`~faultnet.solver.result.label_array` (by default made here)."""
    nodes, faults = labels or (model.nodes, model.faults)
    S = cat_f[:, OFC_CAT_S]
    with np.errstate(divide="ignore"):
        M = np.log(S)
    hyp = cat_i[:, OFC_CAT_HYPOCENTER]
    columns = {
        "event": np.arange(ev0, ev0 + len(S), dtype=np.int64),
        "t": cat_f[:, OFC_CAT_T],
        "n_topplings": cat_i[:, OFC_CAT_TOPPLINGS],
        "n_blocks": cat_i[:, OFC_CAT_BLOCKS],
        "S": S,
        "M": M,
        "hypocenter": node_labels(nodes, hyp),
        "n_generations": cat_i[:, OFC_CAT_GENERATIONS],
    }
    if faults is not None:
        columns["fault"] = node_labels(faults, model.fault_number[hyp])
        columns["n_faults"] = cat_i[:, OFC_CAT_FAULTS]
    return pd.DataFrame(columns)


def ofc_metadata(model, seq, max_topplings=None) -> dict:
    """What defines an automaton's run: the model's parameters, the options, the seed (a
    SeedSequence or None) and the version."""
    md = dict(model.params)
    md.update(
        options={"max_topplings": max_topplings},
        faultnet_version=__version__,
        seed_entropy=None if seq is None else seq.entropy,
        seed_spawn_key=None if seq is None else tuple(seq.spawn_key),
    )
    return md


class OFCSimulator:
    """A running OFC automaton (the counterpart of :class:`faultnet.Simulator`).

    Parameters
    ----------
    model : OFC
    x0 : array_like, State, SimulationResult, Catalog, path or None
        Initial forces (one per block, in [0, 1), drive 0), or a ``State``, previous OFC
        result or OFC catalog (read, or its path) to continue from exactly (the drive and the
        event numbering carry over; a catalog of another model or graph is refused).
        None draws the forces uniformly from [0, 1) with ``rng``, as OFC did (a near-uniform
        start synchronises the lattice and lengthens the transient).
    rng : None, int, SeedSequence or Generator
        Randomness of the initial forces (SPEC 7); its SeedSequence is recorded in every
        chunk's metadata.
    max_topplings : int or None
        Stop with :class:`~faultnet.EventTooLongError` when one avalanche takes more
        topplings (None: no limit; an avalanche always ends).  Recorded in the metadata.

    Examples
    --------
    >>> import faultnet
    >>> from faultnet.solver.ofc import OFCSimulator
    >>> lattice = faultnet.graphs.square_lattice(16, 16, boundary="fixed")
    >>> model = faultnet.OFC.from_alpha(lattice, 0.2)
    >>> sim = OFCSimulator(model, rng=3)
    >>> first = sim.advance(300, progress=False)
    >>> second = sim.advance(200, progress=False)
    >>> whole = faultnet.simulate(model, 500, rng=3, progress=False)
    >>> bool((whole.events["S"].to_numpy()[300:] == second.events["S"].to_numpy()).all())
    True
    """

    def __init__(self, model, x0=None, rng=None, *, max_topplings=None):
        if not isinstance(model, OFC):
            raise InvalidParameterError(f"model must be an OFC; got {type(model).__name__}")
        if max_topplings is not None:
            max_topplings = check_int("max_topplings", max_topplings)
        self._max_topplings = max_topplings
        state, self._seed, self._initial = initial_state(model, x0, rng)
        self._model = model
        n = model.n
        adj = model.adjacency
        kval = adj.data.astype(np.float64)
        uniform = kval.size > 0 and bool(np.all(kval == kval[0]))
        indptr = adj.indptr.astype(np.int64)
        nbr, kflat, width = ofc_neighbours(indptr, adj.indices, kval)
        self._graph = OFCGraph(
            indptr=indptr,
            nbr=nbr,
            kval=kflat,
            width=np.int64(width),
            stiff=model.stiffness.astype(np.float64),
            k_uniform=float(kval[0]) if uniform else 0.0,
            fault=(
                np.zeros(n, np.int64)
                if model.fault_number is None
                else model.fault_number.astype(np.int64)
            ),
        )
        self._scal = np.zeros(SCAL_SIZE, dtype=np.float64)
        self._scal[SCAL_OFFSET], self._scal[SCAL_W] = state.offset, state.w
        tv, ti = ofc_tree(n, OFC_CHUNK_SHIFT)
        self._kstate = OFCState(np.array(state.z, dtype=np.float64), self._scal, tv, ti)
        self._n_events = state.n_events
        self._work = ofc_work(n, len(model.faults or ()), OFC_CHUNK_SHIFT, OFC_CNT_SIZE)
        self._ctrl = np.zeros(OFC_CTRL_SIZE, dtype=np.float64)
        self._ctrl[OFC_CTRL_MAX_TOPPLINGS] = _NO_LIMIT if max_topplings is None else max_topplings
        self._ctrl[OFC_CTRL_REBUILD] = 1.0
        self._labels = label_array(model.nodes), label_array(model.faults)  # for every chunk

    @property
    def model(self) -> OFC:
        """The automaton being run."""
        return self._model

    @property
    def seed(self):
        """The SeedSequence that drew the initial forces (None if ``x0`` was given)."""
        return self._seed

    @property
    def state(self) -> State:
        """The exact state between avalanches (a copy): pass it as ``x0`` to continue."""
        return State(
            self._kstate.keys.copy(),
            float(self._scal[SCAL_OFFSET]),
            float(self._scal[SCAL_W]),
            self._n_events,
        )

    @property
    def compiles(self) -> bool:
        """True if the next :meth:`advance` compiles the kernel (no disk cache for it yet, and
        not yet used in this process)."""
        kernel = _kernels().run_ofc
        return not getattr(kernel, "signatures", True) and _kernels().is_cold(kernel)

    def metadata(self) -> dict:
        """What defines the run: the model's parameters, the options, the seed and the version."""
        return ofc_metadata(self._model, self._seed, self._max_topplings)

    def advance(self, n_events, *, progress=None) -> SimulationResult:
        """Run the next ``n_events`` avalanches and return their catalog.

        ``result.metadata`` holds :meth:`metadata`, ``first_event``, ``n_events``,
        ``initial_state``, ``wall_time_s`` (the kernel's time, without its compilation) and
        the work done, ``n_topplings`` and ``n_generations``; ``result.dt`` is 0.0 (an
        automaton has no time step) and ``result.state`` equals :attr:`state`.
        """
        n_events = check_int("n_events", n_events)
        check_memory(
            f"n_events={n_events:,} in memory",
            n_events * _BYTES_PER_EVENT,
            "advance the simulator a part at a time",
        )
        ev0 = self._n_events
        cat_f = np.zeros((n_events, OFC_CAT_F_SIZE), dtype=np.float64)
        cat_i = np.zeros((n_events, OFC_CAT_I_SIZE), dtype=np.int64)
        cnt = self._work.cnt
        cnt[OFC_CNT_TOPPLINGS] = cnt[OFC_CNT_GENERATIONS] = 0
        wall = self._loop(n_events, cat_f, cat_i, progress)
        self._n_events = ev0 + n_events
        md = self.metadata()
        md.update(
            first_event=ev0,
            n_events=n_events,
            initial_state=self._initial,
            wall_time_s=wall,
            n_topplings=int(cnt[OFC_CNT_TOPPLINGS]),
            n_generations=int(cnt[OFC_CNT_GENERATIONS]),
        )
        events = ofc_events_frame(ev0, cat_f, cat_i, self._model, self._labels)
        return SimulationResult(events, self.state, self._model, 0.0, md)

    def _loop(self, n_events, cat_f, cat_i, progress):
        """Call the entry kernel in chunks sized to ~0.1-0.5 s; return the wall time (without
        the first call in this process, which compiles the kernel or loads it: one avalanche)."""
        K = _kernels()
        kernel = K.run_ofc
        loading = not getattr(kernel, "signatures", True)
        compiling = loading and K.is_cold(kernel)
        chunk = 1 if loading else 256
        cnt = self._work.cnt
        done = 0
        t0 = time.perf_counter()
        with tqdm(
            total=n_events,
            unit="av",
            disable=(None if progress is None else not progress),
            leave=False,
            desc=COMPILING_LABEL if compiling else "faultnet",
        ) as bar:
            while done < n_events:
                n_req = min(chunk, n_events - done)
                records = OFCRecords(cat_f[done:], cat_i[done:])
                cnt[OFC_CNT_EVENTS] = 0
                tic = time.perf_counter()
                status = kernel(n_req, self._kstate, self._graph, self._ctrl, self._work, records)
                got = int(cnt[OFC_CNT_EVENTS])
                done += got
                if status != K.OFC_STATUS_OK:
                    self._raise(cat_i[done], self._n_events + done)
                if compiling:
                    bar.set_description_str("faultnet")
                    compiling = False
                bar.update(got)
                if loading:
                    loading, chunk, t0 = False, 256, time.perf_counter()
                else:
                    chunk = next_call_size(chunk, time.perf_counter() - tic)
        return time.perf_counter() - t0

    def _raise(self, row, event):
        hyp = self._model.nodes[int(row[OFC_CAT_HYPOCENTER])]
        raise EventTooLongError(
            f"avalanche {event} (hypocentre {hyp!r}) took more than max_topplings="
            f"{self._max_topplings:,} topplings; raise max_topplings (or leave it None). The "
            "simulator stopped mid-avalanche: start a new one from the last result's state"
        )


def simulate_ofc(model, n_events, *, x0=None, rng=None, progress=None, max_topplings=None):
    """Run ``n_events`` avalanches of an OFC automaton: one :class:`OFCSimulator` chunk
    (:func:`faultnet.simulate` calls it for an :class:`~faultnet.OFC` model)."""
    n_events = check_int("n_events", n_events)
    sim = OFCSimulator(model, x0, rng, max_topplings=max_topplings)
    return sim.advance(n_events, progress=progress)
