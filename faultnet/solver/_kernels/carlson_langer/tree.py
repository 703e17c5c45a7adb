"""Failure keys and a tournament (min) tree over them.

Every stuck block ``i`` has a *key*: the (re-centred) plate position at which its force
reaches the static threshold 1 (:func:`~.physics.block_key`).  Keys do not depend on the plate
position, so they only change where an event moved blocks.  The next failing block is
the root of a tournament tree over the keys: O(1) to read, O(log N) to update
one leaf.  Ties go to the lower block index.
"""

from faultnet.solver._kernels.carlson_langer.physics import block_key
from faultnet.solver._kernels.jit import kernel
from faultnet.solver._kernels.layout import SCAL_OFFSET

__all__ = ["build_keys_and_tree", "tree_update"]


@kernel
def _winner(a, b, keys):
    """The block of ``a`` and ``b`` (-1: none) that fails first by ``keys``; ties to ``a``."""
    if a < 0:
        return b
    if b < 0:
        return a
    if keys[b] < keys[a]:
        return b
    return a


@kernel
def build_keys_and_tree(state, graph):
    """Recompute every key from ``z`` and rebuild the tree (O(N)).

    ``state``, ``graph``: :class:`~faultnet.solver._kernels.bundles.State` (its ``keys`` and
    ``tree`` are written) and ``Graph``.  The event entries call it before their first event
    (``ctrl[CTRL_REBUILD]``) and at each re-centring of the frame.
    """
    z, keys, tree = state.z, state.keys, state.tree
    n = len(z)
    leaves = len(tree) // 2
    off = state.scal[SCAL_OFFSET]
    for i in range(n):
        keys[i] = block_key(i, z, off, graph)
    for i in range(leaves):
        tree[leaves + i] = i if i < n else -1
    for p in range(leaves - 1, 0, -1):
        tree[p] = _winner(tree[2 * p], tree[2 * p + 1], keys)


@kernel
def tree_update(i, keys, tree):
    """Restore the tree after ``keys[i]`` changed (O(log N), usually a few levels).

    The walk up stops at the first node whose winner is unchanged and is not ``i``: no
    ancestor can then hold ``i`` (a winner reaches a node only through every node below it on
    its path), so every ancestor compares the same blocks with the same keys as before.  On a
    10^6-block lattice the nodes near the root are far apart in memory, and most updates stop
    within a few levels of the leaf.
    """
    p = (len(tree) // 2 + i) // 2
    while p >= 1:
        w = _winner(tree[2 * p], tree[2 * p + 1], keys)
        if w == tree[p] and w != i:
            return
        tree[p] = w
        p //= 2
