"""Ensemble speed-up: the same sweep on 1 worker process and on every core.

    python benchmarks/ensemble.py                  # 8 points x 100,000 events
    python benchmarks/ensemble.py --events 20000   # quicker

The sweep is 4 alpha values x 2 replicas on ring:2000 (independent points,
each with its own child seed).  Both runs use a process pool (``workers=1``
and ``workers=os.cpu_count()``) so both pay the same start-up per worker; the
catalogs of the two runs are compared to show the parallel run did the same
work.  Needs an otherwise idle machine.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

from faultnet.io.parquet import read_catalog
from faultnet.runs.sweep.driver import sweep


def run(workers, events, out):
    tic = time.perf_counter()
    table = sweep(
        graph="ring:2000",
        alpha=[0.5, 1.0, 1.5, 2.0],
        replicas=2,
        events=events,
        seed=2026,
        out=out,
        workers=workers,
        progress=False,
    )
    return time.perf_counter() - tic, table


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--events", type=int, default=100_000)
    args = ap.parse_args(argv)
    cores = os.cpu_count() or 1
    with tempfile.TemporaryDirectory() as tmp:
        one, t1 = run(1, args.events, os.path.join(tmp, "one"))
        many, tn = run(cores, args.events, os.path.join(tmp, "many"))
        same = all(
            read_catalog(os.path.join(tmp, "one", a)).events.equals(
                read_catalog(os.path.join(tmp, "many", b)).events
            )
            for a, b in zip(t1["part"], tn["part"], strict=True)
        )
    n = len(t1)
    print(f"sweep: {n} points x {args.events} events (ring:2000, alpha 0.5-2, 2 replicas)")
    print(f"{'workers':>8} {'wall s':>8} {'points/min':>11}")
    print(f"{1:>8} {one:>8.1f} {60 * n / one:>11.1f}")
    print(f"{cores:>8} {many:>8.1f} {60 * n / many:>11.1f}")
    print(f"speed-up on {cores} cores: {one / many:.2f}x; catalogs identical: {same}")


if __name__ == "__main__":
    main()
