r"""Omori-Utsu aftershock decay: maximum-likelihood fit and synthetic sequences.

The Omori-Utsu law gives the rate of events a time ``t`` after a mainshock as

.. math:: \lambda(t) = \frac{K}{(t + c)^p}.

:func:`fit_omori` maximises the likelihood of a non-homogeneous Poisson
process with this rate on a window ``[t_start, t_end]`` (Ogata 1983),

.. math:: \ln L = n \ln K - p \sum_i \ln(t_i + c) - K \int_{t_s}^{t_e} (t + c)^{-p}\,dt,

and gives standard errors from the inverse of the observed information (the
negative Hessian of ``ln L``).  :func:`sample_omori` draws a sequence with known
``K, c, p`` by thinning, for tests and for checking a fit's coverage.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from faultnet.exceptions import FitWarning, InvalidParameterError

__all__ = ["OmoriFit", "fit_omori", "omori_integral", "sample_omori"]


def omori_integral(c, p, t_start, t_end):
    """``int_{t_start}^{t_end} (t + c)^-p dt``, stable for ``p`` near 1.

    >>> round(omori_integral(1.0, 1.0, 0.0, math.e - 1.0), 12)
    1.0
    >>> round(omori_integral(0.0, 2.0, 1.0, 2.0), 12)
    0.5
    """
    a = math.log(t_start + c)
    b = math.log(t_end + c)
    u = 1.0 - p
    if abs(u) < 1e-12:
        return b - a
    return math.exp(u * a) * math.expm1(u * (b - a)) / u


@dataclass(frozen=True)
class OmoriFit:
    """Maximum-likelihood Omori-Utsu fit ``lambda(t) = K / (t + c)^p``.

    Attributes
    ----------
    K, c, p : float
        Productivity (per sequence), time offset and decay exponent.
    K_err, c_err, p_err : float
        Standard errors from the inverse observed information (Hessian of
        ``ln L`` at the maximum); NaN where the information matrix is singular
        (for example ``c`` pinned at a bound of the search).
    n : int
        Events inside ``[t_start, t_end]``.
    t_start, t_end : float
        Fit window (time since the mainshock).
    n_sequences : int
        Number of stacked sequences; ``K`` is the productivity of one.
    log_likelihood : float
        ``ln L`` at the maximum.
    """

    K: float
    c: float
    p: float
    K_err: float
    c_err: float
    p_err: float
    n: int
    t_start: float
    t_end: float
    n_sequences: int
    log_likelihood: float

    def rate(self, t):
        """Fitted rate of all ``n_sequences`` stacked sequences at times ``t``."""
        return self.n_sequences * self.K / (np.asarray(t, dtype=np.float64) + self.c) ** self.p

    def expected(self, t0=None, t1=None):
        """Expected number of events in ``[t0, t1]`` (default the fit window), all sequences."""
        t0 = self.t_start if t0 is None else float(t0)
        t1 = self.t_end if t1 is None else float(t1)
        return self.n_sequences * self.K * omori_integral(self.c, self.p, t0, t1)

    def __str__(self):
        return (
            f"K = {self.K:.4g} +/- {self.K_err:.2g}, c = {self.c:.4g} +/- {self.c_err:.2g}, "
            f"p = {self.p:.4g} +/- {self.p_err:.2g} (n = {self.n}, "
            f"t in [{self.t_start:g}, {self.t_end:g}], {self.n_sequences} sequence(s))"
        )


def _check_window(t_start, t_end):
    t_start, t_end = float(t_start), float(t_end)
    if not (math.isfinite(t_start) and math.isfinite(t_end)) or t_start < 0 or t_end <= t_start:
        raise InvalidParameterError(
            f"the Omori window needs 0 <= t_start < t_end (finite); got t_start={t_start!r}, "
            f"t_end={t_end!r}"
        )
    return t_start, t_end


def _log_likelihood(log_k, log_c, p, times, t_start, t_end):
    c = math.exp(log_c)
    k = math.exp(log_k)
    return (
        times.size * log_k
        - p * float(np.sum(np.log(times + c)))
        - k * omori_integral(c, p, t_start, t_end)
    )


def _hessian(f, x, h=1e-4):
    """Central-difference Hessian of ``f`` at ``x``."""
    x = np.asarray(x, dtype=np.float64)
    d = x.size
    hess = np.empty((d, d))
    f0 = f(x)
    for i in range(d):
        ei = np.zeros(d)
        ei[i] = h
        hess[i, i] = (f(x + ei) - 2.0 * f0 + f(x - ei)) / h**2
        for j in range(i):
            ej = np.zeros(d)
            ej[j] = h
            hess[i, j] = hess[j, i] = (
                f(x + ei + ej) - f(x + ei - ej) - f(x - ei + ej) + f(x - ei - ej)
            ) / (4.0 * h**2)
    return hess


def _warn_if_unresolved(p, c, c_err, p_bounds, log_c_bounds, span):
    """A :class:`~faultnet.exceptions.FitWarning` for each way the fit fails to find a decay."""
    problems = []
    if min(abs(p - b) for b in p_bounds) < 1e-6:
        problems.append(f"p = {p:.3g} is at its search bound {p_bounds} (no maximum inside)")
    elif p <= 0:
        problems.append(f"p = {p:.3g} <= 0: the rate does not decay in this window")
    if min(abs(math.log(c) - b) for b in log_c_bounds) < 1e-6:
        problems.append(f"c = {c:.3g} is at its search bound")
    elif c > span:
        problems.append(f"c = {c:.3g} is longer than the window ({span:.3g})")
    if not c_err < c:
        problems.append(f"c is unresolved (its error {c_err:.3g} is not below c = {c:.3g})")
    if problems:
        warnings.warn(
            "fit_omori does not pin the decay down: " + "; ".join(problems) + ". Try a "
            "longer window, more sequences, or check that the events follow a mainshock",
            FitWarning,
            stacklevel=3,
        )


def fit_omori(times, t_start, t_end, n_sequences=1, p_bounds=(-3.0, 5.0)):
    """Maximum-likelihood Omori-Utsu fit ``K / (t + c)^p`` on ``[t_start, t_end]``.

    ``K`` is profiled out (``K = n / int (t + c)^-p dt``) and the profile
    likelihood is maximised over ``ln c`` and ``p`` (bounded search, several
    starts).  The standard errors come from the Hessian of the full ``ln L``
    in ``(ln K, ln c, p)``, mapped to ``K`` and ``c`` by the delta method.

    Parameters
    ----------
    times : array_like
        Event times since the mainshock (pooled over ``n_sequences`` stacked
        mainshocks that each cover the whole window).  Times outside the
        window are ignored.
    t_start, t_end : float
        Fit window, ``0 <= t_start < t_end``.
    n_sequences : int, optional
        Number of stacked sequences: the fitted ``K`` is divided by it.
    p_bounds : (float, float), optional
        Search interval of ``p``; it reaches below 0 so that a rate that does
        not decay (``p <= 0``) shows as such instead of being pinned at a bound.
        ``c`` is searched over ``[1e-6, 10] * (t_end - t_start)``.

    Returns
    -------
    OmoriFit

    Raises
    ------
    InvalidParameterError
        For a bad window, ``n_sequences < 1`` or fewer than 10 events inside.

    Warns
    -----
    FitWarning
        When the fit finds no decay to trust: ``p`` at a search bound or ``p <= 0``, ``c``
        at a bound or longer than the window, or ``c``'s error not below ``c``.  The numbers
        are returned all the same.

    Examples
    --------
    >>> t = sample_omori(K=40.0, c=0.05, p=1.1, t_start=0.0, t_end=100.0, rng=7)
    >>> fit = fit_omori(t, 0.0, 100.0)
    >>> bool(abs(fit.p - 1.1) < 3 * fit.p_err), fit.n == t.size
    (True, True)
    """
    from scipy.optimize import minimize

    t_start, t_end = _check_window(t_start, t_end)
    if int(n_sequences) != n_sequences or n_sequences < 1:
        raise InvalidParameterError(f"n_sequences must be an integer >= 1; got {n_sequences!r}")
    t = np.asarray(times, dtype=np.float64).ravel()
    t = t[(t >= t_start) & (t <= t_end)]
    n = t.size
    if n < 10:
        raise InvalidParameterError(
            f"fit_omori needs at least 10 events in [{t_start:g}, {t_end:g}]; got {n}"
        )
    span = t_end - t_start
    lc_lo, lc_hi = math.log(1e-6 * span), math.log(10.0 * span)

    def neg_profile(x):
        log_c, p = x
        a = omori_integral(math.exp(log_c), p, t_start, t_end)
        return -(n * math.log(n / a) - n - p * float(np.sum(np.log(t + math.exp(log_c)))))

    best = None
    for lc0 in (math.log(1e-3 * span), math.log(1e-2 * span), math.log(0.1 * span)):
        for p0 in (0.8, 1.2):
            res = minimize(
                neg_profile,
                [lc0, p0],
                method="L-BFGS-B",
                bounds=[(lc_lo, lc_hi), p_bounds],
            )
            if best is None or res.fun < best.fun:
                best = res
    log_c, p = (float(v) for v in best.x)
    c = math.exp(log_c)
    K_total = n / omori_integral(c, p, t_start, t_end)
    x = np.array([math.log(K_total), log_c, p])
    hess = _hessian(lambda v: _log_likelihood(v[0], v[1], v[2], t, t_start, t_end), x)
    try:
        cov = np.linalg.inv(-hess)
        var = np.diag(cov)
        if np.any(var <= 0) or not np.all(np.isfinite(var)):
            raise np.linalg.LinAlgError
        se = np.sqrt(var)
    except np.linalg.LinAlgError:
        se = np.full(3, np.nan)
    k_seq = K_total / n_sequences
    _warn_if_unresolved(p, c, float(c * se[1]), p_bounds, (lc_lo, lc_hi), span)
    return OmoriFit(
        K=k_seq,
        c=c,
        p=p,
        K_err=float(k_seq * se[0]),
        c_err=float(c * se[1]),
        p_err=float(se[2]),
        n=int(n),
        t_start=t_start,
        t_end=t_end,
        n_sequences=int(n_sequences),
        log_likelihood=float(-best.fun),
    )


def sample_omori(K, c, p, t_start, t_end, rng=None):
    """Event times of an Omori-Utsu process ``K / (t + c)^p`` on ``[t_start, t_end]``.

    Drawn by thinning (Lewis & Shedler 1979): candidates of a homogeneous
    Poisson process at the maximum rate ``K / (t_start + c)^p`` are kept with
    probability ``lambda(t) / lambda_max``.

    Parameters
    ----------
    K, c, p : float
        ``K > 0``, ``c > 0`` (or ``c >= 0`` with ``t_start > 0``), ``p > 0``.
    t_start, t_end : float
        Window, ``0 <= t_start < t_end``.
    rng : None, int, SeedSequence or Generator
        Normalised by :func:`numpy.random.default_rng`.

    Returns
    -------
    numpy.ndarray
        Sorted event times.

    Examples
    --------
    >>> t = sample_omori(10.0, 0.1, 1.0, 0.0, 10.0, rng=0)
    >>> bool(np.all(np.diff(t) >= 0)), bool(t.min() >= 0.0 and t.max() <= 10.0)
    (True, True)
    """
    t_start, t_end = _check_window(t_start, t_end)
    K, c, p = float(K), float(c), float(p)
    if not (K > 0 and p > 0 and c >= 0 and t_start + c > 0):
        raise InvalidParameterError(
            f"sample_omori needs K > 0, p > 0, c >= 0 and t_start + c > 0; got K={K!r}, "
            f"c={c!r}, p={p!r}, t_start={t_start!r}"
        )
    gen = np.random.default_rng(rng)
    lam_max = K / (t_start + c) ** p
    n_cand = gen.poisson(lam_max * (t_end - t_start))
    cand = np.sort(gen.uniform(t_start, t_end, n_cand))
    keep = gen.random(n_cand) * lam_max < K / (cand + c) ** p
    return cand[keep]
