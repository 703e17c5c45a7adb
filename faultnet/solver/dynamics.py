r"""Small-system dynamics: one-block slips, two-block return maps, alpha ramps.

These helpers reproduce Sects. 2-4 of Sakaguchi & Morita (2013): the slip of
the periodic one-block stick-slip against its linear theory (Eq. 6, Fig. 1),
the one-dimensional return map ``x2 - x1 -> x2' - x1'`` of the two-block
system (Figs. 2c, 4c), and the gradual increase of ``alpha`` that finds the
traveling wave of the ring (Fig. 5).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from tqdm.auto import tqdm

from faultnet.exceptions import InvalidParameterError
from faultnet.graphs.builders import chain
from faultnet.model.carlson_langer import CarlsonLanger
from faultnet.solver.engine import run_options, simulate, slip_event
from faultnet.solver.simulator import Simulator

__all__ = ["continuation", "linear_slip", "one_block_slip_curve", "return_map"]


def linear_slip(sigma, alpha, kappa=1.0):
    r"""Slip of one block from the linearised friction, Eq. (6) generalised.

    A single slipping block of total stiffness ``kappa`` (1 alone, ``k + 1``
    in the two-block system, ``2k + 1`` on a ring with its neighbours stuck)
    obeys ``x'' = sigma - kappa x + 2 alpha x'`` to first order; it stops after
    half a period, ``pi / sqrt(kappa - alpha^2)``, having slipped

    .. math:: s = \frac{\sigma}{\kappa}\left(1 + e^{\alpha\pi/\sqrt{\kappa - \alpha^2}}\right).

    Parameters
    ----------
    sigma, alpha, kappa : float or array_like
        Broadcast together.

    Returns
    -------
    float or numpy.ndarray
        ``s``; NaN where ``alpha**2 >= kappa`` (no oscillation: the linear
        theory does not apply).

    Examples
    --------
    >>> round(float(linear_slip(0.01, 2.0, kappa=17.0)), 5)  # two blocks, k = 16
    0.00395
    >>> bool(np.isnan(linear_slip(0.01, 1.0)))
    True
    """
    sigma, alpha, kappa = np.broadcast_arrays(
        np.asarray(sigma, float), np.asarray(alpha, float), np.asarray(kappa, float)
    )
    gap = kappa - alpha**2
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        s = sigma / kappa * (1.0 + np.exp(alpha * np.pi / np.sqrt(gap)))
    s = np.where(gap > 0, s, np.nan)
    return float(s) if s.ndim == 0 else s


def one_block_slip_curve(alphas, sigma, dt=None, n_events=3):
    """Slip of the periodic one-block stick-slip versus ``alpha`` (Fig. 1b, c).

    For each ``alpha`` a one-block model (``chain(1)``) runs ``n_events``
    events from ``x = 0``; every event starts at the static threshold with the
    block at rest, so the motion is periodic and the last slip is taken.

    Parameters
    ----------
    alphas : array_like
        Velocity-weakening rates (>= 0).
    sigma : float
        Friction drop in (0, 1).
    dt : float, optional
        Integration step (default :func:`faultnet.default_dt`).
    n_events : int, optional
        Events per ``alpha`` (>= 1).

    Returns
    -------
    pandas.DataFrame
        Columns ``alpha``, ``s`` (simulated slip), ``s_linear`` (Eq. 6, NaN for
        ``alpha >= 1``) and ``duration`` of the last event.

    Examples
    --------
    >>> curve = one_block_slip_curve([0.2, 2.0], sigma=0.01)
    >>> [round(v, 3) for v in curve["s"]]
    [0.029, 1.275]
    """
    alphas = np.atleast_1d(np.asarray(alphas, dtype=np.float64))
    if alphas.ndim != 1 or alphas.size == 0:
        raise InvalidParameterError(
            f"alphas must be a non-empty 1-D sequence; got shape {alphas.shape}"
        )
    base = CarlsonLanger(chain(1), sigma=sigma, alpha=float(alphas[0]))
    s = np.empty(alphas.size)
    duration = np.empty(alphas.size)
    for i, a in enumerate(alphas):
        res = simulate(base.with_params(alpha=float(a)), n_events, x0=[0.0], dt=dt, progress=False)
        s[i] = res.events["S"].iloc[-1]
        duration[i] = res.events["duration"].iloc[-1]
    return pd.DataFrame(
        {"alpha": alphas, "s": s, "s_linear": linear_slip(sigma, alphas), "duration": duration}
    )


def return_map(model, d_values, base=0.0, dt=None):
    """Two-block return map ``d = x2 - x1 -> d' = x2' - x1'`` (Figs. 2c, 4c).

    For each ``d`` the blocks start at rest at ``x = (base, base + d)`` with
    the plate at 0; the plate loads them until one fails and exactly one slip
    event runs (:func:`faultnet.slip_event`).  Blocks do not move between
    events, so ``d`` is the difference just before the event and ``d'`` the
    difference just after it, which is also the ``d`` of the next event:
    iterating the map gives the dynamics.  ``x1`` and ``x2`` are the blocks in
    the model's node order.

    Parameters
    ----------
    model : CarlsonLanger
        A model with exactly two blocks, e.g. on ``graphs.chain(2)``.
    d_values : array_like
        Differences ``x2 - x1`` before the event.
    base : float, optional
        Displacement of block 1 (the map depends only on ``d``).
    dt : float, optional
        Integration step.

    Returns
    -------
    pandas.DataFrame
        Columns ``d``, ``d_next``, ``S`` (total slip) and ``n_blocks``
        (1: the lagging block alone, 2: a simultaneous slip).

    Examples
    --------
    >>> import faultnet
    >>> two = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=16, sigma=0.01, alpha=2.0)
    >>> table = return_map(two, [0.005])
    >>> round(float(table["d_next"].iloc[0]), 4), int(table["n_blocks"].iloc[0])
    (0.0012, 1)
    """
    if not isinstance(model, CarlsonLanger) or model.n != 2:
        raise InvalidParameterError(
            f"return_map needs a CarlsonLanger model with 2 blocks; got {model!r}"
        )
    d_values = np.atleast_1d(np.asarray(d_values, dtype=np.float64))
    if d_values.ndim != 1 or not np.all(np.isfinite(d_values)):
        raise InvalidParameterError("d_values must be a 1-D sequence of finite numbers")
    out = np.empty((d_values.size, 3))
    for i, d in enumerate(d_values):
        state, row = slip_event(model, [base, base + d], dt=dt)
        x = state.x
        out[i] = (x[1] - x[0], row["S"], row["n_blocks"])
    return pd.DataFrame(
        {"d": d_values, "d_next": out[:, 0], "S": out[:, 1], "n_blocks": out[:, 2].astype(np.int64)}
    )


def continuation(
    model,
    alphas,
    events_per_step,
    x0=None,
    rng=None,
    progress=None,
    *,
    options=None,
    dt=None,
    record_profiles=False,
    **recording,
):
    """Ramp ``alpha`` step by step, carrying the state exactly between steps.

    At each ``alpha`` the model ``model.with_params(alpha=alpha)`` runs
    ``events_per_step`` events continuing from the previous step's final
    state, as an uninterrupted run with a time-dependent ``alpha`` would.  The
    paper reaches the ring's traveling wave (Fig. 5) this way, raising
    ``alpha`` gradually from 0.  One :class:`~faultnet.Simulator` runs the
    whole ramp: each step only swaps the model (:meth:`Simulator.set_model`).

    Parameters
    ----------
    model : CarlsonLanger
        Model whose ``alpha`` is replaced at each step.
    alphas : array_like
        The ``alpha`` values, in order.
    events_per_step : int
        Events run at each ``alpha``.
    x0, rng :
        Initial state for the first step, as in :func:`faultnet.simulate`.
    progress : bool or None
        Progress bar over the steps; None shows it for 20 steps or more (on a
        terminal).
    options, dt :
        Run options (and the ``dt`` shortcut), as in :func:`faultnet.simulate`.
    record_profiles : bool
        Keep the displacement profiles of every step's events.
    **recording :
        ``record_slips``, ``trace_nodes``: passed to the :class:`~faultnet.Simulator`.

    Returns
    -------
    result : SimulationResult
        The last step's result; ``result.state`` continues the ramp.
    steps : pandas.DataFrame
        One row per step: ``alpha``, ``S_last`` (slip of the last event),
        ``n_blocks_mean``, ``n_blocks_max`` and ``t_end`` (start of the last
        event).  ``attrs["seed_entropy"]`` records the seed that drew ``x0``.

    Notes
    -----
    Node attributes ``alpha`` of the graph take precedence over the ramped
    scalar, as in :meth:`CarlsonLanger.with_params`.

    Examples
    --------
    >>> import faultnet
    >>> ring = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=16, sigma=0.01)
    >>> result, steps = continuation(ring, [0.0, 0.5, 1.0], 20, rng=0)
    >>> steps["alpha"].tolist(), result.model.alpha, len(result.events)
    ([0.0, 0.5, 1.0], 1.0, 20)
    """
    alphas = np.atleast_1d(np.asarray(alphas, dtype=np.float64))
    if alphas.ndim != 1 or alphas.size == 0:
        raise InvalidParameterError(
            f"alphas must be a non-empty 1-D sequence; got shape {alphas.shape}"
        )
    if progress is None:
        disable = None if alphas.size >= 20 else True
    else:
        disable = not progress
    rows = []
    sim = result = None
    for a in tqdm(alphas, desc="alpha", unit="step", disable=disable, leave=False):
        step_model = model.with_params(alpha=float(a))
        if sim is None:
            sim = Simulator(step_model, x0, rng, run_options(options, dt), **recording)
        else:
            sim.set_model(step_model)
        result = sim.advance(events_per_step, progress=False, record_profiles=record_profiles)
        ev = result.events
        rows.append(
            {
                "alpha": float(a),
                "S_last": float(ev["S"].iloc[-1]),
                "n_blocks_mean": float(ev["n_blocks"].mean()),
                "n_blocks_max": int(ev["n_blocks"].max()),
                "t_end": float(ev["t"].iloc[-1]),
            }
        )
    steps = pd.DataFrame(rows)
    steps.attrs["seed_entropy"] = result.metadata.get("seed_entropy")
    return result, steps
