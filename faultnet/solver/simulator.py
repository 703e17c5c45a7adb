"""The engine: one :class:`Simulator` owns a running simulation.

The plate is never time-stepped: between events it jumps analytically to the
next failure (a tournament tree over per-block failure keys).  Inside an event
only the slipping blocks are integrated, with Dormand-Prince 5(4) at a fixed step
``dt``; stick (v -> 0) and join (F -> 1) instants are located on the step's dense
output and either the step is redone up to each (exact crossings: the scheme keeps
its order, see ``tests/solver/test_convergence.py``) or the crossings are applied at the
step's end from what it computed (interpolated crossings, ``faultnet.solver.accuracy``).

A :class:`Simulator` allocates the kernel's arrays once (topology, state, work
space); each :meth:`Simulator.advance` only allocates that chunk's catalog.
Continuing from ``sim.state`` in a new Simulator gives the same events bit for
bit, which is what makes checkpointed runs resumable.
"""

from __future__ import annotations

import copy
import time

import numpy as np
from tqdm.auto import tqdm

from faultnet._validate import check_int, check_memory
from faultnet.exceptions import InvalidParameterError
from faultnet.model.carlson_langer import CarlsonLanger
from faultnet.solver._kernels.layout import (
    CAT_F_SIZE,
    CAT_I_SIZE,
    CNT_BLOCK_STEPS,
    CNT_EVENTS,
    CNT_STEPS,
    SCAL_OFFSET,
    SCAL_W,
)
from faultnet.solver.arrays import KernelArrays, initial_state, trace_indices
from faultnet.solver.options import RunOptions
from faultnet.solver.result import SimulationResult, events_frame, label_array
from faultnet.solver.wrap import raise_status, run_metadata, wrap_result

__all__ = ["COMPILING_LABEL", "Simulator", "next_call_size"]

#: the progress bar's label while the first run compiles the kernels
COMPILING_LABEL = "faultnet: compiling the kernels (first run only, 10-20 s)"
#: ``record_profiles`` keeps at most this many values (n_events x n_blocks)
MAX_PROFILE_VALUES = 20_000_000
#: memory of one event in a chunk: the kernels' catalog rows and the events frame made of them
_BYTES_PER_EVENT = 8 * (CAT_F_SIZE + CAT_I_SIZE) * 2


