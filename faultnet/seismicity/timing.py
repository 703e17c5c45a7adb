r"""Statistical seismology of synthetic catalogs: waiting times, recurrence, fore/aftershocks.

Every function works on an events DataFrame (``result.events``: columns ``t``
= plate time, ``M = ln S``, ``hypocenter``; or a :class:`~faultnet.SimulationResult`)
and, for spatial questions, on the graph the catalog was simulated on (node
``pos``; periodic rings and lattices are recognised, see
:func:`faultnet.seismicity.geometry`).  Nothing here needs more than the catalog:
the hypocentre position comes from the graph, the rupture extent is the
``n_blocks`` column.

* :func:`interevent_times` -- waiting times, optionally rescaled by the mean
  rate (Corral 2004); Poisson events give an exponential law.
* :func:`recurrence` -- intervals between large events, system-wide or at a
  set of blocks, and their coefficient of variation (periodic 0, Poisson 1).
* :func:`stack_mainshocks` -- the event rate against time from mainshocks,
  stacked, with counting errors; :func:`aftershock_times` and
  :func:`~faultnet.seismicity.fit_omori` give the Omori-Utsu decay.
* :func:`distance_profile` -- activity against distance from the coming
  mainshock's hypocentre, relative to the background (quiescence, "Mogi
  doughnut").
* :func:`geometry` -- node positions, periodic boxes and distances of a graph.
* :func:`b_series` and :func:`b_around_mainshocks` -- the b-value (MLE, the
  paper's ``P(M) ~ exp(-b M)``) in sliding windows and before/after mainshocks.

The bridge to SeismoStats, powerlaw and QuakeML is :mod:`faultnet.seismicity.ecosystem`
(re-exported here: :func:`to_seismostats`, :func:`to_quakeml`, :func:`compare_b`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from faultnet.exceptions import InvalidParameterError
from faultnet.seismicity.mainshocks import (
    _events,
    _threshold,
)
from faultnet.stats.magnitudes import fit_b_mle, format_pm

__all__ = ["Recurrence", "b_series", "interevent_times", "recurrence"]


def interevent_times(events, m_min=None, rescale=False):
    """Waiting times (plate time) between consecutive events with ``M >= m_min``.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
    m_min : float, optional
        Magnitude threshold (``M = ln S``); default every event.
    rescale : bool, optional
        Corral's rescaling: multiply by the mean rate ``R = 1 / mean(tau)`` so
        that catalogs and thresholds compare on one axis; a Poisson process
        gives ``P(theta) = exp(-theta)``.

    Returns
    -------
    numpy.ndarray

    Examples
    --------
    >>> import numpy as np, pandas as pd
    >>> t = np.cumsum(np.random.default_rng(0).exponential(2.0, 20_000))
    >>> tau = interevent_times(pd.DataFrame({"t": t, "M": np.zeros_like(t)}), rescale=True)
    >>> round(float(tau.mean()), 6), bool(abs(tau.std() - 1.0) < 0.03)
    (1.0, True)
    """
    ev = _events(events)
    M = ev["M"].to_numpy(dtype=np.float64)
    t = ev["t"].to_numpy(dtype=np.float64)[_threshold(M, m_min)]
    if t.size < 2:
        raise InvalidParameterError(
            f"interevent_times needs at least 2 events with M >= m_min={m_min!r}; got {t.size}"
        )
    tau = np.diff(t)
    if rescale:
        mean = tau.mean()
        if mean <= 0:
            raise InvalidParameterError("all selected events occur at one time: no rate")
        tau = tau / mean
    return tau


@dataclass(frozen=True)
class Recurrence:
    """Recurrence intervals of large events and their coefficient of variation.

    Attributes
    ----------
    intervals : numpy.ndarray
        Plate time between consecutive selected events.
    mean, std : float
        Their mean and standard deviation (``ddof=1``).
    cv, cv_err : float
        ``std / mean`` (0 periodic, 1 Poisson, > 1 clustered) and its
        delta-method standard error from the sample moments (``1/sqrt(n)`` for
        exponential intervals).
    n : int
        Number of intervals.
    """

    intervals: np.ndarray
    mean: float
    std: float
    cv: float
    cv_err: float
    n: int

    def __repr__(self):
        return (
            f"Recurrence(n={self.n} intervals, mean={self.mean:.4g}, std={self.std:.4g}, "
            f"cv={format_pm(self.cv, self.cv_err, pm=' +/- ')})"
        )

    __str__ = __repr__


def _cv_and_error(x):
    n = x.size
    m, s2 = x.mean(), x.var(ddof=1)
    s = math.sqrt(s2)
    cv = s / m
    if s == 0.0:
        return 0.0, 0.0
    dev = x - m
    mu3, mu4 = float(np.mean(dev**3)), float(np.mean(dev**4))
    # delta method on CV = sqrt(s2) / m with Var(m) = s2/n, Var(s2) = (mu4 - s2^2)/n,
    # Cov(m, s2) = mu3/n
    var = ((mu4 - s2**2) / (4.0 * s2 * m**2) + s2**2 / m**4 - mu3 / m**3) / n
    return cv, math.sqrt(max(var, 0.0))


def recurrence(events, m_min, where=None, slips=None):
    """Intervals between events with ``M >= m_min``, system-wide or at some blocks.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
    m_min : float
        Magnitude of the "large" events.
    where : node label or collection of node labels, optional
        Count only events at these blocks: whose hypocentre is one of them, or,
        with ``slips``, in which one of them slipped (the rupture reached the
        place).  One label may be given alone (also a lattice's ``(i, j)``).
        Default: every large event (system-wide recurrence).
    slips : pandas.DataFrame, optional
        ``result.slips`` (``simulate(..., record_slips=True)``).

    Returns
    -------
    Recurrence

    Examples
    --------
    >>> import pandas as pd
    >>> ev = pd.DataFrame({"t": [0.0, 2.0, 4.0, 6.0], "M": [3.0, 3.0, 3.0, 3.0]})
    >>> r = recurrence(ev, m_min=1.0)
    >>> r.mean, r.cv, r.n
    (2.0, 0.0, 3)
    """
    ev = _events(events)
    big = ev[ev["M"].to_numpy() >= float(m_min)]
    if where is not None:
        labels = slips["node"] if slips is not None else ev["hypocenter"]
        where = _blocks(where, labels)
        if slips is not None:
            hit = slips.loc[slips["node"].isin(where), "event"].unique()
            big = big[big["event"].isin(hit)]
        else:
            big = big[big["hypocenter"].isin(where)]
    t = big["t"].to_numpy(dtype=np.float64)
    if t.size < 3:
        raise InvalidParameterError(
            f"recurrence needs at least 3 events with M >= {m_min!r}"
            f"{' at the given blocks' if where is not None else ''}; got {t.size}"
        )
    x = np.diff(t)
    cv, cv_err = _cv_and_error(x)
    return Recurrence(x, float(x.mean()), float(x.std(ddof=1)), float(cv), float(cv_err), x.size)


def _blocks(where, labels):
    """The set of block labels ``where`` names (one label, or a collection of them).

    A tuple that has the shape of the catalog's tuple labels is one label, not a collection;
    labels that no event has are an error, not an empty selection.
    """
    sample = labels.iloc[0] if len(labels) else None
    one_tuple = (
        isinstance(where, tuple)
        and isinstance(sample, tuple)
        and len(where) == len(sample)
        and not any(isinstance(w, tuple) for w in where)
    )
    if one_tuple or isinstance(where, (str, bytes)) or not hasattr(where, "__iter__"):
        blocks = {where}
    else:
        blocks = set(where)
    if not blocks & set(labels):
        raise InvalidParameterError(
            f"where: no event has any of the blocks {sorted(blocks, key=repr)[:5]!r} "
            f"(the catalog's block labels look like {sample!r})"
        )
    return blocks


# --------------------------------------------------------------------------- b-values


def b_series(events, window=500, step=None, m_min=None):
    """Aki b (MLE, ``P(M) ~ exp(-b M)``) in sliding windows of ``window`` events.

    Parameters
    ----------
    events : pandas.DataFrame or SimulationResult
    window : int
        Events (with ``M >= m_min``) per window.
    step : int, optional
        Events between window starts (default ``window // 4``).
    m_min : float, optional
        Completeness magnitude; default the maximum-curvature estimate of the
        whole catalog (as :func:`faultnet.stats.fit_b_mle`), used for every window.

    Returns
    -------
    pandas.DataFrame
        ``t_start``, ``t_end`` (times of the first and last event), ``t``
        (their mean), ``b``, ``b_err`` (``b / sqrt(n)``), ``n``;
        ``attrs["m_min"]``.

    Examples
    --------
    >>> import numpy as np, pandas as pd
    >>> M = np.random.default_rng(3).exponential(1 / 0.5, 4000)
    >>> table = b_series(pd.DataFrame({"t": np.arange(4000.0), "M": M}), 1000, m_min=0.0)
    >>> len(table), bool(np.all(np.abs(table["b"] - 0.5) < 4 * table["b_err"]))
    (13, True)
    """
    ev = _events(events)
    M = ev["M"].to_numpy(dtype=np.float64)
    if m_min is None:
        m_min = fit_b_mle(M[np.isfinite(M)]).m_min
    m_min = float(m_min)
    sel = np.isfinite(M) & (M >= m_min)
    m, t = M[sel], ev["t"].to_numpy(dtype=np.float64)[sel]
    window = int(window)
    step = max(1, window // 4) if step is None else int(step)
    if window < 2 or step < 1:
        raise InvalidParameterError(f"need window >= 2 and step >= 1; got {window}, {step}")
    if m.size < window:
        raise InvalidParameterError(
            f"b_series: {m.size} events with M >= {m_min:g}, fewer than window={window}"
        )
    starts = np.arange(0, m.size - window + 1, step)
    csum = np.concatenate([[0.0], np.cumsum(m - m_min)])
    excess = (csum[starts + window] - csum[starts]) / window
    with np.errstate(divide="ignore"):
        b = 1.0 / excess
    table = pd.DataFrame(
        {
            "t_start": t[starts],
            "t_end": t[starts + window - 1],
            "t": 0.5 * (t[starts] + t[starts + window - 1]),
            "b": b,
            "b_err": b / math.sqrt(window),
            "n": window,
        }
    )
    table.attrs["m_min"] = m_min
    return table
