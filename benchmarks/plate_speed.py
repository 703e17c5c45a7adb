"""What the moving plate and the viscous coupling cost: events/s and block-steps/s.

The ring of ``--blocks`` at k = 16, sigma = 0.01, alpha = 1 and the default rtol, from one
saved state (the plain model after ``--transient`` events): nu = eta = 0 with the default
options, the same with the exact crossings and without the solo cache (the path every run
with nu or eta takes), nu = 1e-3 and eta = 0.1, in alternating rounds (the machine drifts).
Each run advances from the saved state for ``--warmup`` seconds (kernels compiled, the new
model's own transient begun), then is timed for ``--seconds`` seconds, in calls of 100 events.

Events/s compares what a user waits for; block-steps/s (slipping blocks times steps) compares
the engine's work rate, since a moving plate changes the events themselves: while it moves,
stuck blocks anywhere on the ring reach the threshold during a long event, and events grow
(see the columns of mean blocks per event and mean duration).

    python benchmarks/plate_speed.py --blocks 2000 --rounds 3
"""

import argparse
import time

import numpy as np

import faultnet


def _run(model, state, warmup, seconds, solo_cache=True, **options):
    """(events/s, block-steps/s, mean n_blocks, mean duration) of one timed run."""
    sim = faultnet.Simulator(
        model, x0=state, options=faultnet.RunOptions(**options), solo_cache=solo_cache
    )
    tic = time.perf_counter()
    while time.perf_counter() - tic < warmup:
        sim.advance(100, progress=False)
    n = steps = 0
    blocks, durations = [], []
    tic = time.perf_counter()
    while (wall := time.perf_counter() - tic) < seconds:
        res = sim.advance(100, progress=False)
        n += len(res.events)
        steps += res.metadata["block_steps"]
        blocks.append(res.events.n_blocks.to_numpy())
        durations.append(res.events.duration.to_numpy())
    blocks, durations = np.concatenate(blocks), np.concatenate(durations)
    return n / wall, steps / wall, blocks.mean(), durations.mean()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=2000)
    ap.add_argument("--transient", type=int, default=20_000)
    ap.add_argument("--warmup", type=float, default=10.0)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    plain = faultnet.CarlsonLanger(faultnet.graphs.ring(args.blocks), k=16, sigma=0.01, alpha=1.0)
    state = faultnet.simulate(plain, args.transient, rng=1, progress=False).state
    cases = {
        "nu = eta = 0 (default options)": (plain, {}),
        "nu = eta = 0, exact, no solo cache": (plain, {"crossings": "exact", "solo_cache": False}),
        "nu = 1e-3": (plain.with_params(nu=1e-3), {}),
        "eta = 0.1": (plain.with_params(eta=0.1), {}),
    }
    runs = {name: [] for name in cases}
    for _ in range(args.rounds):
        for name, (model, kw) in cases.items():
            runs[name].append(_run(model, state, args.warmup, args.seconds, **kw))
    print(f"ring of {args.blocks} at alpha = 1, default rtol, from one state after "
          f"{args.transient:,} events; {args.warmup:g} s warm-up, {args.seconds:g} s timed, "
          f"{args.rounds} alternating rounds (best, and the range)")  # fmt: skip
    ev0 = max(r[0] for r in runs[next(iter(cases))])
    bs0 = max(r[1] for r in runs[next(iter(cases))])
    print("| case | events/s | vs plain | block-steps/s | vs plain | blocks/event | duration |")
    print("|---|---|---|---|---|---|---|")
    for name, values in runs.items():
        ev, bs = [v[0] for v in values], [v[1] for v in values]
        print(f"| {name} | {max(ev):,.0f} ({min(ev):,.0f}-{max(ev):,.0f}) | {max(ev) / ev0:.3f} "
              f"| {max(bs):.3g} ({min(bs):.3g}-{max(bs):.3g}) | {max(bs) / bs0:.2f} "
              f"| {np.mean([v[2] for v in values]):.1f} "
              f"| {np.mean([v[3] for v in values]):.2f} |")  # fmt: skip


if __name__ == "__main__":
    main()
