"""The public calls of the engine: :func:`simulate` and :func:`slip_event`.

Both build a :class:`~faultnet.Simulator` (:mod:`faultnet.solver.simulator`),
which owns the running simulation; :func:`run_options` applies the ``dt``,
``method`` and ``rtol`` shortcuts that every entry point accepts.
"""

from __future__ import annotations

import numpy as np

from faultnet._validate import check_int
from faultnet.exceptions import InvalidParameterError
from faultnet.model.ofc import OFC
from faultnet.model.state import State
from faultnet.solver.options import RunOptions
from faultnet.solver.result import SimulationResult
from faultnet.solver.simulator import Simulator

__all__ = ["run_options", "simulate", "slip_event"]


def run_options(options=None, dt=None, method=None, rtol=None) -> RunOptions:
    """``options`` with the ``dt``, ``method`` and ``rtol`` shortcuts applied (None: unchanged)."""
    opts = RunOptions.coerce(options)
    shortcuts = (("dt", dt), ("method", method), ("rtol", rtol))
    changes = {k: v for k, v in shortcuts if v is not None}
    return opts.replace(**changes) if changes else opts


def simulate(
    model,
    n_events,
    *,
    x0=None,
    rng=None,
    dt=None,
    progress=None,
    options=None,
    method=None,
    rtol=None,
    record_slips=False,
    record_profiles=False,
    trace_nodes=None,
    max_trace_rows=1_000_000,
    max_slip_rows=50_000_000,
    max_topplings=None,
) -> SimulationResult:
    """Run ``n_events`` slip events of a Carlson-Langer model, or avalanches of an OFC automaton.

    A one-chunk :class:`Simulator`:
    ``Simulator(model, x0=x0, rng=rng, options=options).advance(n_events)``.  Every argument
    after ``n_events`` is a keyword.  An :class:`~faultnet.OFC` model runs in an
    :class:`~faultnet.solver.ofc.OFCSimulator` instead: ``x0`` (initial forces in [0, 1),
    None: uniform with ``rng``, or a state to continue), ``rng``, ``progress`` and
    ``max_topplings`` apply, the integration and recording options do not.

    Parameters
    ----------
    model : CarlsonLanger or OFC
    n_events : int
        Number of events (> 0).
    x0 : array_like, State, SimulationResult, Catalog, path or None
        Initial displacements (plate at u = 0), or a ``State`` / previous
        result to continue from exactly (the plate position and the event
        numbering carry over; the model may differ, e.g. a new alpha), or a
        catalog (read, or its path) to continue with the model it was run on.
        None draws ``x0`` uniformly from [0, 0.01) with ``rng``.
    rng : None, int, SeedSequence or Generator
        Randomness for the initial state (SPEC 7); its SeedSequence entropy is
        recorded in ``metadata``.
    dt : float, optional
        Integration step inside events (shortcut for ``options.dt``); default
        :func:`default_dt`.
    progress : bool or None
        Show a progress bar (None: only on a terminal).
    options : RunOptions, dict or None
        Every numerical choice of the run (scheme, step, crossing treatment,
        guards); recorded in ``metadata["options"]``.
    method : {"dopri5"}, optional
        Shortcut for ``options.method``.
    rtol : float, optional
        Shortcut for ``options.rtol``: the target relative accuracy of an
        event's slip (1e-8 to 1e-4); the step and the crossing treatment
        follow from the calibration in :mod:`faultnet.solver.accuracy`.
    record_slips : bool
        Keep per-block slips of every event (``result.slips``), at most
        ``max_slip_rows`` rows (then recording stops with a warning and
        ``slips.attrs["truncated"]`` is True; the catalog stays complete).
    record_profiles : bool
        Keep the displacement profile after every event (small graphs only:
        ``n_events * n_blocks`` is limited to 2e7).
    trace_nodes : graph node, or sequence of graph nodes, optional
        Record ``x(t)``, ``v(t)`` of these blocks at every integration step
        inside events (``result.traces``), at most ``max_trace_rows`` steps.
    max_topplings : int, optional
        OFC only: the most topplings one avalanche may take (None: no limit).

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
    if isinstance(model, OFC):
        from faultnet.solver.ofc import simulate_ofc

        given = {
            "dt": dt is not None,
            "options": options is not None,
            "method": method is not None,
            "rtol": rtol is not None,
            "record_slips": bool(record_slips),
            "record_profiles": bool(record_profiles),
            "trace_nodes": trace_nodes is not None,
            "max_trace_rows": max_trace_rows != 1_000_000,
            "max_slip_rows": max_slip_rows != 50_000_000,
        }
        if any(given.values()):
            name = next(k for k, v in given.items() if v)
            raise InvalidParameterError(
                f"{name} does not apply to an OFC model (an automaton has no integration, "
                "slips, profiles or traces); leave it out. An OFC run takes x0, rng, progress "
                "and max_topplings"
            )
        return simulate_ofc(
            model, n_events, x0=x0, rng=rng, progress=progress, max_topplings=max_topplings
        )
    if max_topplings is not None:
        raise InvalidParameterError(
            "max_topplings applies to an OFC model only; leave it out for a Carlson-Langer model"
        )
    n_events = check_int("n_events", n_events)
    sim = Simulator(
        model,
        x0,
        rng,
        run_options(options, dt, method, rtol),
        record_slips=record_slips,
        trace_nodes=trace_nodes,
        max_slip_rows=max_slip_rows,
        max_trace_rows=max_trace_rows,
    )
    return sim.advance(n_events, progress=progress, record_profiles=record_profiles)


def slip_event(model, x, u=0.0, dt=None, *, options=None, method=None):
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
    res = simulate(model, 1, x0=x, dt=dt, progress=False, options=options, method=method)
    return res.state, res.events.iloc[0]
