"""Matplotlib views of :mod:`faultnet.seismicity.timing` results.

Each function draws on ``ax`` (a new figure when None) and returns the Axes;
matplotlib is imported inside the functions.

Examples
--------
>>> import matplotlib
>>> matplotlib.use("Agg")
>>> import numpy as np, pandas as pd
>>> from faultnet import plotting, seismicity as fs
>>> t = np.cumsum(np.random.default_rng(0).exponential(1.0, 5000))
>>> ax = plotting.plot_interevent_times(fs.interevent_times(pd.DataFrame({"t": t, "M": 0.0}),
...                                                   rescale=True), label="Poisson")
>>> ax.get_xscale(), ax.get_yscale()
('log', 'log')
"""

from __future__ import annotations

import numpy as np

from faultnet._validate import check_columns
from faultnet.plotting.figures import _axes

__all__ = ["plot_distance_profile", "plot_interevent_times", "plot_stack"]

_THETA_EDGES = np.logspace(-5, 2, 36)


def plot_interevent_times(theta, ax=None, bins=None, label=None, poisson=True, **kw):
    """Density of rescaled waiting times ``theta = tau / <tau>`` on log axes, vs ``exp(-theta)``.

    Parameters
    ----------
    theta : array_like or (edges, counts)
        Rescaled waiting times (:func:`faultnet.seismicity.interevent_times`
        with ``rescale=True``), or a histogram of them.
    ax : matplotlib.axes.Axes, optional
    bins : array_like, optional
        Edges for raw input (default 35 log-spaced bins over 1e-5..1e2).
    label : str, optional
    poisson : bool
        Draw the exponential law of a Poisson process (dashed).
    **kw
        Passed to ``ax.plot`` (default ``marker="o"``).

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    if isinstance(theta, tuple):
        edges, counts = (np.asarray(a, dtype=np.float64) for a in theta)
    else:
        edges = _THETA_EDGES if bins is None else np.asarray(bins, dtype=np.float64)
        counts = np.histogram(np.asarray(theta, dtype=np.float64), bins=edges)[0].astype(float)
    width = np.diff(edges)
    centre = np.sqrt(edges[:-1] * edges[1:])
    density = counts / (counts.sum() * width)
    kw.setdefault("marker", "o")
    kw.setdefault("markersize", 3)
    ax.plot(centre, np.where(counts > 0, density, np.nan), label=label, **kw)
    if poisson:  # drawn down to a tenth of the lowest density shown, not to exp(-100)
        shown = density[counts > 0]
        floor = shown.min() / 10.0 if shown.size else 1e-6
        x = np.logspace(np.log10(edges[0]), np.log10(edges[-1]), 200)
        x = x[np.exp(-x) >= floor]
        ax.plot(x, np.exp(-x), "k--", lw=1, label="Poisson: exp(-theta)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"rescaled waiting time $\theta = \tau / \langle\tau\rangle$")
    ax.set_ylabel(r"$P(\theta)$")
    return ax


def plot_stack(table, ax=None, normalise=True, label=None, symlog=1e-4, **kw):
    """Stacked rate around mainshocks (:func:`faultnet.seismicity.stack_mainshocks`).

    Parameters
    ----------
    table : pandas.DataFrame
        Columns ``t_lo``, ``t_hi``, ``rate``, ``rate_err`` (and
        ``attrs["background"]`` for ``normalise``).
    normalise : bool
        Divide by ``table.attrs["background"]`` (1 = the catalog's mean rate,
        or near the hypocentres for a stack with a radius).
    symlog : float or None
        Linear threshold of a symmetric-log time axis (log-spaced bins on
        both sides of the mainshock); None for a linear axis.

    Returns
    -------
    matplotlib.axes.Axes
    """
    check_columns("table", table, ("t_lo", "t_hi", "rate", "rate_err"), "stack_mainshocks")
    ax = _axes(ax)
    scale = table.attrs.get("background", 1.0) if normalise else 1.0
    centre = 0.5 * (table["t_lo"] + table["t_hi"])
    ok = table["exposure"] > 0 if "exposure" in table else np.ones(len(table), bool)
    kw.setdefault("marker", "o")
    kw.setdefault("markersize", 3)
    kw.setdefault("capsize", 2)
    ax.errorbar(
        centre[ok],
        table["rate"][ok] / scale,
        yerr=table["rate_err"][ok] / scale,
        label=label,
        **kw,
    )
    ax.axvline(0.0, color="k", lw=0.8)
    if normalise:
        ax.axhline(1.0, color="0.5", lw=0.8, ls=":")
    if symlog:
        ax.set_xscale("symlog", linthresh=symlog)
    ax.set_xlabel("time from mainshock (plate time)")
    ax.set_ylabel("rate / background rate" if normalise else "events per unit time")
    return ax


def plot_distance_profile(table, ax=None, label=None, **kw):
    """Activity before mainshocks against distance (:func:`faultnet.seismicity.distance_profile`).

    Draws ``ratio = count / expected`` with Poisson errors on a log distance
    axis; 1 is the time-averaged activity at that distance.

    Returns
    -------
    matplotlib.axes.Axes
    """
    check_columns("table", table, ("r_lo", "r_hi", "ratio", "ratio_err"), "distance_profile")
    ax = _axes(ax)
    r = np.sqrt(np.maximum(table["r_lo"], 0.5) * table["r_hi"])
    kw.setdefault("marker", "o")
    kw.setdefault("markersize", 3)
    kw.setdefault("capsize", 2)
    ax.errorbar(r, table["ratio"], yerr=table["ratio_err"], label=label, **kw)
    ax.axhline(1.0, color="0.5", lw=0.8, ls=":")
    ax.set_xscale("log")
    ax.set_xlabel("distance from the coming mainshock's hypocentre")
    ax.set_ylabel("activity / time-averaged activity")
    return ax
