"""Roots of the interpolants a crossing is located on, as a fraction of the step.

The DP5 dense output is a quartic (:func:`poly_root`); a cubic Hermite interpolant of the
end values (:func:`hermite_root`, :func:`hermite_fall`, :func:`hermite_dip`) places the rare
stops that the dense output cannot: a block that joined at rest and stops again within the
step, and a velocity that dips below zero inside a step whose ends are both positive.  The
arguments are the interpolant's end values ``y0``, ``y1`` and slopes times the step ``m0``,
``m1`` (Hermite), or its power-basis coefficients ``c0`` ... ``c4`` (quartic), and the
bracket ``[lo, hi]`` where one is searched; ``th`` is a fraction of the step.
"""

from faultnet.solver._kernels.jit import forced_kernel, inline_kernel, kernel

__all__ = ["hermite", "hermite_dip", "hermite_fall", "hermite_root", "poly_root"]


@kernel
def hermite(th, y0, m0, y1, m1):
    """Cubic Hermite interpolant on [0, 1]; m0, m1 are slopes times h."""
    t2 = th * th
    t3 = t2 * th
    return (
        (2.0 * t3 - 3.0 * t2 + 1.0) * y0
        + (t3 - 2.0 * t2 + th) * m0
        + (3.0 * t2 - 2.0 * t3) * y1
        + (t3 - t2) * m1
    )


@inline_kernel
def _hermite_slope(th, y0, m0, y1, m1):
    t2 = th * th
    return (
        (6.0 * t2 - 6.0 * th) * y0
        + (3.0 * t2 - 4.0 * th + 1.0) * m0
        + (6.0 * th - 6.0 * t2) * y1
        + (3.0 * t2 - 2.0 * th) * m1
    )


@kernel
def hermite_root(lo, hi, y0, m0, y1, m1):
    """Root of the Hermite cubic in [lo, hi], where it changes sign.

    Safeguarded Newton: a Newton step that leaves the bracket is replaced by
    bisection.  Converges to round-off in a handful of iterations.
    """
    flo = hermite(lo, y0, m0, y1, m1)
    th = 0.5 * (lo + hi)
    for _ in range(60):
        f = hermite(th, y0, m0, y1, m1)
        if f == 0.0:
            return th
        if (f > 0.0) == (flo > 0.0):
            lo, flo = th, f
        else:
            hi = th
        d = _hermite_slope(th, y0, m0, y1, m1)
        nxt = th - f / d if d != 0.0 else 0.5 * (lo + hi)
        if not (lo < nxt < hi):
            nxt = 0.5 * (lo + hi)
        if abs(nxt - th) <= 1e-15:
            return nxt
        th = nxt
    return th


@kernel
def poly_root(lo, hi, c0, c1, c2, c3, c4):
    """Root in [lo, hi] of c0 + c1 t + ... + c4 t^4, which changes sign there.

    Safeguarded Newton as in :func:`hermite_root`; used with the DP5 dense output.
    """
    flo = c0 + lo * (c1 + lo * (c2 + lo * (c3 + lo * c4)))
    th = 0.5 * (lo + hi)
    for _ in range(60):
        f = c0 + th * (c1 + th * (c2 + th * (c3 + th * c4)))
        if f == 0.0:
            return th
        if (f > 0.0) == (flo > 0.0):
            lo, flo = th, f
        else:
            hi = th
        d = c1 + th * (2.0 * c2 + th * (3.0 * c3 + th * 4.0 * c4))
        nxt = th - f / d if d != 0.0 else 0.5 * (lo + hi)
        if not (lo < nxt < hi):
            nxt = 0.5 * (lo + hi)
        if abs(nxt - th) <= 1e-15:
            return nxt
        th = nxt
    return th


@forced_kernel
def _first_critical(y0, m0, y1, m1):
    """Smallest root in (0, 1) of the Hermite cubic's slope, or 2.0."""
    c2 = 6.0 * y0 + 3.0 * m0 - 6.0 * y1 + 3.0 * m1
    c1 = -6.0 * y0 - 4.0 * m0 + 6.0 * y1 - 2.0 * m1
    c0 = m0
    best = 2.0
    if c2 == 0.0:
        if c1 != 0.0:
            best = -c0 / c1
    else:
        disc = c1 * c1 - 4.0 * c2 * c0
        if disc >= 0.0:
            r = disc**0.5
            r1 = (-c1 - r) / (2.0 * c2)
            r2 = (-c1 + r) / (2.0 * c2)
            lo, hi = r2 if r2 < r1 else r1, r2 if r2 > r1 else r1
            best = lo if lo > 0.0 else hi
    if not (0.0 < best < 1.0):
        return 2.0
    return best


@inline_kernel
def hermite_fall(m0, y1, m1):
    """Root in (0, 1] of a velocity that starts at 0 rising (m0 > 0) and ends <= 0.

    Returns 0.0 when the cubic never rises above 0 (stop at once).
    """
    if m0 <= 0.0:
        return 0.0
    peak = _first_critical(0.0, m0, y1, m1)
    if peak > 1.0 or hermite(peak, 0.0, m0, y1, m1) <= 0.0:
        return 0.0
    return hermite_root(peak, 1.0, 0.0, m0, y1, m1)


@inline_kernel
def hermite_dip(y0, m0, y1, m1):
    """First root in (0, 1] of a Hermite cubic with y0 > 0, y1 > 0, or 2.0.

    Used for a velocity that dips below zero inside a step although both
    ends are positive (the block should have stuck inside the step).
    """
    best = _first_critical(y0, m0, y1, m1)
    if best > 1.0:
        return 2.0
    if hermite(best, y0, m0, y1, m1) > 0.0:
        return 2.0
    return hermite_root(0.0, best, y0, m0, y1, m1)
