"""Do local regions change the statistics?  b on W4 with and without them.

Local regions (``faultnet._kernels.local``) handle the crossings inside large
events in small regions instead of stepping every slipping block to each one.
They change single large events by about the integrator's own error
(``tests/test_local.py``); this checks what matters for users: b on the
periodic 150^2 lattice (W4, the paper's Fig. 8b) with local regions, with the
exact whole-event treatment (``simulate.LOCAL_REGIONS_FROM = inf``), and with
the whole-event treatment at half the step.  All runs start from one state
after a transient to plate time 2 and decorrelate within a few thousand
events (chaos), so they are in effect independent samples.  Errors are batch
means, as in ``b_half_dt.py``.

    python benchmarks/b_local.py                  # 2x10^5 events per run
    python benchmarks/b_local.py --events 50000   # quicker, looser
"""

from __future__ import annotations

import argparse
import importlib
import time

import numpy as np
from b_half_dt import batch_b  # the same batch-means errors

import faultnet
from faultnet.simulate import default_dt

SIM = importlib.import_module("faultnet.simulate")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--events", type=int, default=200_000)
    ap.add_argument("--batches", type=int, default=10)
    ap.add_argument("--size", type=int, default=150, help="lattice side (default 150: W4)")
    ap.add_argument("--transient-t", type=float, default=2.0)
    args = ap.parse_args(argv)

    graph = faultnet.graphs.square_lattice(args.size, args.size, periodic=True)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    tic = time.perf_counter()
    res = faultnet.simulate(model, 1000, rng=1, progress=False, record_slips=False)
    while res.events.t.iloc[-1] < args.transient_t:
        res = faultnet.simulate(model, model.n, x0=res.state, progress=False, record_slips=False)
    state = res.state
    print(f"transient to plate time {args.transient_t}: {time.perf_counter() - tic:.0f} s")

    fits = {
        "LSQ [-7, 4]": lambda m: faultnet.fit_b_lsq(m, -7.0, 4.0),
        "MLE M >= -7": lambda m: faultnet.fit_b_mle(m, -7.0),
    }
    dt0 = default_dt(model)
    local_from = SIM.LOCAL_REGIONS_FROM
    runs = (
        ("local regions", local_from, dt0),
        ("whole event", float("inf"), dt0),
        ("whole, dt/2", float("inf"), dt0 / 2),
    )
    rows = []
    try:
        for label, threshold, dt in runs:
            SIM.LOCAL_REGIONS_FROM = threshold
            tic = time.perf_counter()
            res = faultnet.simulate(model, args.events, x0=state, dt=dt, record_slips=False)
            wall = time.perf_counter() - tic
            M = res.events.M.to_numpy()
            work = res.metadata["block_steps"] / args.events
            fitted = {k: batch_b(M, f, args.batches) for k, f in fits.items()}
            rows.append((label, dt, wall, work, fitted))
    finally:
        SIM.LOCAL_REGIONS_FROM = local_from

    print(f"\nperiodic {args.size}^2, alpha 1, {args.events} events per run, batch-means errors")
    print(
        f"{'run':14} {'dt':>8} {'wall s':>7} {'bsteps/ev':>9}  "
        + "  ".join(f"{k:>18}" for k in fits)
    )
    for label, dt, wall, work, res in rows:
        cells = "  ".join(f"{b:>9.4f} ± {e:.4f}" for b, e in res.values())
        print(f"{label:14} {dt:8.5f} {wall:7.0f} {work:9.0f}  {cells}")
    for k in fits:
        (b0, e0) = rows[0][4][k]
        for label, _, _, _, res in rows[1:]:
            b1, e1 = res[k]
            z = (b0 - b1) / np.hypot(e0, e1)
            print(f"{k}: local - {label}: {b0 - b1:+.4f} = {z:+.2f} combined standard errors")


if __name__ == "__main__":
    main()
