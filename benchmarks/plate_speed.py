"""What the moving plate and the viscous coupling cost: events/s and block-steps/s.

The ring of ``--blocks`` at k = 16, sigma = 0.01, alpha = 1 and the default rtol, from one
saved state (the plain model after ``--transient`` events): nu = eta = 0, nu = 1e-3, eta = 0.1
and nu = 1e-2, in alternating rounds (the machine drifts).  Each run first takes
``--warmup`` events from the saved state (kernels compiled, the new model's own transient
begun), then times ``--events`` more.  A plain run takes the interpolated crossings and the
cache of lone slips; a run with nu or eta takes the exact crossings and integrates every
event, so a second plain row, ``crossings='exact'`` without the solo cache, shows how much of
the difference is the treatment.

    python benchmarks/plate_speed.py --blocks 2000 --events 30000 --rounds 3
"""

import argparse
import time

import faultnet


def _rate(model, state, warmup, n, solo_cache=True, **options):
    opts = faultnet.RunOptions(**options)
    sim = faultnet.Simulator(model, x0=state, options=opts, solo_cache=solo_cache)
    sim.advance(warmup, progress=False)
    tic = time.perf_counter()
    res = sim.advance(n, progress=False)
    wall = time.perf_counter() - tic
    md = res.metadata
    return n / wall, md["block_steps"] / wall, float(res.events.n_blocks.mean())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=2000)
    ap.add_argument("--events", type=int, default=30_000)
    ap.add_argument("--transient", type=int, default=20_000)
    ap.add_argument("--warmup", type=int, default=3000)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    plain = faultnet.CarlsonLanger(faultnet.graphs.ring(args.blocks), k=16, sigma=0.01, alpha=1.0)
    state = faultnet.simulate(plain, args.transient, rng=1, progress=False).state
    cases = {
        "nu = eta = 0 (default options)": (plain, {}),
        "nu = eta = 0, exact, no solo cache": (plain, {"crossings": "exact", "solo_cache": False}),
        "nu = 1e-3": (plain.with_params(nu=1e-3), {}),
        "eta = 0.1": (plain.with_params(eta=0.1), {}),
        "nu = 1e-2": (plain.with_params(nu=1e-2), {}),
    }
    rates = {name: [] for name in cases}
    for _ in range(args.rounds):
        for name, (model, kw) in cases.items():
            rates[name].append(_rate(model, state, args.warmup, args.events, **kw))
    print(f"ring of {args.blocks} at alpha = 1, default rtol: {args.events:,} events after "
          f"{args.warmup:,} from one state, {args.rounds} alternating rounds")  # fmt: skip
    base = max(r[0] for r in rates[next(iter(cases))])
    print(f"  {'':36} {'events/s (best, range)':>30} {'vs plain':>9} {'block-steps/s':>14}"
          f" {'mean n_blocks':>14}")  # fmt: skip
    for name, values in rates.items():
        ev = [v[0] for v in values]
        best = max(values)
        print(f"  {name:36} {best[0]:12,.0f} ({min(ev):,.0f}-{best[0]:,.0f})"
              f" {best[0] / base:9.2f} {best[1]:14.3g} {best[2]:14.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
