"""Mainshock-centred statistics: stacked rates, aftershock times, distance profiles, b.

The mainshocks of a catalog are its events with ``M >= m_main``; each gets a
time window that stops at the previous and the next mainshock and at the ends
of the catalog, so no foreshock or aftershock window reaches into another
mainshock's.  Public entry points are re-exported by :mod:`faultnet.seismicity.timing`.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from faultnet.exceptions import InvalidParameterError
from faultnet.stats.magnitudes import BFit, fit_b_mle

__all__ = [
    "aftershock_times",
    "b_around_mainshocks",
    "distance_profile",
    "stack_mainshocks",
]


def _events(events):
    """The events DataFrame of a result or frame, sorted by time, with ``t`` and ``M``."""
    if hasattr(events, "events") and hasattr(events, "model"):
        events = events.events
    if not isinstance(events, pd.DataFrame):
        raise InvalidParameterError(
            f"events must be an events DataFrame or a SimulationResult; got {type(events).__name__}"
        )
    missing = {"t", "M"} - set(events.columns)
    if missing:
        raise InvalidParameterError(f"events needs columns 't' and 'M'; missing {sorted(missing)}")
    t = events["t"].to_numpy(dtype=np.float64)
    if t.size > 1 and np.any(np.diff(t) < 0):
        events = events.sort_values("t", kind="stable")
    return events.reset_index(drop=True)


def _threshold(M, m_min):
    return np.ones(M.size, bool) if m_min is None else M >= float(m_min)


def _window(window):
    """``(before, after) >= 0`` from a number or a pair."""
    before, after = (window, window) if np.ndim(window) == 0 else window
    before, after = float(before), float(after)
    if not (before >= 0 and after >= 0 and math.isfinite(before + after) and before + after > 0):
        raise InvalidParameterError(
            f"window must be a positive time or a pair (before, after) of times >= 0; "
            f"got {window!r}"
        )
    return before, after


class _Mainshocks:
    """Mainshocks (``M >= m_main``) of a catalog and their non-overlapping time windows.

    The window of mainshock ``j`` is ``(t_j - before, t_j + after)`` cut at the
    previous and the next mainshock and at the ends of the catalog, so no
    foreshock or aftershock window reaches into another mainshock's.
    """

    def __init__(self, events, m_main, window, m_min=None):
        ev = _events(events)
        self.events = ev
        self.t = ev["t"].to_numpy(dtype=np.float64)
        self.M = ev["M"].to_numpy(dtype=np.float64)
        self.main = np.flatnonzero(self.M >= float(m_main))
        if self.main.size == 0:
            raise InvalidParameterError(
                f"no mainshock: no event has M >= m_main={m_main!r} (largest M = "
                f"{self.M.max():.3g})"
            )
        before, after = _window(window)
        tm = self.t[self.main]
        prev = np.concatenate([[self.t[0]], tm[:-1]])
        nxt = np.concatenate([tm[1:], [self.t[-1]]])
        self.t_main = tm
        self.lo = np.maximum(-before, prev - tm)  # relative times, lo <= 0 <= hi
        self.hi = np.minimum(after, nxt - tm)
        self.selected = np.flatnonzero(_threshold(self.M, m_min))

    def pairs(self):
        """(mainshock number, event position, time since the mainshock) inside the windows."""
        ts = self.t[self.selected]
        i0 = np.searchsorted(ts, self.t_main + self.lo, side="right")
        i1 = np.searchsorted(ts, self.t_main + self.hi, side="left")
        lengths = np.maximum(i1 - i0, 0)
        owner = np.repeat(np.arange(self.main.size), lengths)
        starts = np.repeat(i0 - np.concatenate([[0], np.cumsum(lengths)[:-1]]), lengths)
        pos = self.selected[starts + np.arange(lengths.sum())]
        keep = pos != self.main[owner]  # the mainshock is not its own fore/aftershock
        owner, pos = owner[keep], pos[keep]
        return owner, pos, self.t[pos] - self.t_main[owner]

    def exposure(self, edges):
        """Summed window time of all mainshocks inside each bin of relative time."""
        lo = np.maximum(self.lo[:, None], edges[None, :-1])
        hi = np.minimum(self.hi[:, None], edges[None, 1:])
        return np.clip(hi - lo, 0.0, None).sum(axis=0)


def _edges(bins, before, after):
    if np.ndim(bins) == 0:
        k = int(bins)
        if k < 1:
            raise InvalidParameterError(f"bins must be >= 1 per side or an edge array; got {bins}")
        left = np.linspace(-before, 0.0, k + 1) if before > 0 else np.zeros(1)
        right = np.linspace(0.0, after, k + 1)[1:] if after > 0 else np.zeros(0)
        return np.concatenate([left, right])
    edges = np.asarray(bins, dtype=np.float64)
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0):
        raise InvalidParameterError("bins: edges must be a 1-D increasing array of >= 2 values")
    return edges


def stack_mainshocks(events, m_main, window, bins=20, m_min=None, graph=None, radius=None):
    """Event rate against time from mainshocks (``M >= m_main``), stacked.

    Every event with ``M >= m_min`` inside a mainshock's window counts at its
    time ``tau = t - t_main`` (negative before).  Windows stop at the previous
    and the next mainshock and at the ends of the catalog, and the rate of a
    bin is its count divided by the window time the mainshocks actually spent
    in it (``exposure``), so cut windows do not bias the rate.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
    m_main : float
        Mainshock magnitude threshold.
    window : float or (float, float)
        Plate time before and after each mainshock.
    bins : int or array_like, optional
        Equal bins per side (default 20), or increasing edges of ``tau``
        (e.g. log-spaced after the mainshock for Omori plots).
    m_min : float, optional
        Threshold of the counted events (default every event).
    graph, radius : optional
        With a graph (or model/result) and a radius, count only events whose
        hypocentre lies within ``radius`` (Euclidean, periodic boxes included)
        of the mainshock's.

    Returns
    -------
    pandas.DataFrame
        Columns ``t_lo``, ``t_hi``, ``t`` (bin centre), ``count``,
        ``exposure``, ``rate`` (events per unit plate time, all mainshocks
        together divided by their exposure) and ``rate_err`` (``sqrt(count) /
        exposure``).  ``attrs``: ``n_mainshocks`` and ``background``: the
        mean rate of the counted events over the whole catalog, or with
        ``radius`` the catalog-wide rate of those within ``radius`` of a
        mainshock's hypocentre (averaged over the mainshocks), so that
        ``rate / background`` is 1 without any time correlation.

    Examples
    --------
    >>> import numpy as np, pandas as pd
    >>> rng = np.random.default_rng(1)
    >>> t = np.sort(rng.uniform(0, 1000, 20_000))
    >>> M = np.where(rng.random(t.size) < 0.005, 5.0, 0.0)
    >>> table = stack_mainshocks(pd.DataFrame({"t": t, "M": M}), 4.0, 2.0, bins=2)
    >>> bool(np.all(np.abs(table["rate"] - 20.0) < 4 * table["rate_err"]))
    True
    """
    ms = _Mainshocks(events, m_main, window, m_min)
    edges = _edges(bins, *_window(window))
    owner, pos, tau = ms.pairs()
    if radius is not None:
        if graph is None:
            raise InvalidParameterError("radius needs the graph the catalog was simulated on")
        owner, pos, tau, background = _near(ms, graph, owner, pos, tau, float(radius))
    else:
        span = ms.t[-1] - ms.t[0]
        background = float(ms.selected.size / span) if span > 0 else float("nan")
    count = np.histogram(tau, bins=edges)[0]
    expo = ms.exposure(edges)
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = np.where(expo > 0, count / expo, np.nan)
        err = np.where(expo > 0, np.sqrt(count) / expo, np.nan)
    table = pd.DataFrame(
        {
            "t_lo": edges[:-1],
            "t_hi": edges[1:],
            "t": 0.5 * (edges[:-1] + edges[1:]),
            "count": count,
            "exposure": expo,
            "rate": rate,
            "rate_err": err,
        }
    )
    table.attrs["n_mainshocks"] = int(ms.main.size)
    table.attrs["background"] = background
    return table


def _near(ms, graph, owner, pos, tau, radius):
    """Keep the pairs whose event lies within ``radius`` of its mainshock's hypocentre.

    Also returns the background of such a count: the catalog-wide rate of the
    selected events within ``radius`` of each mainshock's hypocentre, averaged
    over the mainshocks.
    """
    from faultnet.seismicity.geometry import geometry

    geo = geometry(graph)
    if "hypocenter" not in ms.events.columns:
        raise InvalidParameterError("events needs a 'hypocenter' column for distances")
    hyp = geo.indices(ms.events["hypocenter"].tolist())
    node_count = np.bincount(hyp[ms.selected], minlength=len(geo.nodes))
    keep = np.zeros(owner.size, bool)
    bounds = np.searchsorted(owner, np.arange(ms.main.size + 1))  # owner is sorted
    near_total = 0.0
    for j in range(ms.main.size):
        d = geo.distances(hyp[ms.main[j]])
        rows = slice(bounds[j], bounds[j + 1])
        keep[rows] = d[hyp[pos[rows]]] <= radius
        near_total += float(node_count[d <= radius].sum())
    span = ms.t[-1] - ms.t[0]
    background = near_total / ms.main.size / span if span > 0 else float("nan")
    return owner[keep], pos[keep], tau[keep], background


def aftershock_times(events, m_main, t_end, m_min=None, side="after", graph=None, radius=None):
    """Pooled times since (or before) mainshocks whose window ``t_end`` is complete.

    Only mainshocks whose next (for ``side="before"``: previous) mainshock and
    the catalog's end (start) lie more than ``t_end`` away are used, so every
    stacked sequence covers the whole window and :func:`fit_omori` with
    ``n_sequences`` applies.  ``graph`` and ``radius`` keep only events near
    the mainshock's hypocentre, as in :func:`stack_mainshocks`.

    Returns
    -------
    times : numpy.ndarray
        ``t - t_main`` after, or ``t_main - t`` before the mainshocks (> 0).
    n_sequences : int
        Mainshocks used.

    Examples
    --------
    >>> import pandas as pd
    >>> ev = pd.DataFrame({"t": [0.0, 1.0, 1.5, 2.0, 9.0, 9.2, 20.0], "M": [0, 5, 0, 0, 5, 0, 0]})
    >>> aftershock_times(ev, m_main=4.0, t_end=3.0)
    (array([0.5, 1. , 0.2]), 2)
    """
    if side not in ("after", "before"):
        raise InvalidParameterError(f"side must be 'after' or 'before'; got {side!r}")
    t_end = float(t_end)
    window = (0.0, t_end) if side == "after" else (t_end, 0.0)
    ms = _Mainshocks(events, m_main, window, m_min)
    full = (ms.hi >= t_end) if side == "after" else (ms.lo <= -t_end)
    owner, pos, tau = ms.pairs()
    if radius is not None:
        if graph is None:
            raise InvalidParameterError("radius needs the graph the catalog was simulated on")
        owner, pos, tau, _ = _near(ms, graph, owner, pos, tau, float(radius))
    sel = full[owner] & ((tau > 0) if side == "after" else (tau < 0))
    return np.abs(tau[sel]), int(full.sum())


def distance_profile(events, graph, m_main, window, bins=10, m_min=None, metric="euclidean"):
    """Activity against distance from the coming mainshock's hypocentre, relative to background.

    For every mainshock (``M >= m_main``) the events with ``M >= m_min`` in
    its window ``[t_main - window[0], t_main - window[1])`` (cut at the
    previous mainshock) are counted by the distance of their hypocentre from
    the mainshock's.  ``expected`` is what the time-averaged activity would
    put there: for each mainshock, the catalog-wide count of events at each
    distance from its hypocentre times the window length over the catalog's
    duration.  ``ratio = count / expected`` below 1 near ``r = 0`` with
    ``ratio >= 1`` further out is a "Mogi doughnut"; 1 everywhere is no
    spatial precursor.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
        Needs the ``hypocenter`` column.
    graph : networkx.Graph, SparseGraph, CarlsonLanger or SimulationResult
        The graph of the run (node ``pos``; periodic rings and lattices
        wrap, see :mod:`faultnet.seismicity.geometry`).
    m_main : float
    window : float or (float, float)
        ``before`` or ``(before, gap)``: the time window ``[-before, -gap)``
        relative to the mainshock (``gap = 0`` by default).
    bins : int or array_like
        Distance bins: a number of equal bins up to the largest distance, or
        edges.
    m_min : float, optional
    metric : {"euclidean", "graph"}
        Distances through ``pos`` (minimum image on periodic boxes, arc length
        on rings) or shortest-path hops on the graph.

    Returns
    -------
    pandas.DataFrame
        ``r_lo``, ``r_hi``, ``r``, ``count``, ``expected``, ``ratio``,
        ``ratio_err`` (``sqrt(count) / expected``); ``attrs["n_mainshocks"]``.
    """
    from faultnet.seismicity.geometry import METRICS, geometry

    if metric not in METRICS:
        raise InvalidParameterError(f"metric must be one of {METRICS}; got {metric!r}")
    before, gap = (float(window), 0.0) if np.ndim(window) == 0 else map(float, window)
    if not (before > gap >= 0):
        raise InvalidParameterError(f"window needs before > gap >= 0; got {window!r}")
    ms = _Mainshocks(events, m_main, (before, 0.0), m_min)
    geo = geometry(graph)
    if "hypocenter" not in ms.events.columns:
        raise InvalidParameterError("events needs a 'hypocenter' column for distances")
    hyp = geo.indices(ms.events["hypocenter"].tolist())
    owner, pos, tau = ms.pairs()
    keep = tau < -gap
    owner, pos = owner[keep], pos[keep]
    node_count = np.bincount(hyp[ms.selected], minlength=len(geo.nodes))
    span = ms.t[-1] - ms.t[0]
    expo = np.clip(-gap - ms.lo, 0.0, None)
    dists, per_main = [], []
    bounds = np.searchsorted(owner, np.arange(ms.main.size + 1))  # owner is sorted
    for j in range(ms.main.size):
        d = geo.distances(hyp[ms.main[j]], metric)
        per_main.append(d)
        dists.append(d[hyp[pos[bounds[j] : bounds[j + 1]]]])
    d_all = np.concatenate(dists) if dists else np.zeros(0)
    finite_max = max(float(np.max(d[np.isfinite(d)])) for d in per_main)
    if np.ndim(bins) == 0:
        edges = np.linspace(0.0, finite_max * (1 + 1e-9), int(bins) + 1)
    else:
        edges = np.asarray(bins, dtype=np.float64)
        if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0):
            raise InvalidParameterError("bins: distance edges must increase (>= 2 values)")
    count = np.histogram(d_all, bins=edges)[0]
    expected = np.zeros(edges.size - 1)
    for j, d in enumerate(per_main):
        ok = np.isfinite(d)
        expected += np.histogram(d[ok], bins=edges, weights=node_count[ok])[0] * expo[j] / span
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(expected > 0, count / expected, np.nan)
        err = np.where(expected > 0, np.sqrt(count) / expected, np.nan)
    table = pd.DataFrame(
        {
            "r_lo": edges[:-1],
            "r_hi": edges[1:],
            "r": 0.5 * (edges[:-1] + edges[1:]),
            "count": count,
            "expected": expected,
            "ratio": ratio,
            "ratio_err": err,
        }
    )
    table.attrs["n_mainshocks"] = int(ms.main.size)
    return table


def b_around_mainshocks(events, m_main, window, m_min, graph=None, radius=None):
    """Aki b of the events before and after mainshocks (pooled, windows cut as in stacking).

    Parameters
    ----------
    events, m_main, window, graph, radius
        As in :func:`stack_mainshocks` (``radius`` keeps events near the
        mainshock's hypocentre).
    m_min : float
        Completeness magnitude of the fits.

    Returns
    -------
    dict
        ``{"before": BFit, "after": BFit, "all": BFit}`` (``all``: the whole
        catalog above ``m_min``, for reference); a side with fewer than 2
        events is None.
    """
    ms = _Mainshocks(events, m_main, window, m_min)
    owner, pos, tau = ms.pairs()
    if radius is not None:
        if graph is None:
            raise InvalidParameterError("radius needs the graph the catalog was simulated on")
        owner, pos, tau, _ = _near(ms, graph, owner, pos, tau, float(radius))
    out: dict[str, BFit | None] = {}
    for side, rows in (("before", pos[tau < 0]), ("after", pos[tau > 0])):
        try:
            out[side] = fit_b_mle(ms.M[rows], m_min=m_min)
        except ValueError:
            out[side] = None
    out["all"] = fit_b_mle(ms.M, m_min=m_min)
    return out
