"""The order in which an interpolated step applies its crossings (``interp._order``).

Joins first, by their fraction of the step (each joining block's path sees the neighbours
that joined before it), then stops by theirs; the dropped entries (-1) go last and are cut.
"""

import numba as nb
import numpy as np
import pytest

from faultnet.solver._kernels.bundles import Work
from faultnet.solver._kernels.carlson_langer.interp import _order
from faultnet.solver._kernels.carlson_langer.work import CAND, LOC_SIZE, N_IWORK, N_WORK, VS
from faultnet.solver._kernels.layout import CNT_SIZE


@nb.njit(cache=False)
def _sorted(ncand, W, IW):
    work = Work(W, IW, np.zeros(LOC_SIZE), np.zeros(CNT_SIZE, dtype=np.int64))
    return _order(ncand, work)


@pytest.mark.parametrize("n", [1, 5, 40, 300])
def test_joins_by_fraction_then_stops_dropped_cut(n):
    rng = np.random.default_rng(n)
    blocks = rng.permutation(2 * n)[:n]
    W = np.zeros((2 * n, N_WORK))
    IW = np.zeros((N_IWORK, 2 * n), dtype=np.int64)
    W[blocks, VS] = rng.random(n)
    kinds = rng.integers(0, 3, n)  # 0 join, 1 stop, 2 dropped
    entries = np.where(kinds == 0, blocks, np.where(kinds == 1, -2 - blocks, -1))
    IW[CAND, :n] = entries
    kept = _sorted(n, W, IW)
    assert kept == np.count_nonzero(kinds != 2)
    out = IW[CAND, :kept]
    joins, stops = out[out >= 0], -2 - out[out <= -2]
    assert np.all(out[: len(joins)] >= 0)  # joins before stops
    assert np.all(np.diff(W[joins, VS]) >= 0.0)
    assert np.all(np.diff(W[stops, VS]) >= 0.0)
    assert sorted(joins) == sorted(blocks[kinds == 0])
    assert sorted(stops) == sorted(blocks[kinds == 1])
