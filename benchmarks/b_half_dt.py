"""Does b on W1 depend on dt?  Default dt against half of it, same start.

The accuracy check of the default step: b on W1 should agree with a run at
half the dt within its statistical error.  Both runs start from one state taken after a
transient (plate time >= 5, as the paper-scale Fig. 8a entry); the dynamics is
chaotic, so the two catalogs decorrelate within a few thousand events and are
in effect independent samples of the same statistics.

Errors are batch means: the run is cut into ``--batches`` consecutive blocks,
b is fitted in each, and the standard error is the scatter of the block values
over sqrt(batches).  This accounts for correlations between events, which the
regression standard error of a single fit does not.

    python benchmarks/b_half_dt.py                 # 10^6 events per run
    python benchmarks/b_half_dt.py --events 200000 # quicker, looser
    python benchmarks/b_half_dt.py --seed 1 2 3 4  # several starts, pooled

Batch means understate the run-to-run scatter of b on W1 (four starts of 10^6
events gave LSQ differences of -0.0063, +0.0030, -0.0022, +0.0048 between dt and dt / 2, quoted
as -4.45 to +1.93 combined standard errors).  With several seeds the pooled comparison uses the
scatter of the per-start values instead.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import faultnet
from faultnet import default_dt


def batch_b(M, fit, batches):
    parts = np.array_split(M, batches)
    vals = np.array([fit(p).b for p in parts])
    return fit(M).b, vals.std(ddof=1) / np.sqrt(batches)


def pooled_difference(a, b):
    """Mean of ``a`` minus mean of ``b`` (b per independent start), and its standard error
    from the scatter of each between starts."""
    a, b = np.asarray(a), np.asarray(b)
    return a.mean() - b.mean(), np.hypot(a.std(ddof=1), b.std(ddof=1)) / np.sqrt(a.size)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--events", type=int, default=1_000_000)
    ap.add_argument("--batches", type=int, default=10)
    ap.add_argument("--seed", type=int, nargs="+", default=[1])
    args = ap.parse_args(argv)
    pooled = [compare(seed, args.events, args.batches) for seed in args.seed]
    if len(pooled) > 1:
        print(f"\npooled over seeds {args.seed} (errors from the scatter between starts)")
        for k in pooled[0]:
            b = np.array([p[k] for p in pooled])
            d, se = pooled_difference(b[:, 0], b[:, 1])
            print(
                f"{k}: default dt {b[:, 0].mean():.4f}, dt / 2 {b[:, 1].mean():.4f}, "
                f"difference {d:+.4f} = {d / se:+.2f} standard errors"
            )


def compare(seed, events, batches):
    """One start: b at the default dt and at dt / 2; returns {fit: (b_dt, b_half)}."""

    model = faultnet.CarlsonLanger(faultnet.graphs.ring(2000), k=16, sigma=0.01, alpha=1.0)
    rng = np.random.default_rng(seed)
    state = rng.uniform(0.0, 0.01, model.n)
    tic = time.perf_counter()
    n_trans = 0
    while True:
        res = faultnet.simulate(model, 50_000, x0=state, progress=False)
        state, n_trans = res.state, n_trans + len(res.events)
        if res.events.t.iloc[-1] >= 5.0:
            break
    print(f"transient: {n_trans} events to plate time 5 ({time.perf_counter() - tic:.0f} s)")

    fits = {
        "LSQ [-6, 3]": lambda m: faultnet.fit_b_lsq(m, -6.0, 3.0),
        "MLE M >= -6 (M <= 3)": lambda m: faultnet.fit_b_mle(m[m <= 3.0], -6.0),
    }
    dt0 = default_dt(model)
    rows = []
    for label, dt in (("default dt", dt0), ("dt / 2", dt0 / 2)):
        tic = time.perf_counter()
        res = faultnet.simulate(model, events, x0=state, dt=dt, progress=True)
        wall = time.perf_counter() - tic
        M = res.events.M.to_numpy()
        rows.append((label, dt, wall, {k: batch_b(M, f, batches) for k, f in fits.items()}))

    print(f"\nW1 (ring 2000, alpha 1), seed {seed}, {events} events per run, batch-means errors")
    print(f"{'run':11} {'dt':>9} {'wall s':>7}  " + "  ".join(f"{k:>22}" for k in fits))
    for label, dt, wall, res in rows:
        cells = "  ".join(f"{b:>13.4f} ± {e:.4f}" for b, e in res.values())
        print(f"{label:11} {dt:9.5f} {wall:7.0f}  {cells}")
    for k in fits:
        (b1, e1), (b2, e2) = rows[0][3][k], rows[1][3][k]
        z = (b1 - b2) / np.hypot(e1, e2)
        print(f"{k}: difference {b1 - b2:+.4f} = {z:+.2f} combined standard errors")
    return {k: (rows[0][3][k][0], rows[1][3][k][0]) for k in fits}


if __name__ == "__main__":
    main()
