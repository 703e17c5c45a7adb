"""A slow, obviously correct OFC automaton: the oracle of the OFC kernel's tests.

It holds the forces themselves (no keys, no tree, no offset), finds the next block to topple
by scanning every force (``np.argmax``: the lowest index among ties), drives every force by
the same amount, and topples synchronously with dense matrices: every block at or over the
threshold at the start of a generation slips by ``F_i / K_i`` to the force 0, and its
neighbours gain ``k_ij F_i / K_i``.  The blocks whose force was the largest before the drive
are at the threshold exactly (force 1).

Exact ties are common in OFC: blocks that toppled together restart from 0 and may gain the
same amounts.  Two codes then break them as their round-off falls (the kernel's keys sum the
gains in another order), and their avalanches part.  Each avalanche therefore reports its
``margin``: how near any force came to a decision (a tie at the top, a force near 1), so that
a comparison can leave out the avalanches that round-off decides.
"""

import numpy as np

__all__ = ["reference_avalanches"]


def reference_avalanches(K, frame, forces, n_events, fault=None):
    """Run ``n_events`` avalanches from ``forces``.

    Parameters
    ----------
    K : (N, N) array
        Symmetric spring constants, zero diagonal.
    frame : (N,) array
        Frame-spring stiffness per block (``k wall_i``).
    forces : (N,) array
        Initial forces, all below 1.
    n_events : int
    fault : (N,) int array, optional
        Each block's fault number (for ``n_faults``).

    Returns
    -------
    (events, forces, drive)
        ``events``: one dict per avalanche (``t``, ``hypocenter``, ``n_topplings``,
        ``n_blocks``, ``S``, ``n_generations``, ``n_faults``, ``slips``: per block, and
        ``margin``: the smallest gap between the largest force and another before the drive,
        or between any force and 1 in a generation); the final forces and the total drive.
    """
    K = np.asarray(K, dtype=float)
    stiff = 1.0 + K.sum(axis=1) + np.asarray(frame, dtype=float)
    F = np.array(forces, dtype=float)
    n = F.size
    fault = np.zeros(n, dtype=int) if fault is None else np.asarray(fault)
    drive = 0.0
    events = []
    for _ in range(n_events):
        hyp = int(np.argmax(F))
        top = F[hyp]
        at = F == top
        others = np.delete(F, hyp)
        margin = float(np.min(top - others)) if others.size else np.inf
        d = 1.0 - top
        drive += d
        F = F + d
        F[at] = 1.0
        slips = np.zeros(n)
        toppled = np.zeros(n, dtype=bool)
        n_top = n_gen = 0
        while True:
            if n_gen:
                margin = min(margin, float(np.min(np.abs(F - 1.0))))
            over = F >= 1.0
            if not over.any():
                break
            n_gen += 1
            n_top += int(over.sum())
            dx = np.where(over, F / stiff, 0.0)
            F = np.where(over, 0.0, F) + K @ dx
            slips += dx
            toppled |= over
        events.append(
            {
                "t": drive,
                "hypocenter": hyp,
                "n_topplings": n_top,
                "n_blocks": int(toppled.sum()),
                "S": float(slips.sum()),
                "n_generations": n_gen,
                "n_faults": len(set(fault[toppled].tolist())),
                "slips": slips,
                "margin": margin,
            }
        )
    return events, F, drive
