r"""Event statistics: magnitude distributions, b-value fits, spatial irregularity.

Conventions for the exponent ``b``
----------------------------------
faultnet follows Sakaguchi & Morita (2013): the magnitude of an event is the
natural logarithm of its total slip, ``M = ln S`` (the ``M`` column of
``result.events``), and ``b`` is the exponent of the magnitude density in
natural-log units,

.. math:: P(M) \propto e^{-bM}.

Changing variables (``dM = dS / S``) gives ``P(S) \propto S^{-(1+b)}`` and a
cumulative (Gutenberg-Richter) count ``N(\ge S) \propto S^{-b}``.  Other
conventions for the same catalogue:

* log10 magnitudes of the slip (moment-like), ``m = log10 S``:
  ``N(\ge m) \propto S^{-b} = 10^{-b m}``, so ``P(m) \propto 10^{-b m}`` and
  ``b10 = b`` -- the same number, because
  ``e^{-b ln S} = S^{-b} = 10^{-b log10 S}``.
* seismological moment magnitude ``Mw = (2/3) log10 M0 + const`` with
  ``M0 \propto S``: ``log10 S = 1.5 Mw + const`` so ``N(\ge Mw) \propto
  10^{-1.5 b Mw}`` and ``b_GR = 1.5 b`` (the paper's ``b = 2/3`` is
  ``b_GR = 1``).
* ``powerlaw`` (Alstott et al.) fits ``P(S) \propto S^{-alpha}``:
  ``alpha = 1 + b``.
* ``seismostats`` writes ``P(m) \propto e^{-beta m}`` for its (log10)
  magnitudes, ``beta = b_value ln 10``.  Given ``m = log10 S`` its b-value is
  ``b`` and ``beta = b ln 10``; given ``M = ln S`` directly its ``beta`` is
  ``b`` (and its "b-value" ``b / ln 10``).

The spatial irregularity :func:`irregularity` is Eq. (13) of the paper.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from faultnet.exceptions import InvalidParameterError

__all__ = [
    "BFit",
    "fit_b_lsq",
    "fit_b_mle",
    "format_pm",
    "magnitude_distribution",
]

_DEFAULT_BINS = 50
_CHUNK_VALUES = 4_000_000  # |x_i - x_j| values held at once by irregularity()


def format_pm(value, err, decimals=3, pm=" ± "):
    """``value`` and its error ``err`` with ``decimals`` decimals, or as many more as show
    the error's first digit (never "± 0.000").

    >>> format_pm(0.4621, 0.0083), format_pm(0.46213, 0.00031), format_pm(1.0, float("nan"))
    ('0.462 ± 0.008', '0.4621 ± 0.0003', '1.000 ± nan')
    """
    if math.isfinite(err) and err > 0:
        decimals = max(decimals, -math.floor(math.log10(err)))
    return f"{value:.{decimals}f}{pm}{err:.{decimals}f}"


def _magnitudes(M, name="M"):
    """Finite magnitudes as a float array from an array, Series, events DataFrame or result."""
    if hasattr(M, "events") and hasattr(M, "model"):  # a SimulationResult
        M = M.events
    if isinstance(M, pd.DataFrame):
        if "M" in M.columns:
            M = M["M"]
        elif "S" in M.columns:
            with np.errstate(divide="ignore", invalid="ignore"):
                M = np.log(np.asarray(M["S"], dtype=np.float64))
        else:
            raise InvalidParameterError(
                f"{name}: DataFrame needs an 'M' or 'S' column; got {list(M.columns)}"
            )
    arr = np.asarray(M, dtype=np.float64).ravel()
    return arr[np.isfinite(arr)]


@dataclass(frozen=True)
class BFit:
    """Result of a b-value fit (``P(M) ~ exp(-b M)``, ``M = ln S``).

    Attributes
    ----------
    b, b_err : float
        Exponent in natural-log magnitude units and its standard error.
    m_min, m_max : float
        Magnitude window of the fit.
    n : int
        Number of events inside the window.
    method : str
        ``"lsq"``, ``"wlsq"``, ``"mle"`` or ``"mle-unbiased"``.
    """

    b: float
    b_err: float
    m_min: float
    m_max: float
    n: int
    method: str

    @property
    def b_gr(self) -> float:
        """Gutenberg-Richter b for moment magnitudes ``Mw = (2/3) log10 S + c``: ``1.5 b``."""
        return 1.5 * self.b

    @property
    def powerlaw_alpha(self) -> float:
        """Exponent of the slip density ``P(S) ~ S^-alpha``: ``1 + b``."""
        return 1.0 + self.b

    def __str__(self):
        return (
            f"b = {format_pm(self.b, self.b_err, pm=' +/- ')} ({self.method}, "
            f"M in [{self.m_min:.3g}, {self.m_max:.3g}], n = {self.n})"
        )


def magnitude_distribution(M, bins=_DEFAULT_BINS, range=None):
    """Histogram estimate of the magnitude density ``P(M)``.

    Parameters
    ----------
    M : array_like, pandas.DataFrame or SimulationResult
        Magnitudes ``M = ln S``, or an events DataFrame (its ``M`` column, else
        ``ln S``) or a result (its events).  Non-finite values are dropped.
    bins : int, sequence or str, optional
        As in :func:`numpy.histogram` (default 50 equal bins).
    range : (float, float), optional
        Lower and upper edge; default the range of the data.

    Returns
    -------
    pandas.DataFrame
        Columns ``M`` (bin centre), ``density``, ``count`` and ``width``.
        ``density = count / (n * width)`` with ``n`` the number of all finite
        magnitudes, so ``sum(density * width) = 1`` when the bins cover every
        event, and a narrower ``range`` keeps the densities of the full
        catalogue.  ``attrs["n"]`` holds ``n``.

    Examples
    --------
    >>> import numpy as np
    >>> M = np.random.default_rng(0).exponential(1 / 0.5, 10_000)
    >>> table = magnitude_distribution(M, bins=20)
    >>> float(round((table["density"] * table["width"]).sum(), 12))
    1.0
    """
    m = _magnitudes(M)
    if m.size == 0:
        raise InvalidParameterError("magnitude_distribution needs at least one finite magnitude")
    count, edges = np.histogram(m, bins=bins, range=range)
    width = np.diff(edges)
    table = pd.DataFrame(
        {
            "M": 0.5 * (edges[:-1] + edges[1:]),
            "density": count / (m.size * width),
            "count": count.astype(np.int64),
            "width": width,
        }
    )
    table.attrs["n"] = int(m.size)
    return table


def _check_window(m_min, m_max):
    if not (math.isfinite(m_min) and math.isfinite(m_max)):
        raise InvalidParameterError(
            f"fit window must be finite; got m_min={m_min!r}, m_max={m_max!r}"
        )
    if m_min >= m_max:
        raise InvalidParameterError(
            f"fit window is empty: need m_min < m_max; got {m_min!r} >= {m_max!r}"
        )


def fit_b_lsq(M, m_min, m_max, bins=20, weighted=False):
    """Least-squares b on ``ln P(M)`` over ``[m_min, m_max]`` (the paper's method).

    The magnitudes inside the window are binned (``bins`` equal bins spanning
    the window, or explicit edges), empty bins are ignored, and a straight line
    ``ln P = a - b M`` is fitted to the bin centres.  With equal bins the
    centring does not bias the slope of an exponential.

    ``b`` is the paper's exponent: ``P(M) ~ exp(-b M)`` with ``M = ln S``, so
    ``N(>= S) ~ S^-b`` and ``P(S) ~ S^-(1+b)``.  The same number is the b of
    log10 slip magnitudes; ``b_GR = 1.5 b`` for moment magnitudes ``Mw``
    (module docstring).

    Parameters
    ----------
    M : array_like, pandas.DataFrame or SimulationResult
        Magnitudes ``M = ln S``, an events DataFrame or a result (its events).
    m_min, m_max : float
        Fit window (the paper: -6..3 on the ring, -7..4 on the square lattice).
    bins : int or sequence, optional
        Number of equal bins across the window (default 20), or increasing bin
        edges inside the window.
    weighted : bool, optional
        Weight each bin by its count (inverse Poisson variance of ``ln count``);
        the paper's fit is unweighted.

    Returns
    -------
    BFit
        ``b_err`` is the standard error of the slope from the residuals
        (``sqrt(RSS / (k - 2) / Sxx)`` for ``k`` non-empty bins).

    Raises
    ------
    ValueError
        For an empty or non-finite window or fewer than 3 non-empty bins.

    Examples
    --------
    >>> import numpy as np
    >>> M = np.random.default_rng(1).exponential(1 / 0.67, 50_000)
    >>> fit = fit_b_lsq(M, 0.0, 6.0)
    >>> abs(fit.b - 0.67) < 3 * fit.b_err
    True
    """
    m_min, m_max = float(m_min), float(m_max)
    _check_window(m_min, m_max)
    m = _magnitudes(M)
    if np.ndim(bins) == 0:
        if int(bins) < 3:
            raise InvalidParameterError(
                f"fit_b_lsq needs bins >= 3 to estimate a slope and its error; got {bins}"
            )
        edges = np.linspace(m_min, m_max, int(bins) + 1)
    else:
        edges = np.asarray(bins, dtype=np.float64)
        if edges.min() < m_min or edges.max() > m_max or np.any(np.diff(edges) <= 0):
            raise InvalidParameterError(
                f"fit_b_lsq: bin edges must increase and lie inside [{m_min:g}, {m_max:g}]"
            )
    count, edges = np.histogram(m, bins=edges)
    keep = count > 0
    if keep.sum() < 3:
        raise InvalidParameterError(
            f"fit_b_lsq: only {int(keep.sum())} non-empty bins in [{m_min:g}, {m_max:g}] "
            f"({int(count.sum())} events); need at least 3 -- widen the window or use more events"
        )
    width = np.diff(edges)
    x = 0.5 * (edges[:-1] + edges[1:])[keep]
    y = np.log(count[keep] / (m.size * width[keep]))
    w = count[keep].astype(np.float64) if weighted else np.ones_like(x)
    xm = np.sum(w * x) / np.sum(w)
    ym = np.sum(w * y) / np.sum(w)
    sxx = np.sum(w * (x - xm) ** 2)
    slope = np.sum(w * (x - xm) * (y - ym)) / sxx
    resid = y - ym - slope * (x - xm)
    err = math.sqrt(np.sum(w * resid**2) / (x.size - 2) / sxx)
    return BFit(
        b=float(-slope),
        b_err=float(err),
        m_min=m_min,
        m_max=m_max,
        n=int(count.sum()),
        method="wlsq" if weighted else "lsq",
    )


def fit_b_mle(M, m_min=None, unbiased=False, bins=_DEFAULT_BINS):
    """Aki maximum-likelihood b for continuous magnitudes above ``m_min``.

    For ``P(M) = b exp(-b (M - m_min))`` on ``M >= m_min`` the MLE is
    ``b = 1 / (mean(M[M >= m_min]) - m_min)`` (Aki 1965, in natural-log units:
    no ``log10 e`` factor).  Its standard error is the asymptotic ``b / sqrt(n)``.
    The MLE is biased upwards, ``E[b_hat] = n b / (n - 1)``; ``unbiased=True``
    multiplies by ``(n - 1) / n``, which matters only for small ``n`` (it is far
    below ``b_err`` once ``n >> 1``).  Magnitudes are continuous here, so no
    Utsu binning correction is applied.

    ``b`` is in the paper's units, ``P(M) ~ exp(-b M)`` with ``M = ln S``
    (``N(>= S) ~ S^-b``); it equals the b of log10 slip magnitudes, and
    ``b_GR = 1.5 b`` for moment magnitudes ``Mw`` (module docstring).

    Parameters
    ----------
    M : array_like, pandas.DataFrame or SimulationResult
        Magnitudes ``M = ln S``, an events DataFrame or a result (its events).
    m_min : float, optional
        Completeness threshold.  Default: the maximum-curvature estimate, the
        centre of the most populated bin of the ``bins``-bin histogram
        (Wiemer & Wyss 2000); check it against a plot of ``P(M)``.
    unbiased : bool, optional
        Apply the ``(n - 1) / n`` correction.
    bins : int, optional
        Histogram bins for the default ``m_min``.

    Returns
    -------
    BFit
        ``m_max`` is the largest magnitude used.

    Raises
    ------
    ValueError
        If fewer than 2 magnitudes lie at or above ``m_min`` or they all equal it.

    Examples
    --------
    >>> import numpy as np
    >>> M = -2.0 + np.random.default_rng(2).exponential(1 / 0.85, 20_000)
    >>> fit = fit_b_mle(M, m_min=-2.0)
    >>> abs(fit.b - 0.85) < 3 * fit.b_err, fit.n
    (True, 20000)
    """
    m = _magnitudes(M)
    if m.size < 2:
        raise InvalidParameterError(f"fit_b_mle needs at least 2 finite magnitudes; got {m.size}")
    if m_min is None:
        table = magnitude_distribution(m, bins=bins)
        m_min = float(table["M"].iloc[int(np.argmax(table["count"].to_numpy()))])
    m_min = float(m_min)
    if not math.isfinite(m_min):
        raise InvalidParameterError(f"m_min must be finite; got {m_min!r}")
    above = m[m >= m_min]
    n = above.size
    if n < 2:
        raise InvalidParameterError(
            f"fit_b_mle: {n} magnitudes at or above m_min={m_min:g} (of {m.size}); need >= 2"
        )
    excess = float(np.mean(above)) - m_min
    if excess <= 0.0:
        raise InvalidParameterError(
            f"fit_b_mle: all {n} magnitudes equal m_min={m_min:g}; b is undefined"
        )
    b = 1.0 / excess
    if unbiased:
        b *= (n - 1) / n
    return BFit(
        b=b,
        b_err=b / math.sqrt(n),
        m_min=m_min,
        m_max=float(above.max()),
        n=int(n),
        method="mle-unbiased" if unbiased else "mle",
    )
