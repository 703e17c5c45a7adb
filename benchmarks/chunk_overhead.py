"""Fixed cost of one call on a large model: a new Simulator against Simulator.advance.

A long run (``faultnet simulate --out``) advances one Simulator chunk after
chunk; building a Simulator (CSR copies, work space, failure keys and tree)
is O(N) and is paid once.  This script prints both costs on a square lattice
of ``--side``² blocks (default 1000² = 10⁶ blocks), best of ``--repeat``:

    python benchmarks/chunk_overhead.py --side 1000 --repeat 5
"""

import argparse
import time

import faultnet


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--side", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    g = faultnet.graphs.square_lattice(args.side, args.side, periodic=True, sparse=True)
    model = faultnet.CarlsonLanger(g, k=16, sigma=0.01, alpha=1.0)
    sim = faultnet.Simulator(model, rng=1)
    sim.advance(10, progress=False)  # compile or load the kernels
    state = sim.state
    new, adv, one_ev = [], [], []
    for _ in range(args.repeat):
        tic = time.perf_counter()
        fresh = faultnet.Simulator(model, x0=state)
        new.append(time.perf_counter() - tic)
        tic = time.perf_counter()
        res = fresh.advance(1, progress=False)
        adv.append(time.perf_counter() - tic)
        one_ev.append(res.metadata["wall_time_s"])
    print(f"square {args.side}x{args.side} periodic ({model.n:,} blocks), best of {args.repeat}")
    print(f"{'new Simulator (set-up)':32} {1e3 * min(new):9.1f} ms")
    print(f"{'advance(1): whole call':32} {1e3 * min(adv):9.1f} ms")
    print(f"{'advance(1): inside the kernel':32} {1e3 * min(one_ev):9.1f} ms")


if __name__ == "__main__":
    main()
