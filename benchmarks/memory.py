"""Memory of a long run on a 10^6-block lattice: 10^7 events, catalog streamed to Parquet.

Run by hand (about 40 minutes at L = 1024 on the reference machine)::

    python benchmarks/memory.py                      # L = 1024, 10^7 events
    python benchmarks/memory.py --size 256 --events 200000   # a short check

The periodic L x L lattice (k = 16, sigma = 0.01, alpha = 1) starts from the
steady state of the L = 128 lattice, tiled (as in the scaling series of
``run.py``: a random start spends hours in its first system-wide events).
Events are run in chunks of ``--chunk``, each chunk continuing exactly from the
previous state, and each chunk's catalog is written to its own Parquet part and
dropped, so memory is O(N + chunk).  Every ``--report`` events a row gives the
events done, the rate over the last interval, the resident memory now (from
/proc) and its peak so far (``ru_maxrss``).  The last line is a JSON summary.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import run as suite  # noqa: E402  (the graphs and tiled states of the suite)


def rss_mib():
    """Resident memory of this process now, in MiB (Linux /proc)."""
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def peak_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--size", type=int, default=1024, help="L (a multiple of --tile-from)")
    ap.add_argument("--events", type=float, default=1e7, help="events after the start state")
    ap.add_argument("--chunk", type=int, default=100_000, help="events per Parquet part")
    ap.add_argument("--report", type=float, default=5e5, help="events between table rows")
    ap.add_argument("--tile-from", type=int, default=128, help="L of the steady state tiled")
    ap.add_argument("--transient-t", type=float, default=2.0, help="plate time of its transient")
    ap.add_argument("--out", help="folder for the parts (default: a temporary one, removed)")
    args = ap.parse_args(argv)
    if args.size % args.tile_from:
        ap.error("--size must be a multiple of --tile-from")
    import faultnet

    n_events = int(args.events)
    model = faultnet.CarlsonLanger(suite.build_graph(f"L{args.size}"), k=16.0, sigma=0.01)
    state, n_trans, t_end, wall_t = suite._tiled_state(args.tile_from, args.size, args.transient_t)
    out = args.out or tempfile.mkdtemp(prefix="faultnet-memory-")
    os.makedirs(out, exist_ok=True)
    print(
        f"L = {args.size} ({model.n} blocks), start: L = {args.tile_from} steady state after "
        f"{n_trans} events (plate time {t_end:.2f}, {wall_t:.0f} s), tiled; parts in {out}",
        flush=True,
    )
    cols = ("events", 10), ("plate t", 8), ("events/s", 9), ("RSS MiB", 8), ("peak MiB", 8)
    print(" ".join(f"{c:>{w}}" for c, w in cols), f"{'wall s':>7}")
    done, n_part, block_steps = 0, 0, 0
    tic = last_t = time.perf_counter()
    last_done = 0
    t_plate = 0.0
    while done < n_events:
        n = min(args.chunk, n_events - done)
        res = faultnet.simulate(model, n, x0=state, progress=False, record_slips=False)
        res.events.to_parquet(os.path.join(out, f"part-{n_part:06d}.parquet"))
        state, t_plate = res.state, float(res.events.t.iloc[-1])
        block_steps += res.metadata["block_steps"]
        done += n
        n_part += 1
        del res
        if done - last_done >= args.report or done == n_events:
            now = time.perf_counter()
            rate = (done - last_done) / (now - last_t)
            print(
                f"{done:>10,} {t_plate:>8.3f} {rate:>9,.0f} {rss_mib():>8.0f} {peak_mib():>8.0f} "
                f"{now - tic:>7.0f}",
                flush=True,
            )
            last_t, last_done = now, done
    wall = time.perf_counter() - tic
    summary = {
        "blocks": model.n,
        "events": done,
        "parts": n_part,
        "wall_s": wall,
        "events_per_s": done / wall,
        "block_steps_per_s": block_steps / wall,
        "plate_time_end": t_plate,
        "peak_rss_mib": peak_mib(),
    }
    if not args.out:
        shutil.rmtree(out)
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
