"""Matplotlib views of catalogs, slip profiles, time series and return maps.

Every function draws on ``ax`` (a new figure when None) and returns the Axes.
Matplotlib is imported inside the functions, so ``import faultnet.plotting.figures`` is
cheap and ``import faultnet`` never pulls it in.

Examples
--------
>>> import matplotlib
>>> matplotlib.use("Agg")
>>> import numpy as np
>>> from faultnet import plotting
>>> from faultnet.stats.magnitudes import fit_b_mle
>>> M = np.random.default_rng(0).exponential(1 / 0.67, 5000) - 3.0
>>> ax = plotting.plot_magnitude_distribution(M, fit=fit_b_mle(M, -3.0), label="synthetic")
>>> ax.get_yscale()
'log'
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from faultnet._validate import check_columns
from faultnet.exceptions import InvalidParameterError

__all__ = [
    "plot_magnitude_distribution",
    "plot_profiles",
    "plot_return_map",
    "plot_time_series",
]


def _axes(ax):
    """``ax``, or the Axes of a new figure (every plot of the package draws through this)."""
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots()
    return ax


def plot_magnitude_distribution(M_or_table, fit=None, ax=None, label=None, bins=50, **kw):
    """Magnitude density ``P(M)`` on a log axis, with an optional fitted line.

    Parameters
    ----------
    M_or_table : array_like, pandas.DataFrame or SimulationResult
        Magnitudes, an events DataFrame (or a result), or a table from
        :func:`faultnet.stats.magnitude_distribution` (columns ``M``, ``density``).
    fit : faultnet.stats.BFit, optional
        Draws ``A exp(-b M)`` (dashed) over ``[fit.m_min, fit.m_max]``, with
        ``A`` chosen so the line holds the probability the histogram has there.
    ax : matplotlib.axes.Axes, optional
    label : str, optional
        Legend label of the data.
    bins : int, sequence or str
        Passed to :func:`~faultnet.stats.magnitude_distribution` for raw input.
    **kw
        Passed to ``ax.plot`` for the data (default ``marker="o"``).

    Returns
    -------
    matplotlib.axes.Axes
    """
    from faultnet.stats.magnitudes import format_pm, magnitude_distribution

    ax = _axes(ax)
    table = M_or_table
    if not (isinstance(table, pd.DataFrame) and {"M", "density"} <= set(table.columns)):
        table = magnitude_distribution(M_or_table, bins=bins)
    # empty bins become gaps (NaN) so the line does not bridge sparse tails
    shown = table.assign(density=table["density"].where(table["density"] > 0))
    kw.setdefault("marker", "o")
    kw.setdefault("markersize", 3)
    (line,) = ax.plot(shown["M"], shown["density"], label=label, **kw)
    if fit is not None:
        m = np.linspace(fit.m_min, fit.m_max, 100)
        centres = table["M"].to_numpy()
        inside = (centres >= fit.m_min) & (centres <= fit.m_max)
        widths = table["width"].to_numpy() if "width" in table else np.gradient(centres)
        mass = float(np.sum(table["density"].to_numpy()[inside] * widths[inside]))
        lo, hi = (centres[inside].min(), centres[inside].max()) if inside.any() else (0, 0)
        if fit.b > 0 and mass > 0 and hi > lo:
            # A * integral of exp(-b M) over the window's bins = mass
            half = 0.5 * widths[inside]
            integral = np.sum(
                (
                    np.exp(-fit.b * (centres[inside] - half))
                    - np.exp(-fit.b * (centres[inside] + half))
                )
                / fit.b
            )
            ax.plot(
                m,
                mass / integral * np.exp(-fit.b * m),
                linestyle="--",
                color=line.get_color(),
                label=f"b = {format_pm(fit.b, fit.b_err, decimals=2)}",
            )
    ax.set_yscale("log")
    ax.set_xlabel("M = ln S")
    ax.set_ylabel("P(M)")
    if label is not None or fit is not None:
        ax.legend()
    return ax


def plot_profiles(profiles, t=None, ax=None, subtract_mean=False, cmap="viridis"):
    """Space-time image of the displacements ``x_i`` after each event.

    Parameters
    ----------
    profiles : array_like or SimulationResult
        Shape ``(n_events, N)``, e.g. ``result.profiles`` (or the result itself, simulated
        with ``record_profiles=True``).
    t : array_like, optional
        Event start times (``result.events["t"]``): row ``i`` is then drawn
        from ``t[i]`` to ``t[i + 1]``, the interval it holds.  Default: event
        index.
    ax : matplotlib.axes.Axes, optional
    subtract_mean : bool, optional
        Show ``x_i - mean_j x_j`` per row, removing the plate drift.
    cmap : str, optional

    Returns
    -------
    matplotlib.axes.Axes
        With a colour bar; block index on x, event or time on y.
    """
    from faultnet.stats.irregularity import profiles_of

    x = np.asarray(profiles_of(profiles, "profiles")[0], dtype=np.float64)
    if x.ndim != 2 or 0 in x.shape:
        raise InvalidParameterError(f"profiles must have shape (n_events, N); got {x.shape}")
    if subtract_mean:
        x = x - x.mean(axis=1, keepdims=True)
    ax = _axes(ax)
    n_events, n = x.shape
    if t is None:
        image = ax.imshow(
            x,
            aspect="auto",
            origin="lower",
            interpolation="nearest",
            cmap=cmap,
            extent=(-0.5, n - 0.5, -0.5, n_events - 0.5),
        )
        ax.set_ylabel("event")
    else:
        t = np.asarray(t, dtype=np.float64)
        if t.shape != (n_events,):
            raise InvalidParameterError(
                f"t must have one entry per profile ({n_events}); got {t.shape}"
            )
        last = t[-1] - t[-2] if n_events > 1 else 1.0
        edges = np.append(t, t[-1] + (last if last > 0 else 1.0))
        image = ax.pcolormesh(np.arange(n + 1) - 0.5, edges, x, cmap=cmap, shading="flat")
        ax.set_ylabel("t")
    ax.set_xlabel("block i")
    ax.figure.colorbar(image, ax=ax, label="x_i - <x>" if subtract_mean else "x_i")
    return ax


def plot_time_series(t, values, ax=None, kind="S", **kw):
    """Slip sizes ``S(t)`` as vertical lines, or the irregularity ``Delta(t)`` as a line.

    Parameters
    ----------
    t, values : array_like
        Event times and ``S`` (``kind="S"``) or ``Delta`` after each event
        (``kind="delta"``, drawn as a step held until the next event).
    ax : matplotlib.axes.Axes, optional
    kind : {"S", "delta"}
    **kw
        Passed to ``ax.vlines`` or ``ax.plot``.

    Returns
    -------
    matplotlib.axes.Axes
    """
    t = np.asarray(t, dtype=np.float64)
    values = np.asarray(values, dtype=np.float64)
    if t.shape != values.shape or t.ndim != 1:
        raise InvalidParameterError(
            f"t and values must be 1-D of equal length; got {t.shape}, {values.shape}"
        )
    ax = _axes(ax)
    if kind == "S":
        ax.vlines(t, 0.0, values, **kw)
        ax.set_ylabel("S")
        ax.set_ylim(bottom=0.0)
    elif kind == "delta":
        kw.setdefault("drawstyle", "steps-post")
        ax.plot(t, values, **kw)
        ax.set_ylabel("Δ")
    else:
        raise InvalidParameterError(f"kind must be 'S' or 'delta'; got {kind!r}")
    ax.set_xlabel("t")
    return ax


def plot_return_map(table, ax=None, **kw):
    """Two-block return map ``x2 - x1 -> x2' - x1'`` with the lines ``d' = d`` and ``d' = -d``.

    Parameters
    ----------
    table : pandas.DataFrame
        From :func:`faultnet.solver.dynamics.return_map` (columns ``d``, ``d_next``).
    ax : matplotlib.axes.Axes, optional
    **kw
        Passed to ``ax.scatter`` (default ``s=6``).

    Returns
    -------
    matplotlib.axes.Axes
    """
    check_columns("table", table, ("d", "d_next"), "faultnet.solver.dynamics.return_map")
    ax = _axes(ax)
    d = np.asarray(table["d"], dtype=np.float64)
    d_next = np.asarray(table["d_next"], dtype=np.float64)
    kw.setdefault("s", 6)
    ax.scatter(d, d_next, label="map", zorder=3, **kw)
    lim = float(np.max(np.abs(d))) if d.size else 1.0
    span = np.array([-lim, lim])
    ax.plot(span, span, color="0.5", linestyle=":", label="d' = d")
    ax.plot(span, -span, color="0.5", linestyle="--", label="d' = -d")
    ax.set_xlabel("x2 - x1")
    ax.set_ylabel("x2' - x1'")
    ax.legend()
    return ax
