"""Do local regions change the statistics?  b on W4 with and without them.

Local regions (``faultnet._kernels.local``) handle the crossings inside large
events in small regions instead of stepping every slipping block to each one.
They change single large events by about the integrator's own error
(``tests/test_local.py``); this checks what matters for users: b on the
periodic 150^2 lattice (W4, the paper's Fig. 8b) with local regions, with the
exact whole-event treatment (``RunOptions(local_regions_from=inf)``), and with
the whole-event treatment at half the step.  For each seed, every run starts
from one state after a transient to plate time 2 from that seed's random
start; the runs decorrelate within a few thousand events (chaos), so they are
in effect independent samples.  Errors of one start are batch means, as in
``b_half_dt.py``.

One start is not enough for the LSQ tail fit: its b scatters between starts
by 0.026-0.030 (measured over 5 region runs and 4 whole-event runs of 10^6
events), more than the batch-means error of one start (0.015-0.025).  With
several seeds the pooled comparison uses the scatter of the per-start values.

    python benchmarks/b_local.py                       # 2x10^5 events per run, seed 1
    python benchmarks/b_local.py --events 50000        # quicker, looser
    python benchmarks/b_local.py --seed 2 3 4 5 --only local whole   # pooled, two runs each
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from b_half_dt import batch_b, pooled_difference  # the same errors

import faultnet
from faultnet import default_dt

#: run name -> (label, local regions on, fraction of the default dt)
RUNS = {
    "local": ("local regions", True, 1.0),
    "whole": ("whole event", False, 1.0),
    "half": ("whole, dt/2", False, 0.5),
}
FITS = {
    "LSQ [-7, 4]": lambda m: faultnet.fit_b_lsq(m, -7.0, 4.0),
    "MLE M >= -7": lambda m: faultnet.fit_b_mle(m, -7.0),
}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--events", type=int, default=200_000)
    ap.add_argument("--batches", type=int, default=10)
    ap.add_argument("--size", type=int, default=150, help="lattice side (default 150: W4)")
    ap.add_argument("--transient-t", type=float, default=2.0)
    ap.add_argument("--seed", type=int, nargs="+", default=[1], help="one start per seed")
    ap.add_argument("--only", nargs="+", choices=list(RUNS), default=list(RUNS), help="runs to do")
    args = ap.parse_args(argv)
    if len(args.only) < 2:
        ap.error("--only needs two runs to compare")
    runs = [r for r in RUNS if r in args.only]  # in the table's order
    starts = [one_start(seed, runs, args) for seed in args.seed]
    if len(starts) > 1:
        pooled(runs, args.seed, starts)


def one_start(seed, runs, args):
    """The runs from one seed's start; prints their table, returns {run: {fit: b}}."""
    graph = faultnet.graphs.square_lattice(args.size, args.size, periodic=True)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    tic = time.perf_counter()
    res = faultnet.simulate(model, 1000, rng=seed, progress=False, record_slips=False)
    while res.events.t.iloc[-1] < args.transient_t:
        res = faultnet.simulate(model, model.n, x0=res.state, progress=False, record_slips=False)
    state = res.state
    wall = time.perf_counter() - tic
    print(f"seed {seed}: transient to plate time {args.transient_t}: {wall:.0f} s")

    dt0 = default_dt(model)
    rows = {}
    for name in runs:
        label, local, frac = RUNS[name]
        options = faultnet.RunOptions(
            dt=dt0 * frac, local_regions_from=32 if local else float("inf")
        )
        tic = time.perf_counter()
        res = faultnet.simulate(model, args.events, x0=state, options=options)
        wall = time.perf_counter() - tic
        M = res.events.M.to_numpy()
        work = res.metadata["block_steps"] / args.events
        fitted = {k: batch_b(M, f, args.batches) for k, f in FITS.items()}
        rows[name] = (dt0 * frac, wall, work, fitted)

    print(f"\nperiodic {args.size}^2, alpha 1, seed {seed}, {args.events} events per run, "
          "batch-means errors")  # fmt: skip
    print(
        f"{'run':14} {'dt':>8} {'wall s':>7} {'bsteps/ev':>9}  "
        + "  ".join(f"{k:>18}" for k in FITS)
    )
    for name, (dt, wall, work, res) in rows.items():
        cells = "  ".join(f"{b:>9.4f} ± {e:.4f}" for b, e in res.values())
        print(f"{RUNS[name][0]:14} {dt:8.5f} {wall:7.0f} {work:9.0f}  {cells}")
    first = runs[0]
    for k in FITS:
        b0, e0 = rows[first][3][k]
        for name in runs[1:]:
            b1, e1 = rows[name][3][k]
            z = (b0 - b1) / np.hypot(e0, e1)
            print(
                f"{k}: {RUNS[first][0]} - {RUNS[name][0]}: {b0 - b1:+.4f} = {z:+.2f} "
                "combined standard errors"
            )
    return {name: {k: row[3][k][0] for k in FITS} for name, row in rows.items()}


def pooled(runs, seeds, starts):
    """Mean b of each run over the starts; differences with errors from their scatter."""
    print(f"\npooled over seeds {seeds} (errors from the scatter between starts)")
    first = runs[0]
    for k in FITS:
        b = {name: np.array([s[name][k] for s in starts]) for name in runs}
        means = ", ".join(
            f"{RUNS[n][0]} {v.mean():.4f} ± {v.std(ddof=1) / np.sqrt(v.size):.4f}"
            for n, v in b.items()
        )
        print(f"{k}: {means}")
        for name in runs[1:]:
            d, se = pooled_difference(b[first], b[name])
            print(f"  {RUNS[first][0]} - {RUNS[name][0]}: {d:+.4f} = {d / se:+.2f} standard errors")


if __name__ == "__main__":
    main()
