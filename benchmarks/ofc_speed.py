"""The OFC automaton: faultnet's kernel against a naive automaton, on the same avalanches.

The workload: the 256^2 square lattice with fixed ("open") boundaries at alpha = 0.2 (k = 1),
from forces drawn uniformly from [0, 1), measured after the first 3x10^5 avalanches (the
transient of such a lattice is far longer; steady state is out of reach of a check).

The naive automaton is compiled by Numba too (a fair yardstick: the same compiled language,
the same CSR springs): it drives by scanning every force for the largest (O(N)) and adding the
drive to every force (O(N)), then topples synchronously, touching the toppled blocks and
their neighbours only.  faultnet drives in O(log N) (keys and a tournament tree).  Both start
from the same state (faultnet's after the transient) and run the same next avalanches; the
table gives avalanches/s, topplings/s and the ratio, the best of ``--rounds`` rounds each, and
the topplings both counted (equal unless round-off broke a tie differently).

With ``--steady-drive D`` faultnet then runs on alone to a total drive of ``D`` (the 256^2
lattice is in its steady state from a drive of about 3000: mean size 12-13 topplings, two
thirds single topplings) and times ``--steady-events`` avalanches there, the issue's goal of
10^7 topplings/s.

Run by hand (never a timed test)::

    PYTHONPATH=. python benchmarks/ofc_speed.py                     # about a minute
    PYTHONPATH=. python benchmarks/ofc_speed.py --steady-drive 5000  # 5 minutes more
    PYTHONPATH=. python benchmarks/ofc_speed.py --size 128 --transient 100000
"""

from __future__ import annotations

import argparse
import time

import numba as nb
import numpy as np

import faultnet
from faultnet.solver.ofc import OFCSimulator


@nb.njit(cache=True)
def naive_avalanches(n_events, F, indptr, indices, kval, stiff, cur, nxt, amount, mark, topplings):
    """``n_events`` avalanches on the forces ``F`` (in place); topplings per avalanche."""
    n = F.shape[0]
    stamp = 0
    for e in range(n_events):
        top = 0
        for i in range(1, n):  # the O(N) scan for the largest force (lowest index on ties)
            if F[i] > F[top]:
                top = i
        fmax = F[top]
        d = 1.0 - fmax
        nc = 0
        for i in range(n):  # the O(N) drive; the blocks at the largest force reach 1 exactly
            if F[i] == fmax:
                F[i] = 1.0
                cur[nc] = i
                amount[nc] = 1.0
                nc += 1
            else:
                F[i] += d
        count = 0
        while nc > 0:  # synchronous generations, touching the toppled blocks' neighbours only
            count += nc
            for q in range(nc):
                i = cur[q]
                amount[q] = F[i] / stiff[i]
                F[i] = 0.0
            stamp += 1
            nn = 0
            for q in range(nc):
                i = cur[q]
                dx = amount[q]
                for p in range(indptr[i], indptr[i + 1]):
                    j = indices[p]
                    F[j] += kval[p] * dx
                    if F[j] >= 1.0 and mark[j] != stamp:
                        mark[j] = stamp
                        nxt[nn] = j
                        nn += 1
            cur, nxt = nxt, cur
            nc = nn
        topplings[e] = count


def _naive_round(model, forces, n_events):
    adj = model.adjacency
    F = forces.copy()
    n = model.n
    args = (
        adj.indptr.astype(np.int64),
        adj.indices.astype(np.int64),
        adj.data.astype(np.float64),
        model.stiffness,
        np.zeros(n, np.int64),
        np.zeros(n, np.int64),
        np.zeros(n, np.float64),
        np.zeros(n, np.int64),
    )
    top = np.zeros(n_events, np.int64)
    naive_avalanches(1, F.copy(), *args, np.zeros(1, np.int64))  # compile outside the clock
    tic = time.perf_counter()
    naive_avalanches(n_events, F, *args, top)
    return time.perf_counter() - tic, int(top.sum())


def _faultnet_round(model, state, n_events):
    sim = OFCSimulator(model, state)
    res = sim.advance(n_events, progress=False)
    return res.metadata["wall_time_s"], int(res.metadata["n_topplings"])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=256, help="lattice side L (default 256)")
    ap.add_argument("--alpha", type=float, default=0.2)
    ap.add_argument("--transient", type=int, default=300_000, help="avalanches left out first")
    ap.add_argument("--events", type=int, default=30_000, help="avalanches timed per round")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--steady-drive", type=float, default=0.0, help="0: no steady-state timing")
    ap.add_argument("--steady-events", type=int, default=2_000_000)
    args = ap.parse_args(argv)

    g = faultnet.graphs.square_lattice(args.size, args.size, boundary="fixed", sparse=True)
    model = faultnet.OFC.from_alpha(g, args.alpha)
    sim = OFCSimulator(model, rng=args.seed)
    tic = time.perf_counter()
    warm = sim.advance(args.transient, progress=False)
    print(
        f"{args.size}^2 fixed lattice, alpha = {model.alpha} (k = {model.k}): transient of "
        f"{args.transient:,} avalanches in {time.perf_counter() - tic:.1f} s "
        f"(mean {warm.events.n_topplings.mean():.2f} topplings each)"
    )
    state = sim.state
    forces = model.forces(state)
    fast, slow = [], []
    for _ in range(args.rounds):  # alternating rounds, the best of each
        fast.append(_faultnet_round(model, state, args.events))
        slow.append(_naive_round(model, forces, args.events))
    (tf, nf), (tn, nn) = min(fast), min(slow)
    rows = [("faultnet (tree)", tf, nf), ("naive (O(N) scan)", tn, nn)]
    print(f"next {args.events:,} avalanches, best of {args.rounds} rounds, one core")
    print(f"{'code':<20}{'avalanches/s':>14}{'topplings/s':>14}{'topplings':>12}{'s':>9}")
    for name, t, n in rows:
        print(f"{name:<20}{args.events / t:>14,.0f}{n / t:>14,.0f}{n:>12,}{t:>9.3f}")
    print(
        f"ratio (avalanches/s): {tn / tf:,.1f}x  (all rounds: faultnet "
        f"{', '.join(f'{t:.3f}' for t, _ in fast)} s; naive "
        f"{', '.join(f'{t:.3f}' for t, _ in slow)} s)"
    )
    if args.steady_drive > 0:
        tic = time.perf_counter()
        while sim.state.offset + sim.state.w < args.steady_drive:
            sim.advance(5_000_000, progress=False)
        state = sim.state
        print(
            f"steady state: drive {state.offset + state.w:.0f} after {state.n_events:,} "
            f"avalanches ({time.perf_counter() - tic:.0f} s)"
        )
        for _ in range(args.rounds):
            md = OFCSimulator(model, state).advance(args.steady_events, progress=False).metadata
            t = md["wall_time_s"]
            print(
                f"  {args.steady_events:,} avalanches: {args.steady_events / t:,.0f} avalanches/s, "
                f"{md['n_topplings'] / t:,.0f} topplings/s "
                f"(mean {md['n_topplings'] / args.steady_events:.2f} topplings)"
            )


if __name__ == "__main__":
    main()
