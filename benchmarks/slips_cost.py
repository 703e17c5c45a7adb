"""What the slips cost: per-block slips streamed to disk, and per-fault slips of a network.

Two comparisons, each in alternating rounds from the same seed (the machine drifts), all
runs to Parquet in chunks as ``faultnet simulate --out`` writes them, events/s of the whole
call (simulation, chunk files, checkpoints and the final merge):

* the ring of ``--blocks`` at alpha = 1: without slips, and with ``record_slips=True``;
* two parallel rings of ``--blocks`` / 2 coupled by springs of 2: the same graph without
  fault labels, and with them (a network of faults sums each event's slips per fault and
  writes them next to the catalog).

    python benchmarks/slips_cost.py --blocks 2000 --events 40000 --rounds 3
"""

import argparse
import os
import tempfile
import time

import networkx as nx

import faultnet


def _rate(model, n, **kw):
    """Events/s of one run of ``n`` events to Parquet from seed 1, and its files' bytes."""
    faultnet.simulate(model, 1, rng=1, progress=False)  # kernels loaded before the clock
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "run.parquet")
        tic = time.perf_counter()
        faultnet.simulate_to_parquet(model, n, out, rng=1, progress=False, **kw)
        wall = time.perf_counter() - tic
        size = sum(os.path.getsize(os.path.join(d, f)) for f in os.listdir(d))
    return n / wall, size


def _compare(title, cases, n, rounds):
    rates = {name: [] for name in cases}
    sizes = {}
    for _ in range(rounds):
        for name, (model, kw) in cases.items():
            rate, sizes[name] = _rate(model, n, **kw)
            rates[name].append(rate)
    print(f"\n{title}: {n:,} events, {rounds} alternating rounds")
    base = None
    for name, values in rates.items():
        best = max(values)
        base = base or best
        print(f"  {name:34} {best:9,.0f} ev/s (rounds {min(values):,.0f}-{best:,.0f})"
              f"  {best / base:5.2f}x  files {sizes[name] / 1e6:7.1f} MB")  # fmt: skip


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=2000)
    ap.add_argument("--events", type=int, default=40_000)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    ring = faultnet.CarlsonLanger(faultnet.graphs.ring(args.blocks), k=16, sigma=0.01, alpha=1.0)
    _compare(
        f"ring of {args.blocks} at alpha = 1",
        {"without slips": (ring, {}), "record_slips=True": (ring, {"record_slips": True})},
        args.events,
        args.rounds,
    )
    net = faultnet.graphs.parallel_faults(2, args.blocks // 2, k_coupling=2.0, periodic=True)
    plain = nx.Graph(net)
    for _, data in plain.nodes(data=True):
        del data["fault"]
    _compare(
        f"two coupled rings of {args.blocks // 2} at alpha = 1",
        {
            "no fault labels": (faultnet.CarlsonLanger(plain, k=16, sigma=0.01, alpha=1.0), {}),
            "fault labels (per-fault slips)": (
                faultnet.CarlsonLanger(net, k=16, sigma=0.01, alpha=1.0),
                {},
            ),
        },
        args.events,
        args.rounds,
    )


if __name__ == "__main__":
    main()
