"""The plate during events: the blocks that its motion alone brings to the threshold.

Where the plate moves during events (``graph.nu > 0``), every stuck block's force grows at
the rate ``nu``, also far from the slipping blocks: a block that no slipping neighbour
pushes can still start to slip, and so can a block that stuck earlier in the event.  The
failure keys and their tree (:mod:`.tree`) are the watch list.  A stuck block's key is the
plate position at which its force reaches 1 if no neighbour moves on:

- an untouched block's key is exact all event long (nothing near it moves);
- a block next to a slipping one may hold a stale key, but the step's scan watches it
  (:func:`.crossing.block_crossings`); when its last slipping neighbour sticks, its key is
  refreshed from its force (:func:`refresh_stuck`), and so is the key of the block that
  stuck;
- a slipping block's key is set to +inf when it reaches the root of the tree.

The integration then shortens the step that would pass the smallest key and lets that block
join at the step's end (:func:`next_plate_join`, :func:`plate_join`); a touched block whose
key turns out stale there has it refreshed instead.  The event's end refreshes every touched
key from the displacements (:mod:`.events`), and the next loading starts from the plate's
position at the end of the event.  A plain model compiles none of this (``kelvin_kernel``).

Arguments: ``h`` a step's length, ``j`` a block, ``w`` the plate position at the event's start,
``nact`` and ``ntouch`` the lengths of the active and touched lists, ``lo``, ``hi`` a range of
the active list ``IW[ACT]``, and the bundles ``state``, ``graph``, ``work``
(:mod:`faultnet.solver._kernels.bundles`).
"""

import math

from faultnet.solver._kernels.carlson_langer.physics import force, stuck_key
from faultnet.solver._kernels.carlson_langer.stepping import activate, touch
from faultnet.solver._kernels.carlson_langer.tree import tree_update
from faultnet.solver._kernels.carlson_langer.work import (
    ACT,
    ACTIVE,
    FLAG,
    PLATE,
    UNTOUCHED,
    D,
)
from faultnet.solver._kernels.jit import kelvin_kernel

__all__ = ["PLATE_MARGIN", "next_plate_join", "plate_join", "refresh_stuck"]

#: a touched block whose key surfaces joins when its force is within this of 1 (the step was
#: cut to its key: round-off only), else its key was stale and is refreshed
PLATE_MARGIN = 1e-12


@kelvin_kernel(plain=lambda h, w, state, graph, work: (h, -1))
def next_plate_join(h, w, state, graph, work):
    """The step to take (at most ``h``) and the block the plate brings to 1 at its end.

    Returns (step, block); block -1 when no stuck block reaches 1 within ``h``.  Slipping
    blocks that reach the root of the tree leave it (key +inf).
    """
    keys, tree = state.keys, state.tree
    W, IW = work.W, work.IW
    j = tree[1]
    while IW[FLAG, j] == ACTIVE and keys[j] < math.inf:  # (+inf: every block slips)
        keys[j] = math.inf
        tree_update(j, keys, tree)
        j = tree[1]
    hp = (keys[j] - w - W[PLATE, D]) / graph.nu
    if hp < h and IW[FLAG, j] != ACTIVE:
        return (hp if hp > 0.0 else 0.0), j
    return h, j - j - 1


@kelvin_kernel(plain=lambda j, nact, ntouch, w, state, graph, work: (nact, ntouch))
def plate_join(j, nact, ntouch, w, state, graph, work):
    """Block ``j``, whose key the plate has reached, starts to slip (returns (nact, ntouch)).

    An untouched block is at 1 by construction; a touched one joins if its force is within
    ``PLATE_MARGIN`` of 1, else its key was stale and is refreshed.
    """
    W, IW, keys = work.W, work.IW, state.keys
    if IW[FLAG, j] == UNTOUCHED:
        ntouch = touch(j, w, keys, W, IW, ntouch)
    elif force(j, D, W, graph) < 1.0 - PLATE_MARGIN:
        keys[j] = stuck_key(j, w, W, graph)
        tree_update(j, keys, state.tree)
        return nact, ntouch
    return activate(j, nact, ntouch, w, keys, graph, work)


@kelvin_kernel
def refresh_stuck(lo, hi, w, state, graph, work):
    """Refresh the keys of the blocks that just stuck, ``IW[ACT, lo:hi]``, and of their stuck
    neighbours, from their forces now."""
    W, IW, keys, tree = work.W, work.IW, state.keys, state.tree
    for q in range(lo, hi):
        i = IW[ACT, q]
        keys[i] = stuck_key(i, w, W, graph)
        tree_update(i, keys, tree)
        for p in range(graph.indptr[i], graph.indptr[i + 1]):
            j = graph.indices[p]
            if IW[FLAG, j] != ACTIVE:
                keys[j] = stuck_key(j, w, W, graph)
                tree_update(j, keys, tree)
