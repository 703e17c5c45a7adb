"""The tournament tree of failure keys against a rebuild from scratch after every change."""

import numba as nb
import numpy as np
import pytest

from faultnet.solver._kernels.bundles import empty_tree
from faultnet.solver._kernels.carlson_langer.tree import _winner, tree_update


@nb.njit(cache=False)
def _change_and_update(i, key, keys, tree):
    keys[i] = key
    tree_update(i, keys, tree)


@nb.njit(cache=False)
def _rebuild(keys, tree):
    leaves = tree.shape[0] // 2
    for i in range(leaves):
        tree[leaves + i] = i if i < keys.shape[0] else -1
    for p in range(leaves - 1, 0, -1):
        tree[p] = _winner(tree[2 * p], tree[2 * p + 1], keys)


@pytest.mark.parametrize("n", [1, 2, 5, 64, 1000])
def test_update_matches_a_rebuild_after_every_change(n):
    """Keys rise and fall, with many ties (ties go to the lower block index)."""
    rng = np.random.default_rng(n)
    keys = rng.integers(0, 8, n).astype(np.float64)
    tree = empty_tree(n)
    _rebuild(keys, tree)
    fresh = empty_tree(n)
    for _ in range(3000):
        i = int(rng.integers(n))
        _change_and_update(i, float(rng.integers(0, 8)), keys, tree)
        _rebuild(keys, fresh)
        np.testing.assert_array_equal(tree, fresh)
        assert tree[1] == int(np.argmin(keys))  # argmin: the first of equal minima
