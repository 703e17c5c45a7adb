"""The table of cached solo slips: one row per parameter class (``layout.SOLO_*``).

A block that slips alone from the threshold, its neighbours held, follows a path that depends
on its class only (:attr:`~faultnet.CarlsonLanger.block_classes`).  The kernels integrate it
the first time and read it from this table afterwards, wherever no neighbour can reach the
threshold during it (:mod:`faultnet.solver._kernels.carlson_langer.solo`).
"""

from __future__ import annotations

import numpy as np

from faultnet.solver._kernels.layout import SOLO_SIZE, SOLO_SPEED

__all__ = ["solo_speed_bound", "solo_table"]


def solo_table(model, classes):
    """A fresh table for ``model``'s block ``classes``: the slips not yet computed (NaN), the
    bound on each class's velocity (:func:`solo_speed_bound`) in place.

    >>> import faultnet
    >>> m = faultnet.CarlsonLanger(faultnet.graphs.ring(5), k=16, sigma=0.01, alpha=0.0)
    >>> table = solo_table(m, m.block_classes)
    >>> table.shape[0], bool(np.isnan(table[0, 0])), round(float(table[0, -1]), 6)
    (1, True, 0.001758)
    """
    table = np.full((int(classes.max()) + 1, SOLO_SIZE), np.nan)
    first = np.unique(classes, return_index=True)[1]  # a block of each class
    table[:, SOLO_SPEED] = solo_speed_bound(
        model.stiffness[first], model.sigma_values[first], model.alpha_values[first]
    )
    return table


def solo_speed_bound(stiffness, sigma, alpha):
    """A bound on the fastest velocity of a block slipping alone from rest at the threshold.

    Its neighbours held, the block obeys ``v' = 1 - K x - phi(v) - eta v`` (``K`` its
    stiffness, ``eta`` its dashpots' total, ``phi(v) = (1 - sigma) / (1 + c v)`` with
    ``c = 2 alpha / (1 - sigma)``).  With ``eta v >= 0`` and ``phi`` falling with v, a path
    whose velocity stays at most ``V`` has ``v v' <= (r - K x) x'``, ``r = 1 - phi(V)``, so
    ``v <= r / sqrt(K)``: the fastest velocity ``V`` meets ``V sqrt(K) <= 1 - phi(V)``.  The
    right side is concave in V and the left linear, so V lies below their one positive
    crossing, the root of ``s c V^2 + (s - c) V - sigma = 0`` (``s = sqrt(K)``), returned
    with 1% to spare for the integration's error.  A cached solo slip is then free where
    every neighbour stays below 1 with ``k s1 + eta V`` added
    (:func:`~faultnet.solver._kernels.carlson_langer.solo.solo_free`).

    >>> v = solo_speed_bound(np.array([33.0]), np.array([0.01]), np.array([0.0]))
    >>> bool(np.isclose(v[0], 1.01 * 0.01 / np.sqrt(33.0)))
    True
    """
    s = np.sqrt(stiffness)
    c = 2.0 * alpha / (1.0 - sigma)
    b = s - c
    # the root written so that c -> 0 gives sigma / s without cancellation
    return 1.01 * 2.0 * sigma / (b + np.sqrt(b * b + 4.0 * s * c * sigma))
