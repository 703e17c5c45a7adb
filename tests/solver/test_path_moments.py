"""The interpolated crossings' path moments and a join's cubic, against exact polynomial calculus.

``path_moments`` integrates ``x0 - p(s)``, p a quartic in ``s - z0``, against ``(t1 -
s)^(m - 1) / (m - 1)!`` over ``[t0, t1]`` (in units of the step of length h) by four-point
Gauss-Legendre, which is exact for these integrands; ``join_cubic`` gives a joining block's
cubic from rest at its join to its integrated path's end.  Both are checked here against
NumPy's polynomial arithmetic, with the kernels' Python functions (``py_func``): compiled
kernels are callable from other kernels only.
"""

import math

import numpy as np
import pytest
from numpy.polynomial import Polynomial

from faultnet.solver._kernels.carlson_langer.response import join_cubic, path_moments
from faultnet.solver._kernels.carlson_langer.work import N_WORK, SA, SV, VS

moments = path_moments.py_func
cubic = join_cubic.py_func


def exact_moments(x0, t0, t1, h, z0, c):
    """``h^m int_t0^t1 (t1 - s)^(m - 1) / (m - 1)! (x0 - p(s)) ds`` for m = 1..4."""
    d = Polynomial([x0]) - Polynomial(c)(Polynomial([-z0, 1.0]))
    out = []
    for m in range(1, 5):
        weight = Polynomial([t1, -1.0]) ** (m - 1) / math.factorial(m - 1)
        integral = (weight * d).integ()
        out.append(h**m * (integral(t1) - integral(t0)))
    return out


@pytest.mark.parametrize("seed", range(6))
def test_path_moments_are_exact_over_any_interval(seed):
    rng = np.random.default_rng(seed)
    x0 = rng.normal()
    t0, t1 = np.sort(rng.uniform(0.0, 1.0, 2))
    if seed == 0:
        t1 = 1.0  # the stops' interval, [th, 1]
    h = rng.uniform(0.05, 0.5)
    z0 = 0.0 if seed < 3 else t0  # the dense output's origin, or a join's
    c = rng.normal(size=5)
    got = moments(x0, t0, t1, h, z0, *c)
    want = exact_moments(x0, t0, t1, h, z0, c)
    scale = np.abs(want).max()
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-13 * scale)


def test_path_moments_vanish_on_an_empty_interval():
    assert moments(0.3, 0.4, 0.4, 0.2, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0) == (0.0, 0.0, 0.0, 0.0)


@pytest.mark.parametrize("t, x1, v1, h", [(0.0, 0.02, 0.3, 0.2), (0.37, -1e-3, 0.05, 0.1)])
def test_join_cubic_starts_at_rest_and_ends_on_its_path(t, x1, v1, h):
    W = np.zeros((1, N_WORK))
    W[0, VS], W[0, SV], W[0, SA] = t, x1, v1
    t0, a, c = cubic(0, h, W)
    assert t0 == t
    p = Polynomial([0.0, 0.0, a, c])(Polynomial([-t, 1.0]))  # a (s - t)^2 + c (s - t)^3
    dp = p.deriv()
    assert abs(p(t)) < 1e-15 and abs(dp(t)) < 1e-14  # from rest at its join
    assert p(1.0) == pytest.approx(x1, rel=1e-12)  # its path's end position
    assert dp(1.0) == pytest.approx(h * v1, rel=1e-12)  # and velocity (per fraction of step)
