"""Work and time of single large events, each from its own pre-event state.

Whole runs from one saved state compare two versions of the code badly: the
dynamics is chaotic, so a change that moves one crossing by round-off makes the
runs diverge after a few thousand events, and then the event mix differs (W4:
476 against 506 block-steps per event for two versions that each made every
event cheaper).  This tool fixes the events instead:

- ``save`` runs a workload past its transient (as ``run.py`` does), then N
  events, and keeps the pre-event states of the first COUNT events with at
  least MIN slipping blocks, with their size and slip;
- ``time`` runs each saved event alone from its state (best of ``--repeat``
  rounds) and prints the time inside the event loop (``wall_time_s`` of each
  run: without the set-up of a ``simulate`` call, about 10 ms, which would
  otherwise dominate events of a few hundred blocks), the block-steps and the
  work counters summed over the events, and whether each event still has its
  saved size, with the largest relative change of S against the saved value
  (restarting from a saved state alone moves S by round-off, ~1e-11).

Run ``time`` once per version of the code, alternating, on the same file::

    python benchmarks/events_ab.py save W4 /tmp/big_W4.npz --min-blocks 100 --count 40
    python benchmarks/events_ab.py time /tmp/big_W4.npz --repeat 3
    PYTHONPATH=/path/to/other/checkout python benchmarks/events_ab.py time /tmp/big_W4.npz

The time of a ``simulate`` call around its event (about 0.1 ms) counts too: it dominates small
events.  Time solo slips (``save W4 /tmp/solo_W4.npz --min-blocks 1 --max-blocks 1 --count
1000``) to subtract it.
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np
from run import SIGMA, WORKLOADS, K, _warm_state, build_graph

COUNTERS = ("partial_block_steps", "interpolated_crossings")


def _model(wid):
    import faultnet

    return faultnet.CarlsonLanger(build_graph(wid), k=K, sigma=SIGMA, alpha=WORKLOADS[wid][1])


def save(wid, path, min_blocks, count, events, transient_t, max_blocks=None):
    """Keep the pre-event states of the first ``count`` events of min_blocks..max_blocks blocks."""
    import faultnet

    model = _model(wid)
    start, n_trans, t_end, wall = _warm_state(model, transient_t)
    print(f"{wid}: transient of {n_trans} events to plate time {t_end:.2f} ({wall:.0f} s)")
    run = faultnet.simulate(model, events, x0=start, progress=False, record_slips=False)
    n_blocks = run.events.n_blocks.to_numpy()
    top = n_blocks.max() if max_blocks is None else max_blocks
    picked = np.flatnonzero((n_blocks >= min_blocks) & (n_blocks <= top))[:count]
    if picked.size == 0:
        raise SystemExit(f"no event of {min_blocks}-{top} blocks in {events}; widen the range")
    xs, ws, state, done = [], [], start, 0
    for e in picked:
        if e > done:  # the same trajectory, continued up to event e
            state = faultnet.simulate(
                model, int(e - done), x0=state, progress=False, record_slips=False
            ).state
            done = int(e)
        xs.append(state.x.copy())
        ws.append(state.offset + state.w)
    np.savez(
        path,
        wid=wid,
        x=np.array(xs),
        w=np.array(ws),
        n_blocks=n_blocks[picked],
        S=run.events.S.to_numpy()[picked],
    )
    sizes = n_blocks[picked]
    print(
        f"saved {picked.size} events of {sizes.min()}-{sizes.max()} blocks "
        f"(mean {sizes.mean():.0f}) from {events} to {path}"
    )


def time_events(path, repeat, rtol=None):
    """Each saved event alone; returns the row printed (a dict)."""
    import faultnet

    options = faultnet.RunOptions() if rtol is None else faultnet.RunOptions(rtol=rtol)

    d = np.load(path)
    wid = str(d["wid"])
    model = _model(wid)
    states = [faultnet.State.from_x(x, float(w)) for x, w in zip(d["x"], d["w"], strict=True)]
    faultnet.simulate(model, 1, x0=states[0], progress=False, options=options)  # compile/load
    best = None
    for _ in range(repeat):
        loop = 0.0
        work = dict.fromkeys(("block_steps", *COUNTERS), 0)
        sizes, slips = [], []
        for st in states:
            res = faultnet.simulate(model, 1, x0=st, progress=False, options=options)
            loop += res.metadata["wall_time_s"]
            for k in work:
                work[k] += int(res.metadata.get(k, 0))
            sizes.append(int(res.events.n_blocks.iloc[0]))
            slips.append(float(res.events.S.iloc[0]))
        if best is None or loop < best[0]:
            best = (loop, work, sizes, slips)
    loop, work, sizes, slips = best
    row = {
        "file": path,
        "workload": wid,
        "code": os.path.dirname(os.path.dirname(faultnet.__file__)),
        "events": len(states),
        "rtol": options.rtol,
        "loop_s": loop,
        "us_per_event": 1e6 * loop / len(states),
        "ns_per_block_step": 1e9 * loop / work["block_steps"] if work["block_steps"] else None,
        **work,
        "same_sizes": bool(np.array_equal(sizes, d["n_blocks"])),
        "max_rel_dS": float(np.max(np.abs(np.array(slips) / d["S"] - 1.0))),
    }
    print(
        f"{wid} {row['code']} (rtol {row['rtol']:g}): "
        f"{row['events']} events {loop:.3f} s ({row['us_per_event']:.1f} µs each), "
        f"{work['block_steps']:,} block-steps"
        + (f" ({row['ns_per_block_step']:.1f} ns each), " if work["block_steps"] else ", ")
        + ", ".join(f"{k} {work[k]:,}" for k in COUNTERS)
        + f"; sizes as saved: {row['same_sizes']}, largest |S/S_saved - 1| {row['max_rel_dS']:.1e}"
    )
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    sv = sub.add_parser("save", help="keep the pre-event states of large events")
    sv.add_argument("workload", choices=sorted(WORKLOADS))
    sv.add_argument("path", help=".npz file to write")
    sv.add_argument("--min-blocks", type=int, default=100)
    sv.add_argument("--max-blocks", type=int, help="largest size kept (default: any)")
    sv.add_argument("--count", type=int, default=40)
    sv.add_argument("--events", type=int, default=20_000, help="events searched")
    sv.add_argument("--transient-t", type=float, default=2.0)
    tm = sub.add_parser("time", help="time each saved event alone")
    tm.add_argument("path", help=".npz file written by save")
    tm.add_argument("--repeat", type=int, default=3, help="rounds; the fastest counts")
    tm.add_argument("--json", help="append the row as a JSON line to this file")
    tm.add_argument("--rtol", type=float, help="RunOptions.rtol for this run (default 1e-6)")
    args = ap.parse_args(argv)
    if args.cmd == "save":
        if args.min_blocks < 1 or args.count < 1 or args.events < 1:
            ap.error("--min-blocks, --count and --events must be >= 1")
        if args.max_blocks is not None and args.max_blocks < args.min_blocks:
            ap.error("--max-blocks must be >= --min-blocks")
        tic = time.perf_counter()
        save(
            args.workload,
            args.path,
            args.min_blocks,
            args.count,
            args.events,
            args.transient_t,
            args.max_blocks,
        )
        print(f"{time.perf_counter() - tic:.0f} s")
        return
    if args.repeat < 1:
        ap.error("--repeat must be >= 1")
    row = time_events(args.path, args.repeat, args.rtol)
    if args.json:
        with open(args.json, "a") as fh:
            fh.write(json.dumps(row) + "\n")


if __name__ == "__main__":
    main()
