"""Run the model: validate, allocate, call the Numba kernel in chunks, wrap.

The plate is never time-stepped: between events it jumps analytically to the
next failure (a tournament tree over per-block failure keys).  Inside an event
only the slipping blocks are integrated, with Dormand-Prince 5(4) (default) or
classical RK4 at a fixed step ``dt``; stick (v -> 0) and join (F -> 1) instants
are located inside a step (on the DP5 dense output, or a cubic Hermite
interpolant for RK4) and the step is redone up to that instant, so the scheme
keeps its order (see ``tests/test_convergence.py``).
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
from tqdm.auto import tqdm

from faultnet.catalog import SimulationResult, events_frame, slips_frame, traces_frame
from faultnet.exceptions import (
    EventTooLongError,
    InvalidParameterError,
    NumericalInstabilityError,
)
from faultnet.model import CarlsonLanger
from faultnet.state import State

__all__ = ["DT_COEFFICIENT", "default_dt", "simulate", "slip_event"]

#: integration schemes inside events, and their kernel codes
METHODS = {"rk4": 0, "dopri5": 1}
#: default step = DT_COEFFICIENT[method] / sqrt(omega2_max); see :func:`default_dt`
DT_COEFFICIENT = {"rk4": 0.08, "dopri5": 0.3}
DEFAULT_METHOD = "dopri5"
#: An event whose hypocentre slips alone (no neighbour reaches the threshold
#: during its slip) is the block's *solo slip*, which depends only on its own
#: stiffness, sigma and alpha: it is integrated once per such parameter class
#: and reused.  Off: every event is integrated (the reference for tests).
SOLO_FAST_PATH = True
#: Events with at least this many slipping blocks handle the crossings of a
#: step in small local regions (``faultnet._kernels.local``) instead of
#: stepping every slipping block to each crossing: far fewer block-steps in
#: large 2-D events, with each region's change neglected outside it: the
#: error of such events against dt -> 0 is 1.1-2.4 times the whole-event
#: treatment's at the same dt (``tests/test_local.py``).  ``float("inf")``: always the
#: exact whole-event treatment (the reference for tests).
LOCAL_REGIONS_FROM = 32
#: treatment of stops and joins inside a step (``faultnet.accuracy.CROSSINGS``): "exact"
#: reaches each crossing and keeps the scheme's order; "interpolated" places them on the
#: step's dense output without redoing the step (cheaper, an O(dt^4) error per crossing)
CROSSINGS = "exact"
#: RK4 is stable on an oscillator for omega*dt < 2.83; refuse steps near it
_DT_STABILITY = 2.5
#: initial displacements are drawn uniformly from [0, X0_AMPLITUDE)
X0_AMPLITUDE = 0.01
_MAX_PROFILE_VALUES = 20_000_000


def omega2_max(model: CarlsonLanger) -> float:
    """Gershgorin bound on the squared top frequency, plus the alpha growth rate.

    ``max_i (1 + 2 sum_j k_ij) + max_i alpha_i^2``: the largest eigenvalue of
    the dynamical matrix ``L + I`` is at most the first term; the second
    accounts for the growth rate of the negative damping ``2 alpha``.
    """
    deg = np.asarray(model.adjacency.sum(axis=1)).ravel()
    return float(np.max(1.0 + 2.0 * deg) + np.max(model.alpha_values) ** 2)


def default_dt(model: CarlsonLanger, method: str = DEFAULT_METHOD) -> float:
    """Default integration step: ``DT_COEFFICIENT[method] / sqrt(omega2_max(model))``.

    With the coefficients 0.3 (dopri5) and 0.08 (rk4), slip sizes of single
    events are within 3e-7 relative of the dt -> 0 limit on the one-block,
    two-block and ring test cases (``tests/test_convergence.py``).

    >>> import faultnet
    >>> one = faultnet.CarlsonLanger(faultnet.graphs.chain(1), alpha=2.0)
    >>> round(default_dt(one), 6), round(default_dt(one, "rk4"), 6)
    (0.134164, 0.035777)
    """
    return DT_COEFFICIENT[_check_method(method)] / math.sqrt(omega2_max(model))


def _check_method(method):
    if method not in METHODS:
        raise InvalidParameterError(f"method must be one of {sorted(METHODS)}; got {method!r}")
    return method


def _crossings_code(crossings):
    from faultnet.accuracy import CROSSINGS as codes

    if crossings not in codes:
        raise InvalidParameterError(f"crossings must be one of {sorted(codes)}; got {crossings!r}")
    return codes[crossings]


def _check_count(n_events):
    if isinstance(n_events, bool) or not isinstance(n_events, (int, np.integer)):
        raise InvalidParameterError(f"n_events must be a positive integer; got {n_events!r}")
    if n_events <= 0:
        raise InvalidParameterError(f"n_events must be > 0; got {n_events}")
    return int(n_events)


def _check_dt(model, dt, method):
    if dt is None:
        return default_dt(model, method)
    dt = float(dt)
    if not (math.isfinite(dt) and dt > 0.0):
        raise InvalidParameterError(f"dt must be finite and > 0; got {dt!r}")
    limit = _DT_STABILITY / math.sqrt(omega2_max(model))
    if dt > limit:
        raise InvalidParameterError(
            f"dt={dt:g} is beyond the RK4 stability limit {limit:.4g} of this model "
            f"(stiffest block); use dt <= {limit:.4g} or leave dt=None for "
            f"{default_dt(model, method):.4g}"
        )
    return dt


def _seed_and_rng(rng):
    """SPEC 7: normalise ``rng``; record the SeedSequence when we can."""
    if isinstance(rng, np.random.Generator):
        seq = getattr(rng.bit_generator, "seed_seq", None)
        return rng, seq
    seq = rng if isinstance(rng, np.random.SeedSequence) else np.random.SeedSequence(rng)
    return np.random.default_rng(seq), seq


def _initial_state(model, x0, rng):
    """State from ``x0`` (array, State or SimulationResult) or drawn from ``rng``."""
    if isinstance(x0, SimulationResult):
        x0 = x0.state
    if isinstance(x0, State):
        z = np.asarray(x0.z, dtype=np.float64)
        if z.shape != (model.n,):
            raise InvalidParameterError(f"x0 state has {z.size} blocks but the model has {model.n}")
        return x0.copy(), None
    gen, seq = _seed_and_rng(rng)
    if x0 is None:
        return State.from_x(gen.uniform(0.0, X0_AMPLITUDE, model.n)), seq
    x = np.asarray(x0, dtype=np.float64)
    if x.shape != (model.n,):
        raise InvalidParameterError(
            f"x0 must have one entry per block: expected shape ({model.n},), got {x.shape}"
        )
    bad = np.flatnonzero(~np.isfinite(x))
    if bad.size:
        raise InvalidParameterError(
            f"x0 has non-finite entries at positions {bad[:5].tolist()}: {x[bad[:5]].tolist()}"
        )
    return State.from_x(x), None


def _trace_indices(model, trace_nodes):
    if trace_nodes is None:
        return np.zeros(0, dtype=np.int64)
    index = {node: i for i, node in enumerate(model.nodes)}
    missing = [n for n in trace_nodes if n not in index]
    if missing:
        raise InvalidParameterError(f"trace_nodes not in the graph: {missing[:5]}")
    return np.array([index[n] for n in trace_nodes], dtype=np.int64)


def _kernels():
    """The Numba kernels, imported on the first run (not by ``import faultnet``: numba's import
    takes a quarter of a second)."""
    from faultnet import _kernels

    return _kernels


def _helper():
    """:mod:`faultnet._compile_helper`, imported by the first run (``python -m
    faultnet._compile_helper --record`` must not find it imported by the package)."""
    from faultnet import _compile_helper

    return _compile_helper


#: the progress bar's label while the first run compiles the kernels
COMPILING_LABEL = "faultnet: compiling the kernels (first run only, ~30 s)"


def _compiling(kernel):
    """True if ``kernel`` (an entry kernel) will compile: its on-disk cache has nothing for it."""
    return _helper().cache_is_cold(kernel)


#: error class and message per kernel status (by name: the codes live in the kernels)
_STATUS_MESSAGES = {
    "STATUS_NONFINITE": (
        NumericalInstabilityError,
        "a velocity became NaN at block {node!r} in event {event}; reduce dt (now {dt:g})",
    ),
    "STATUS_RUNAWAY": (
        NumericalInstabilityError,
        "runaway velocity (> {vmax:g}) at block {node!r} in event {event}; the integration "
        "is unstable: reduce dt (now {dt:g}) or check k, sigma and alpha",
    ),
    "STATUS_EVENT_TOO_LONG": (
        EventTooLongError,
        "event {event} was still running after {maxd:g} time units; raise "
        "max_event_duration if such long events are expected, else reduce dt (now {dt:g})",
    ),
}


class _Run:
    """Arrays of one run: topology, state, work space and output buffers."""

    def __init__(
        self,
        model,
        state,
        dt,
        record_slips,
        trace_idx,
        max_trace_rows,
        profiles_rows,
        max_event_duration,
        max_velocity,
        method=DEFAULT_METHOD,
    ):
        n = model.n
        adj = model.adjacency
        self.indptr = adj.indptr.astype(np.int64)
        self.indices = adj.indices.astype(np.int64)
        self.kval = adj.data.astype(np.float64)
        self.diag = model.stiffness.astype(np.float64)
        self.oms = 1.0 - model.sigma_values
        self.cfr = 2.0 * model.alpha_values / self.oms
        self.z = np.array(state.z, dtype=np.float64)
        self.scal = np.array([state.offset, state.w], dtype=np.float64)
        self.keys = np.empty(n, dtype=np.float64)
        K = _kernels()
        # one entry kernel per scheme: a run compiles only its own scheme's code
        self.kernel = K.run_events_rk4 if method == "rk4" else K.run_events_dopri5
        _helper().start(self.kernel)  # a cold cache: a second core compiles too
        self.tree = K.empty_tree(n)
        K.build_keys_and_tree(
            self.z, self.indptr, self.indices, self.kval, self.diag, self.keys, self.tree
        )
        self.W = np.zeros(
            (n, K.N_WORK_DOPRI), dtype=np.float64
        )  # block-major: one block's rows share cache lines
        self.IW = np.zeros((K.N_IWORK, n), dtype=np.int64)
        # dt, max duration, max velocity, solo fast path on, local regions from, crossings
        self.ctrl = np.array(
            [
                dt,
                max_event_duration,
                max_velocity,
                float(SOLO_FAST_PATH),
                float(LOCAL_REGIONS_FROM),
                float(_crossings_code(CROSSINGS)),
            ],
            dtype=np.float64,
        )
        cap = max(4 * n, 1 << 16) if record_slips else 0
        self.slip_e = np.zeros(cap, dtype=np.int64)
        self.slip_n = np.zeros(cap, dtype=np.int64)
        self.slip_v = np.zeros(cap, dtype=np.float64)
        self.slip_rows = 0
        self.slips_truncated = False
        self.trace_idx = trace_idx
        rows = max_trace_rows if trace_idx.size else 0
        self.trace = np.zeros((rows, 2 + 2 * trace_idx.size), dtype=np.float64)
        self.profiles = np.zeros((profiles_rows, n if profiles_rows else 0), dtype=np.float64)
        self.cnt = np.zeros(16, dtype=np.int64)
        # local-region context (boundary, times) and the boundary's dense coefficients
        self.loc = np.zeros(K.LOC_SIZE, dtype=np.float64)
        # blocks with equal (stiffness, sigma, alpha) share one cached solo slip
        self.cls = model.block_classes
        self.solo = np.full((int(self.cls.max()) + 1, 3), np.nan)
        self.out = np.zeros(6, dtype=np.float64)

    def call(self, n_req, ev0, cat_f, cat_i, profiles):
        self.cnt[0] = 0
        return self.kernel(
            n_req,
            ev0,
            self.z,
            self.scal,
            self.keys,
            self.tree,
            self.W,
            self.IW,
            self.indptr,
            self.indices,
            self.kval,
            self.diag,
            self.oms,
            self.cfr,
            self.ctrl,
            self.loc,
            self.cls,
            self.solo,
            cat_f,
            cat_i,
            self.slip_e,
            self.slip_n,
            self.slip_v,
            self.trace_idx,
            self.trace,
            profiles,
            self.cnt,
            self.out,
        )

    def take_slips(self, parts, limit):
        """Move the buffered slip rows to ``parts``; stop recording past ``limit`` rows."""
        m = min(int(self.cnt[1]), limit - self.slip_rows)
        if m > 0:
            parts.append((self.slip_e[:m].copy(), self.slip_n[:m].copy(), self.slip_v[:m].copy()))
            self.slip_rows += m
        self.cnt[1] = 0
        if self.slip_v.size and self.slip_rows >= limit:
            self.slips_truncated = True
            self.slip_e = self.slip_n = np.zeros(0, dtype=np.int64)
            self.slip_v = np.zeros(0, dtype=np.float64)


def simulate(
    model,
    n_events,
    x0=None,
    rng=None,
    dt=None,
    progress=None,
    *,
    record_slips=False,
    record_profiles=False,
    trace_nodes=None,
    max_trace_rows=1_000_000,
    max_slip_rows=50_000_000,
    max_event_duration=1e4,
    max_velocity=1e3,
    method=DEFAULT_METHOD,
):
    """Run ``n_events`` slip events of a Carlson-Langer model.

    Parameters
    ----------
    model : CarlsonLanger
    n_events : int
        Number of events (> 0).
    x0 : array_like, State, SimulationResult or None
        Initial displacements (plate at u = 0), or a ``State`` / previous
        result to continue from exactly (the plate position and the event
        numbering carry over; the model may differ, e.g. a new alpha).  None
        draws ``x0`` uniformly from [0, 0.01) with ``rng``.
    rng : None, int, SeedSequence or Generator
        Randomness for the initial state (SPEC 7); its SeedSequence entropy is
        recorded in ``metadata``.
    dt : float, optional
        Integration step inside events; default :func:`default_dt`.
    progress : bool or None
        Show a progress bar (None: only on a terminal).
    record_slips : bool
        Keep per-block slips of every event (``result.slips``), at most
        ``max_slip_rows`` rows (then recording stops with a warning and
        ``slips.attrs["truncated"]`` is True; the catalog stays complete).
    record_profiles : bool
        Keep the displacement profile after every event (small graphs only:
        ``n_events * n_blocks`` is limited to 2e7).
    trace_nodes : sequence of graph nodes, optional
        Record ``x(t)``, ``v(t)`` of these blocks at every integration step
        inside events (``result.traces``), at most ``max_trace_rows`` steps.
    max_event_duration, max_velocity : float
        Safety limits: a longer event or a faster block stops the run with an
        error that says what to change.
    method : {"dopri5", "rk4"}
        Scheme inside events: fixed-step Dormand-Prince 5(4) (default) or
        classical RK4.  Both locate stick and join instants inside a step.

    Returns
    -------
    SimulationResult

    Examples
    --------
    >>> import faultnet
    >>> one = faultnet.CarlsonLanger(faultnet.graphs.chain(1), sigma=0.01, alpha=2.0)
    >>> res = faultnet.simulate(one, n_events=3, x0=[0.0], progress=False)
    >>> [round(s, 3) for s in res.events["S"]]
    [1.275, 1.275, 1.275]
    >>> more = faultnet.simulate(one, n_events=2, x0=res.state, progress=False)
    >>> more.events["event"].tolist()
    [3, 4]
    """
    if not isinstance(model, CarlsonLanger):
        raise InvalidParameterError(f"model must be a CarlsonLanger; got {type(model).__name__}")
    n_events = _check_count(n_events)
    method = _check_method(method)
    dt = _check_dt(model, dt, method)
    for name, val in (("max_event_duration", max_event_duration), ("max_velocity", max_velocity)):
        if not (math.isfinite(float(val)) and float(val) > 0):
            raise InvalidParameterError(f"{name} must be finite and > 0; got {val!r}")
    state, seq = _initial_state(model, x0, rng)
    trace_idx = _trace_indices(model, trace_nodes)
    if record_profiles and n_events * model.n > _MAX_PROFILE_VALUES:
        raise InvalidParameterError(
            f"record_profiles would store {n_events} x {model.n} values (limit "
            f"{_MAX_PROFILE_VALUES:.0e}); run fewer events or record slips instead"
        )
    run = _Run(
        model,
        state,
        dt,
        record_slips,
        trace_idx,
        int(max_trace_rows),
        n_events if record_profiles else 0,
        float(max_event_duration),
        float(max_velocity),
        method,
    )
    cat_f = np.zeros((n_events, 3), dtype=np.float64)
    cat_i = np.zeros((n_events, 3), dtype=np.int64)
    slip_parts = []
    ev0 = state.n_events
    done = 0
    steps = block_steps = 0
    chunk = 256
    compiling = _compiling(run.kernel)  # reads the cache index: outside the timed loop
    t0 = time.perf_counter()
    with tqdm(
        total=n_events,
        unit="ev",
        disable=(None if progress is None else not progress),
        leave=False,
        desc=COMPILING_LABEL if compiling else "faultnet",
    ) as bar:
        K = _kernels()
        while done < n_events:
            n_req = min(chunk, n_events - done)
            tic = time.perf_counter()
            prof = run.profiles[done:] if record_profiles else run.profiles
            status = run.call(n_req, ev0 + done, cat_f[done:], cat_i[done:], prof)
            _helper().stop()  # compiled (or loaded) by now
            if compiling:  # the bar's clock and rate count the simulation only
                bar.unpause()
                bar.set_description_str("faultnet")
                compiling = False
            got = int(run.cnt[0])
            done += got
            steps += int(run.cnt[3])
            block_steps += int(run.cnt[4])
            run.cnt[3] = run.cnt[4] = 0
            if status == K.STATUS_SLIPS_FULL:
                run.take_slips(slip_parts, max_slip_rows)
            elif status != K.STATUS_OK:
                _raise(status, run, model, ev0 + done, dt)
            bar.update(got)
            bar.set_postfix(t=f"{run.scal[0] + run.scal[1]:.4g}", refresh=False)
            elapsed = time.perf_counter() - tic
            if elapsed < 0.1:
                chunk = min(chunk * 2, 1 << 20)
            elif elapsed > 0.5:
                chunk = max(chunk // 2, 1)
    wall = time.perf_counter() - t0
    run.take_slips(slip_parts, max_slip_rows)
    final = State(run.z, float(run.scal[0]), float(run.scal[1]), ev0 + n_events)
    return _wrap(
        model,
        run,
        final,
        dt,
        method,
        ev0,
        cat_f,
        cat_i,
        slip_parts,
        record_slips,
        record_profiles,
        seq,
        wall,
        steps,
        block_steps,
        x0,
    )


def _raise(status, run, model, event, dt):
    K = _kernels()
    cls, template = next(v for name, v in _STATUS_MESSAGES.items() if getattr(K, name) == status)
    bad = int(run.out[4]) if status == K.STATUS_EVENT_TOO_LONG else None
    node = model.nodes[bad] if bad is not None else "?"
    raise cls(template.format(node=node, event=event, dt=dt, vmax=run.ctrl[2], maxd=run.ctrl[1]))


def _wrap(
    model,
    run,
    final,
    dt,
    method,
    ev0,
    cat_f,
    cat_i,
    slip_parts,
    record_slips,
    record_profiles,
    seq,
    wall,
    steps,
    block_steps,
    x0,
):
    from faultnet import __version__

    events = events_frame(ev0, cat_f, cat_i, model.nodes)
    slips = None
    if record_slips:
        parts = slip_parts or [(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0))]
        event, node, slip = (np.concatenate([p[c] for p in parts]) for c in range(3))
        slips = slips_frame(event, node, slip, model.nodes)
        slips.attrs["truncated"] = run.slips_truncated
        if run.slips_truncated:
            warnings.warn(
                f"per-block slips were recorded for the first {len(slips):,} rows only "
                "(max_slip_rows); the event catalog is complete",
                stacklevel=3,
            )
    traces = None
    if run.trace_idx.size:
        traces = traces_frame(run.trace[: int(run.cnt[2])], run.trace_idx, model.nodes)
        traces.attrs["truncated"] = bool(run.cnt[5])
    md = dict(model.params)
    md.update(
        dt=dt,
        method=method,
        faultnet_version=__version__,
        first_event=ev0,
        n_events=len(events),
        seed_entropy=None if seq is None else seq.entropy,
        seed_spawn_key=None if seq is None else tuple(seq.spawn_key),
        initial_state="random U[0, 0.01)" if x0 is None else "given",
        wall_time_s=wall,
        n_steps=steps,
        block_steps=block_steps,
        solo_events=int(run.cnt[8]),
        local_steps=int(run.cnt[9]),
        local_fallbacks=int(run.cnt[10]),
        partial_block_steps=int(run.cnt[6]),
        region_block_steps=int(run.cnt[12]),
        landed_joins=int(run.cnt[13]),
        interpolated_crossings=int(run.cnt[14]),
    )
    return SimulationResult(
        events=events,
        state=final,
        model=model,
        dt=dt,
        metadata=md,
        slips=slips,
        profiles=run.profiles if record_profiles else None,
        traces=traces,
    )


def slip_event(model, x, u=0.0, dt=None, **kwargs):
    """Run exactly one slip event from displacements ``x`` (or a ``State``).

    The plate is loaded until the first block fails, the event runs to its
    end, and the state after it is returned with the event's catalog row.
    This is the building block of return maps (paper, Figs. 2c and 4c).

    Returns
    -------
    state : State
    row : pandas.Series
        The event's row of ``events`` (t, duration, n_blocks, S, M, hypocenter).

    Examples
    --------
    >>> import faultnet
    >>> two = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=16, sigma=0.01, alpha=2.0)
    >>> state, row = faultnet.slip_event(two, [0.0, 0.01])
    >>> int(row["n_blocks"]), int(row["hypocenter"])
    (1, 0)
    """
    if not isinstance(x, State):
        x = np.asarray(x, dtype=np.float64)
        if x.shape == (model.n,) and np.all(np.isfinite(x)):
            x = State.from_x(x, u)
    res = simulate(model, 1, x0=x, dt=dt, progress=False, **kwargs)
    return res.state, res.events.iloc[0]
