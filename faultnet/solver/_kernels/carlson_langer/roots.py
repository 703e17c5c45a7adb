"""The root of a crossing on the step's dense output, as a fraction of the step.

The DP5 dense output of a value over a step (a position, a velocity, a force) is a quartic
in the fraction ``th`` of the step, with power-basis coefficients ``c0`` ... ``c4``;
:func:`poly_root` finds its root in a bracket ``[lo, hi]``, where it changes sign.  The same
kernel finds a velocity's minimum (the root of its slope, a cubic: ``c4 = 0``) and the stop
of a block that starts from rest (the root of ``v / th``).
"""

from faultnet.solver._kernels.jit import kernel

__all__ = ["poly_root"]


@kernel
def poly_root(lo, hi, c0, c1, c2, c3, c4):
    """Root in [lo, hi] of c0 + c1 t + ... + c4 t^4, which changes sign there.

    Safeguarded Newton: a Newton step that leaves the bracket is replaced by bisection.
    Converges to round-off in a handful of iterations.
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
