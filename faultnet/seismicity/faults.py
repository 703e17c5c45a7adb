"""Statistics of networks of faults: ruptures that jump, P(M) and b per fault, triggering.

Every function takes the events of a network of faults: ``result.events`` (or a
catalog's ``.events``) of a graph whose blocks carry the node attribute
``fault`` (:func:`faultnet.graphs.compose` and the other fault builders), with
the columns ``fault`` (the hypocentre's fault) and ``n_faults`` (how many faults
slipped).  An event belongs to the fault of its hypocentre.

* :func:`multi_fault_fraction` -- the fraction of events that ruptured more than
  one fault, by magnitude;
* :func:`fault_magnitudes` -- P(M) of each fault's events, one tidy table;
* :func:`b_per_fault` -- the b-value of each fault, at one common threshold;
* :func:`fault_triggering` -- given an event on fault A, how often an event on
  fault B follows within a time window, against chance.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from faultnet.exceptions import InvalidParameterError
from faultnet.seismicity.mainshocks import _events
from faultnet.stats.magnitudes import fit_b_mle, magnitude_distribution

__all__ = ["b_per_fault", "fault_magnitudes", "fault_triggering", "multi_fault_fraction"]


def _fault_events(events, columns=("fault",)):
    """The events, sorted by time, checked to be those of a network of faults."""
    frame = _events(events)
    missing = [c for c in columns if c not in frame.columns]
    if missing:
        raise InvalidParameterError(
            f"events needs the column(s) {missing} of a network of faults: simulate a graph "
            "whose blocks carry the node attribute 'fault' (e.g. faultnet.graphs.step_over)"
        )
    return frame


def multi_fault_fraction(events, bins=10, m_min=None):
    """The fraction of events that ruptured more than one fault, in magnitude bins.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
        Events of a network of faults (columns ``M`` and ``n_faults``).
    bins : int or sequence, optional
        As in :func:`numpy.histogram`, over the magnitudes ``M >= m_min``.
    m_min : float, optional
        Leave out smaller events (default: none).

    Returns
    -------
    pandas.DataFrame
        One row per non-empty bin: ``M`` (bin centre), ``events``, ``multi`` (events
        on more than one fault), ``fraction`` and its binomial standard ``error``.

    Examples
    --------
    >>> import faultnet
    >>> G = faultnet.graphs.parallel_faults(2, 20, k_coupling=8.0)
    >>> res = faultnet.simulate(faultnet.CarlsonLanger(G), 2000, rng=1, progress=False)
    >>> table = multi_fault_fraction(res, bins=5)
    >>> list(table.columns), int(table["events"].sum()) == len(res.events)
    (['M', 'events', 'multi', 'fraction', 'error'], True)
    """
    frame = _fault_events(events, ("n_faults",))
    M = frame["M"].to_numpy(dtype=np.float64)
    keep = np.isfinite(M) & (True if m_min is None else M >= float(m_min))
    M, multi = M[keep], frame["n_faults"].to_numpy()[keep] > 1
    if M.size == 0:
        raise InvalidParameterError(f"no event with a finite M >= m_min={m_min!r}")
    edges = np.histogram_bin_edges(M, bins=bins)
    which = np.clip(np.searchsorted(edges, M, side="right") - 1, 0, len(edges) - 2)
    n = np.bincount(which, minlength=len(edges) - 1)
    k = np.bincount(which, weights=multi, minlength=len(edges) - 1)
    used = n > 0
    p = k[used] / n[used]
    return pd.DataFrame(
        {
            "M": 0.5 * (edges[:-1] + edges[1:])[used],
            "events": n[used].astype(np.int64),
            "multi": k[used].astype(np.int64),
            "fraction": p,
            "error": np.sqrt(p * (1.0 - p) / n[used]),
        }
    )


def fault_magnitudes(events, bins=30, range=None):
    """P(M) of each fault's events, on common bins, as one tidy table.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
        Events of a network of faults (columns ``M`` and ``fault``).
    bins, range
        As in :func:`faultnet.magnitude_distribution`; ``range`` defaults to that
        of all the events, so the faults share their bins.

    Returns
    -------
    pandas.DataFrame
        Columns ``fault``, ``M``, ``density``, ``count``, ``width``: each fault's
        :func:`faultnet.magnitude_distribution`, normalised over its own events.
    """
    frame = _fault_events(events)
    M = frame["M"].to_numpy(dtype=np.float64)
    if range is None:
        finite = M[np.isfinite(M)]
        if finite.size == 0:
            raise InvalidParameterError("fault_magnitudes needs events with a finite M")
        range = (float(finite.min()), float(finite.max()))
    tables = []
    for fault, group in frame.groupby("fault", sort=False):
        table = magnitude_distribution(group["M"].to_numpy(), bins=bins, range=range)
        label = np.empty(len(table), dtype=object)
        label[:] = [fault] * len(table)  # element-wise: a tuple label stays one label
        tables.append(table.assign(fault=label))
    return pd.concat(tables, ignore_index=True)[["fault", "M", "density", "count", "width"]]


def b_per_fault(events, m_min=None):
    """The Aki maximum-likelihood b of each fault's events, above one common ``m_min``.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
        Events of a network of faults (columns ``M`` and ``fault``).
    m_min : float, optional
        The threshold (default: the one :func:`faultnet.fit_b_mle` picks on all the
        events, so that the faults' b-values compare on the same magnitudes).

    Returns
    -------
    pandas.DataFrame
        Indexed by fault, in order of first appearance: ``events`` (all), ``n`` (above
        ``m_min``), ``m_min``, ``b`` and ``b_err``; NaN where a fault has fewer than two
        events above ``m_min``.
    """
    frame = _fault_events(events)
    if m_min is None:
        m_min = fit_b_mle(frame["M"].to_numpy()).m_min
    rows = {}
    for fault, group in frame.groupby("fault", sort=False):
        M = group["M"].to_numpy(dtype=np.float64)
        above = int(np.sum(np.isfinite(M) & (M >= m_min)))
        fit = fit_b_mle(M, m_min=m_min) if above >= 2 else None
        rows[fault] = {
            "events": len(group),
            "n": above,
            "m_min": float(m_min),
            "b": fit.b if fit else math.nan,
            "b_err": fit.b_err if fit else math.nan,
        }
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index.name = "fault"
    return table


def fault_triggering(events, window, m_min=None):
    """Given an event on fault A, how often an event on fault B follows within ``window``.

    For every ordered pair of faults (A, B), A and B equal included: the fraction of
    A's events (``M >= m_min``) followed by at least one event of B within plate time
    ``(t, t + window]``, and the fraction chance alone gives, ``1 - exp(-r_B window)``
    with ``r_B`` B's rate over the catalogue.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
        Events of a network of faults (columns ``t``, ``M`` and ``fault``).
    window : float
        The time after an event, in plate time, > 0.
    m_min : float, optional
        Only events with ``M >= m_min``, as triggers and as followers.

    Returns
    -------
    pandas.DataFrame
        Indexed by ``(source, target)``: ``n_source``, ``followed``, ``fraction``,
        ``chance`` and ``ratio`` (``fraction / chance``; above 1: B follows A more
        often than chance).

    Examples
    --------
    >>> import faultnet
    >>> G = faultnet.graphs.step_over(30, overlap=5, gap=1.0, k_coupling=4.0)
    >>> res = faultnet.simulate(faultnet.CarlsonLanger(G), 3000, rng=1, progress=False)
    >>> table = fault_triggering(res, window=0.05)
    >>> sorted(table.index)
    [('A', 'A'), ('A', 'B'), ('B', 'A'), ('B', 'B')]
    """
    window = float(window)
    if not (math.isfinite(window) and window > 0):
        raise InvalidParameterError(f"window must be a finite plate time > 0; got {window!r}")
    frame = _fault_events(events)
    if m_min is not None:
        frame = frame[frame["M"] >= float(m_min)]
    if len(frame) < 2:
        raise InvalidParameterError(
            f"fault_triggering needs two events or more above m_min={m_min!r}"
        )
    t = frame["t"].to_numpy(dtype=np.float64)
    span = t[-1] - t[0]
    faults = frame["fault"].to_numpy()
    rows = {}
    for source in pd.unique(faults):
        t_source = t[faults == source]
        for target in pd.unique(faults):
            t_target = t[faults == target]
            # the first target event strictly after each source event, and whether it is in time
            nxt = np.searchsorted(t_target, t_source, side="right")
            ok = nxt < t_target.size
            followed = int(np.sum(t_target[nxt[ok]] <= t_source[ok] + window))
            chance = 1.0 - math.exp(-t_target.size / span * window) if span > 0 else math.nan
            fraction = followed / t_source.size
            rows[(source, target)] = {
                "n_source": int(t_source.size),
                "followed": followed,
                "fraction": fraction,
                "chance": chance,
                "ratio": fraction / chance if chance > 0 else math.nan,
            }
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index = pd.MultiIndex.from_tuples(list(rows), names=["source", "target"])
    return table
