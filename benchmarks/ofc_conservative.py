"""The OFC automaton towards its conservative limit, alpha -> 1/4 on the square lattice.

For each boundary (free and fixed) and alpha in ``--alphas``: ``k = alpha / (1 - 4 alpha)``
on an L x L lattice, a drive of 40 L left out, then ``--avalanches`` avalanches measured.
Prints the mean and largest avalanche size (topplings), the share of single topplings, the
most topplings of one block in one avalanche, and the plate springs' share of the dissipation,
``mean S / (N x drive per avalanche)``: a toppling of slip ``dx`` hands ``dx`` of force to its
plate spring (and ``k wall dx`` to its frame springs), so in the steady state, where the force
the drive adds leaves again, the share is 1 on a free lattice and below 1 on a fixed one.

    python benchmarks/ofc_conservative.py --side 64 --alphas 0.2 0.24 0.249
"""

import argparse
import time

import numpy as np

import faultnet
from faultnet.solver.ofc import OFCSimulator


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--side", type=int, default=64)
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.2, 0.24, 0.249])
    ap.add_argument("--avalanches", type=int, default=3_000_000)
    args = ap.parse_args()
    L = args.side
    print(f"{L}x{L} lattice, a drive of {40 * L} left out, {args.avalanches:,} avalanches")
    print("boundary  alpha      k   mean size   max size  single  max topplings/block  plate share")
    for boundary in ("free", "fixed"):
        for alpha in args.alphas:
            k = alpha / (1 - 4 * alpha)
            graph = faultnet.graphs.square_lattice(L, L, boundary=boundary, sparse=True)
            sim = OFCSimulator(faultnet.OFC(graph, k=k), rng=1)
            tic = time.perf_counter()
            while sim.state.offset + sim.state.w < 40 * L:
                sim.advance(1_000_000, progress=False)
            ev = sim.advance(args.avalanches, progress=False).events
            s = ev["n_topplings"].to_numpy()
            drive = (ev["t"].iloc[-1] - ev["t"].iloc[0]) / (len(ev) - 1)
            share = ev["S"].mean() / (L * L * drive)
            per_block = (s / np.maximum(ev["n_blocks"].to_numpy(), 1)).max()
            print(f"{boundary:8} {alpha:6.3f} {k:6.4g} {s.mean():11.2f} {s.max():10,d} "
                  f"{np.mean(s == 1):7.3f} {per_block:20.1f} {share:12.3f}"
                  f"   ({time.perf_counter() - tic:.0f} s)", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