def next_call_size(n, seconds):
    """Events for the next call of an entry kernel after ``n`` took ``seconds``: twice as
    many below 0.1 s (at most 2**20), half as many above 0.5 s (at least 1), so that a call
    takes 0.1-0.5 s (a smooth progress bar, Ctrl-C heard soon)."""
    if seconds < 0.1:
        return min(n * 2, 1 << 20)
    if seconds > 0.5:
        return max(n // 2, 1)
    return n


def _kernels():
    """The Numba kernels, imported on the first run (numba's import takes a quarter second)."""
    from faultnet.solver import _kernels

    return _kernels


class Simulator:
    """A running simulation of a Carlson-Langer model.

    Parameters
    ----------
    model : CarlsonLanger
    x0 : array_like, State, SimulationResult, Catalog, path or None
        Initial displacements (plate at u = 0), or a ``State``, previous
        result or catalog (read, or its path) to continue from exactly (the plate
        position and the event numbering carry over; a catalog of another graph or
        other parameters is refused).  None draws ``x0`` uniformly from [0, 0.01)
        with ``rng``.
    rng : None, int, SeedSequence or Generator
        Randomness for the initial state (SPEC 7); its SeedSequence is
        recorded in every chunk's metadata.
    options : RunOptions, dict or None
        The numerical choices (scheme, step, guards); see :class:`RunOptions`.
    record_slips : bool
        Keep per-block slips of every event (``result.slips``), at most
        ``max_slip_rows`` rows per :meth:`advance`.
    trace_nodes : graph node, or sequence of graph nodes, optional
        Record ``x(t)``, ``v(t)`` of these blocks at every integration step
        inside events, at most ``max_trace_rows`` steps per :meth:`advance`.
    solo_cache : bool
        An event whose hypocentre slips alone depends only on that block's
        stiffness, sigma and alpha: the engine integrates it once per such
        class and reuses it (True, the default).  False integrates every event,
        the reference the tests compare with; the events agree to round-off.
        Recorded in the metadata.

    Examples
    --------
    >>> import faultnet
    >>> ring = faultnet.CarlsonLanger(faultnet.graphs.ring(20), k=16, sigma=0.01, alpha=1.0)
    >>> sim = faultnet.Simulator(ring, rng=3)
    >>> first = sim.advance(100, progress=False)
    >>> second = sim.advance(50, progress=False)
    >>> sim.state.n_events, int(second.events["event"].iloc[0])
    (150, 100)
    >>> whole = faultnet.simulate(ring, 150, rng=3, progress=False)
    >>> bool((whole.events["S"].to_numpy()[100:] == second.events["S"].to_numpy()).all())
    True
    """

    def __init__(
        self,
        model,
        x0=None,
        rng=None,
        options=None,
        *,
        record_slips=False,
        trace_nodes=None,
        max_slip_rows=50_000_000,
        max_trace_rows=1_000_000,
        solo_cache=True,
    ):
        if not isinstance(model, CarlsonLanger):
            raise InvalidParameterError(
                f"model must be a CarlsonLanger; got {type(model).__name__}"
            )
        self._options = RunOptions.coerce(options)
        self._dt = self._options.step(model)
        self._labels = label_array(model.nodes), label_array(model.faults)  # for every chunk
        state, self._seed = initial_state(model, x0, rng)
        self._initial = "random U[0, 0.01)" if x0 is None else "given"
        self._max_slip_rows = check_int("max_slip_rows", max_slip_rows, minimum=0)
        trace_idx = trace_indices(model, trace_nodes)
        rows = check_int("max_trace_rows", max_trace_rows, minimum=0)
        self._model = model
        if not isinstance(solo_cache, bool | np.bool_):
            raise InvalidParameterError(f"solo_cache must be True or False; got {solo_cache!r}")
        self._solo_cache = bool(solo_cache)
        self._arrays = KernelArrays(
            model, state, self._options, self._dt, record_slips, trace_idx, rows, self._solo_cache
        )
        self._checked_cache = False
        self._metadata = self._run_metadata()

    # -- what the simulation is --------------------------------------------------------------

    @property
    def model(self) -> CarlsonLanger:
        """The model being run (see :meth:`set_model`)."""
        return self._model

    @property
    def options(self) -> RunOptions:
        """The run options (fixed for the Simulator's life)."""
        return self._options

    @property
    def dt(self) -> float:
        """The integration step of the current model."""
        return self._dt

    @property
    def seed(self):
        """The SeedSequence that drew the initial state (None if ``x0`` was given)."""
        return self._seed

    @property
    def state(self):
        """The exact state between events (a copy): pass it as ``x0`` to continue."""
        return self._arrays.state()

    def set_model(self, model):
        """Continue with another model on the same blocks (e.g. a new alpha).

        The model must have the same blocks, in the same order, joined by the same springs;
        their constants may differ.  The topology, the state and every work array are kept;
        only the per-block parameters, the solo-slip cache and the failure keys are renewed,
        and the step is re-derived when ``options.dt`` is None.  The
        events that follow equal a fresh run of ``model`` from
        :attr:`state`, bit for bit.

        >>> import faultnet
        >>> ring = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=16, sigma=0.01)
        >>> sim = faultnet.Simulator(ring, rng=0)
        >>> _ = sim.advance(20, progress=False)
        >>> sim.set_model(ring.with_params(alpha=2.0))
        >>> sim.model.alpha
        2.0
        """
        if not isinstance(model, CarlsonLanger):
            raise InvalidParameterError(
                f"model must be a CarlsonLanger; got {type(model).__name__}"
            )
        if model.n != self._model.n or list(model.nodes) != list(self._model.nodes):
            raise InvalidParameterError(
                f"set_model needs a model on the same blocks ({self._model.n} blocks in the "
                f"same node order); got {model.n} blocks. Start a new Simulator from "
                "sim.state for another graph"
            )
        new, old = model.adjacency, self._model.adjacency
        if not (
            np.array_equal(new.indptr, old.indptr) and np.array_equal(new.indices, old.indices)
        ):
            raise InvalidParameterError(
                "set_model needs a model on the same blocks joined by the same springs (their "
                "constants may differ); the new model's graph has other edges. Start a new "
                "Simulator from sim.state for another graph"
            )
        dt = self._options.step(model)
        self._arrays.set_parameters(model, dt)
        self._model, self._dt = model, dt
        self._metadata = self._run_metadata()

    # -- running -----------------------------------------------------------------------------

    def advance(self, n_events, *, progress=None, record_profiles=False) -> SimulationResult:
        """Run the next ``n_events`` events and return their catalog.

        Parameters
        ----------
        n_events : int
            Number of events (> 0).
        progress : bool or None
            Show a progress bar (None: only on a terminal).
        record_profiles : bool
            Keep the displacement profile after every event (small graphs
            only: ``n_events * n_blocks`` is limited to 2e7).

        Returns
        -------
        SimulationResult
            The chunk's events; ``result.state`` equals :attr:`state`.

        Notes
        -----
        Ctrl-C (``KeyboardInterrupt``) stops the call within one integration step, also inside
        a long event, which is undone (in the main thread; SIGTERM too where a handler for it
        raises, as the command line's does): the simulator is left after its last complete event and
        goes on with the events of an uninterrupted run.  The catalog of the interrupted call
        is not returned.
        """
        n_events = check_int("n_events", n_events)
        n = self._model.n
        if record_profiles and n_events * n > MAX_PROFILE_VALUES:
            raise InvalidParameterError(
                f"record_profiles would store {n_events} x {n} values (limit "
                f"{MAX_PROFILE_VALUES:.0e}); run fewer events or record slips instead"
            )
        check_memory(
            f"n_events={n_events:,} in memory",
            n_events * _BYTES_PER_EVENT,
            "write long runs to a file in chunks (simulate_to_parquet, faultnet simulate "
            "--out), or advance a Simulator a part at a time",
        )
        arr = self._arrays
        arr.start_chunk(n_events if record_profiles else 0)
        ev0 = arr.n_events
        cat_f = np.zeros((n_events, CAT_F_SIZE), dtype=np.float64)
        cat_i = np.zeros((n_events, CAT_I_SIZE), dtype=np.int64)
        wall, steps, block_steps = self._loop(n_events, ev0, cat_f, cat_i, progress)
        arr.take_slips(self._max_slip_rows)
        md = copy.deepcopy(self._metadata)
        md.update(
            first_event=ev0,
            n_events=n_events,
            initial_state=self._initial,
            wall_time_s=wall,
            n_steps=steps,
            block_steps=block_steps,
        )
        model = self._model
        nodes, faults = self._labels
        events = events_frame(ev0, cat_f, cat_i, nodes, faults, model.fault_number)
        return wrap_result(
            model, arr, self.state, self._dt, events, md, record_profiles, self._labels
        )

    def _run_metadata(self):
        """The metadata every chunk of the current model starts from (copied per chunk: its
        crossing treatment and parameter summary take 15 ms on a 1024^2 lattice)."""
        return run_metadata(self._model, self._options, self._dt, self._seed, self._solo_cache)

    @property
    def compiles(self) -> bool:
        """True if the next :meth:`advance` compiles the kernel (no disk cache for it yet, and
        not yet used in this process): it then takes :data:`COMPILING_LABEL`'s seconds."""
        kernel = self._arrays.kernel
        return not getattr(kernel, "signatures", True) and _kernels().is_cold(kernel)

    def _loop(self, n_events, ev0, cat_f, cat_i, progress):
        """Call the entry kernel in chunks sized to ~0.1-0.5 s; return wall time and work.

        The wall time leaves out the first call of a kernel in this process, which compiles it
        or loads it from Numba's cache (that call runs a single event).
        """
        arr = self._arrays
        compiling = False
        if not self._checked_cache:  # reads the cache index: outside the timed loop
            compiling = _kernels().is_cold(arr.kernel)
            self._checked_cache = True
        K = _kernels()
        done = steps = block_steps = 0
        # the first call of a kernel in this process compiles it or loads it from the cache:
        # it runs one event, and the wall time returned starts after it
        loading = not getattr(arr.kernel, "signatures", True)
        chunk = 1 if loading else 256
        t0 = time.perf_counter()
        with tqdm(
            total=n_events,
            unit="ev",
            disable=(None if progress is None else not progress),
            leave=False,
            desc=COMPILING_LABEL if compiling else "faultnet",
        ) as bar:
            while done < n_events:
                n_req = min(chunk, n_events - done)
                tic = time.perf_counter()
                status = arr.call(n_req, ev0 + done, cat_f[done:], cat_i[done:], done)
                if compiling:  # the bar's clock and rate count the simulation only
                    bar.unpause()
                    bar.set_description_str("faultnet")
                    compiling = False
                got = int(arr.cnt[CNT_EVENTS])
                done += got
                steps += int(arr.cnt[CNT_STEPS])
                block_steps += int(arr.cnt[CNT_BLOCK_STEPS])
                arr.cnt[CNT_STEPS] = arr.cnt[CNT_BLOCK_STEPS] = 0
                if status == K.STATUS_SLIPS_FULL:
                    arr.take_slips(self._max_slip_rows)
                elif status == K.STATUS_INTERRUPTED:
                    pass  # a signal handler that did not raise: the undone event runs again
                elif status != K.STATUS_OK:
                    raise_status(K, status, arr, self._model, ev0 + done, self._dt)
                bar.update(got)
                bar.set_postfix(t=f"{arr.scal[SCAL_OFFSET] + arr.scal[SCAL_W]:.4g}", refresh=False)
                if loading:
                    loading, chunk, t0 = False, 256, time.perf_counter()
                else:
                    chunk = next_call_size(chunk, time.perf_counter() - tic)
        return time.perf_counter() - t0, steps, block_steps
