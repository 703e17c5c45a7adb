"""faultnet benchmark suite: throughput, work and memory per workload.

Run by hand (never a timed unit test)::

    python benchmarks/run.py            # all workloads, default lengths
    python benchmarks/run.py --quick    # shorter runs, same table
    python benchmarks/run.py W1 W4      # a subset

Each workload runs in its own subprocess so peak memory (ru_maxrss) is its
own.  Throughput is measured after a transient (from a random state until
plate time ``--transient-t``, default 2: every block has slipped about twice),
with the kernel already compiled; compile times are measured separately
(``--compile``) with a cold, empty Numba cache directory and with the warm
cache.  ``--scaling`` adds periodic square lattices L = 32 ... 1024 (built as
:class:`faultnet.SparseGraph`); ``benchmarks/plot_scaling.py`` draws them.  The columns
"largest" and "steps" are the largest event's slipping blocks and its share of the run's steps:
a single plate-wide event can carry most of a large lattice's block-steps.  "set-up" is the
model's first ``simulate`` call (one event), timed apart from the measured events: on 10⁶ blocks
it takes 1.5-1.8 s (the step's scale from the stiffness spectrum, the work arrays), which in a
run of 5x10^4 events would read as a 40% slower lattice.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

K, SIGMA = 16.0, 0.01
#: children share the tiled scaling runs' base steady state through this directory
STATE_DIR_ENV = "FAULTNET_BENCH_STATES"

WORKLOADS = {
    "W1": ("ring N=2000", 1.0),
    "W2": ("ring N=2000", 2.0),
    "W3": ("ring N=2000", 0.25),
    "W4": ("periodic square 150x150", 1.0),
    "W5": ("largest cluster, square 150x150, p=0.5927", 0.9),
    "W6": ("critical cluster, triangular 150x150, p=0.5", 1.0),
}


def build_graph(wid, size=150):
    from faultnet import graphs

    if wid in ("W1", "W2", "W3"):
        return graphs.ring(2000)
    if wid == "W4":
        return graphs.square_lattice(size, size, periodic=True)
    if wid == "W5":
        return graphs.site_percolation(graphs.square_lattice(size, size), 0.5927, rng=1)
    if wid == "W6":
        return graphs.site_percolation(graphs.triangular_lattice(size, size), 0.5, rng=1)
    if wid.startswith("L"):
        n = int(wid[1:])
        return graphs.square_lattice(n, n, periodic=True, sparse=True)
    raise SystemExit(f"unknown workload {wid!r}; choose from {sorted(WORKLOADS)}")


def _warm_state(model, transient_t):
    """Random start, then events until plate time ``transient_t``; (state, events, wall)."""
    import faultnet

    tic = time.perf_counter()
    warm = faultnet.simulate(model, 1000, rng=1, progress=False)
    n_trans = 1000
    while warm.events.t.iloc[-1] < transient_t:
        chunk = max(1000, model.n)  # about one event per block: small overshoot of the time
        warm = faultnet.simulate(model, chunk, x0=warm.state, progress=False, record_slips=False)
        n_trans += chunk
    return warm.state, n_trans, float(warm.events.t.iloc[-1]), time.perf_counter() - tic


def _tiled_state(base_l, n, transient_t):
    """A steady state of the periodic base_l lattice, tiled to n x n (n a multiple of base_l).

    A periodic lattice's state tiles exactly (forces match across the seams), so the big
    lattice starts in the same correlated regime as the small one without the transient,
    which grows like N (hours at 1024^2).  Equal tiles have equal failure keys, so each
    event of the base repeats in every tile: the event mix is the base's, which makes
    block-steps/s comparable across sizes.
    """
    import faultnet

    saved = os.path.join(os.environ.get(STATE_DIR_ENV, ""), f"L{base_l}_t{transient_t}.npz")
    if os.environ.get(STATE_DIR_ENV) and os.path.exists(saved):
        d = np.load(saved)
        st = faultnet.State.from_x(d["x"], float(d["w"]))
        n_trans, t_end, wall = int(d["n_trans"]), float(d["t_end"]), float(d["wall"])
    else:
        base = faultnet.CarlsonLanger(build_graph(f"L{base_l}"), k=K, sigma=SIGMA, alpha=1.0)
        st, n_trans, t_end, wall = _warm_state(base, transient_t)
        if os.environ.get(STATE_DIR_ENV):
            np.savez(saved, x=st.x, w=st.offset + st.w, n_trans=n_trans, t_end=t_end, wall=wall)
    x = np.tile(st.x.reshape(base_l, base_l), (n // base_l, n // base_l)).ravel()
    return faultnet.State.from_x(x, st.offset + st.w), n_trans, t_end, wall


def measure(wid, alpha, transient_t, events, tile_from=0):
    """Run in a child process: transient, then the timed run; print JSON."""
    import faultnet

    model = faultnet.CarlsonLanger(build_graph(wid), k=K, sigma=SIGMA, alpha=alpha)
    n = int(wid[1:]) if wid.startswith("L") else 0
    if tile_from and n >= tile_from and n % tile_from == 0:
        start, n_trans, t_end, transient_wall = _tiled_state(tile_from, n, transient_t)
    else:
        start, n_trans, t_end, transient_wall = _warm_state(model, transient_t)
    # the model's one-off set-up (its step from the stiffness spectrum, a Lanczos run that takes
    # 0.6 s on 10^6 blocks) and the first touch of the work arrays, timed on their own
    tic = time.perf_counter()
    faultnet.simulate(model, 1, x0=start, progress=False, record_slips=False)
    setup = time.perf_counter() - tic
    tic = time.perf_counter()
    res = faultnet.simulate(model, events, x0=start, progress=False, record_slips=False)
    wall = time.perf_counter() - tic
    md = res.metadata
    out = {
        "id": wid,
        "blocks": model.n,
        "alpha": alpha,
        "events": events,
        "transient_events": n_trans,
        "transient_t": t_end,
        "transient_wall_s": transient_wall,
        "tiled_from": tile_from if (tile_from and n >= tile_from) else 0,
        "setup_s": setup,
        "wall_s": wall,
        "events_per_s": events / wall,
        "block_steps_per_s": md["block_steps"] / wall,
        "us_per_event": 1e6 * wall / events,
        "mean_blocks": float(res.events.n_blocks.mean()),
        # one plate-wide event can carry most of a large lattice's work: its size and steps
        "max_blocks": int(res.events.n_blocks.max()),
        "max_event_step_share": float(
            res.events.n_steps.iloc[int(res.events.n_blocks.to_numpy().argmax())] / md["n_steps"]
        ),
        "steps_per_event": md["n_steps"] / events,
        "solo_fraction": md["solo_events"] / events,
        "dt": res.dt,
        "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    }
    print(json.dumps(out))


#: the first-run models of the compile measurement: each compiles its own entry kernel (a ring
#: and a periodic lattice with interpolated crossings, the default; a ring at alpha 0.1, where
#: only the exact treatment is calibrated)
COMPILE_GRAPHS = {
    "ring": "faultnet.graphs.ring(10)",
    "lattice": "faultnet.graphs.square_lattice(20, 20, periodic=True)",
    "exact": "faultnet.graphs.ring(10), alpha=0.1",
}


def compile_times(graph):
    """Seconds for the first simulate call, cold (empty cache) and warm; and the import."""
    code = (
        "import time, faultnet; t=time.perf_counter();"
        f"m=faultnet.CarlsonLanger({COMPILE_GRAPHS[graph]});"
        "faultnet.simulate(m, 1, rng=1, progress=False);"
        "print(time.perf_counter()-t)"
    )
    imp = "import time; t=time.perf_counter(); import faultnet; print(time.perf_counter()-t)"
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        cold = float(subprocess.check_output([sys.executable, "-c", code], env=env))
        warm = float(subprocess.check_output([sys.executable, "-c", code], env=env))
        import_s = float(subprocess.check_output([sys.executable, "-c", imp], env=env))
    return cold, warm, import_s


def _compile_rounds(rounds):
    """Print compile times of a first run on a ring and on a lattice, alternating."""
    for r in range(rounds):
        for graph in COMPILE_GRAPHS:
            cold, warm, import_s = compile_times(graph)
            print(
                f"round {r + 1}, {graph:7}: import faultnet {import_s:.2f} s; first simulate "
                f"{cold:.1f} s cold cache, {warm:.2f} s warm cache",
                flush=True,
            )


def _child_run(args, wid, alpha, scale, env):
    """One workload in a fresh subprocess; its JSON row."""
    events = args.events or (200_000 if wid.startswith("W") else 20_000) // scale
    tile = args.tile_from if wid.startswith("L") else 0
    cmd = [sys.executable, __file__, "--child", wid, str(alpha), str(args.transient_t)]
    out = subprocess.check_output([*cmd, str(events), str(tile)], env=env)
    return json.loads(out.decode().strip().splitlines()[-1])


def _median_row(rows):
    """The run with the median block-steps/s (the lower middle one for an even count)."""
    ranked = sorted(rows, key=lambda r: r["block_steps_per_s"])
    row = dict(ranked[(len(ranked) - 1) // 2])
    row["rounds"] = len(rows)
    row["block_steps_per_s_all"] = [r["block_steps_per_s"] for r in rows]
    row["events_per_s_all"] = [r["events_per_s"] for r in rows]
    return row


def _print_row(row, alpha):
    print(
        f"{row['id']:5} {row['workload']:46} {row['blocks']:>8} {alpha:>5} "
        f"{row['events_per_s']:>10,.0f} {row['block_steps_per_s']:>14,.0f} "
        f"{row['mean_blocks']:>9.2f} {row['steps_per_event']:>8.1f} "
        f"{row['solo_fraction']:>5.2f} {row['peak_rss_mib']:>8.0f} "
        f"{row['max_blocks']:>9} {row['max_event_step_share']:>6.0%} {row['setup_s']:>7.2f}",
        flush=True,
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("ids", nargs="*", help="workloads (default: W1..W6)")
    ap.add_argument("--quick", action="store_true", help="10x shorter runs")
    ap.add_argument("--events", type=int, default=None, help="timed events per workload")
    ap.add_argument(
        "--transient-t", type=float, default=2.0, help="plate time of the transient (default 2)"
    )
    ap.add_argument("--compile", action="store_true", help="also measure JIT compile times")
    ap.add_argument(
        "--compile-only",
        type=int,
        metavar="R",
        help="only the compile times: R rounds, each on a ring and on a lattice",
    )
    ap.add_argument("--scaling", action="store_true", help="periodic square L=32..1024 at alpha=1")
    ap.add_argument("--scaling-only", action="store_true", help="the scaling series alone")
    ap.add_argument("--sizes", help="comma-separated L of the scaling series (default 32..1024)")
    ap.add_argument(
        "--tile-from",
        type=int,
        default=128,
        help="scaling series: start L = m * this from its steady state, tiled (0: own transient)",
    )
    ap.add_argument(
        "--repeat",
        type=int,
        default=1,
        help="run the workloads this many times in interleaved rounds; report the median\n"
        "by block-steps/s (this VM drifts by 15-25%% within an hour)",
    )
    ap.add_argument("--json", help="write the rows as JSON lines to this file")
    ap.add_argument("--child", nargs=5, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        wid, alpha, transient_t, events, tile = args.child
        measure(wid, float(alpha), float(transient_t), int(events), int(tile))
        return
    if args.compile_only:
        _compile_rounds(args.compile_only)
        return
    scale = 10 if args.quick else 1
    ids = args.ids or ([] if args.scaling_only else sorted(WORKLOADS))
    jobs = [(w, WORKLOADS[w][1], WORKLOADS[w][0]) for w in ids]
    if args.scaling or args.scaling_only:
        sizes = (32, 64, 128, 150, 256, 512, 1024)
        if args.sizes:
            sizes = tuple(int(x) for x in args.sizes.split(","))
        jobs += [(f"L{n}", 1.0, f"periodic square {n}x{n}") for n in sizes]
    if args.repeat < 1:
        ap.error("--repeat must be >= 1")
    rows = []
    header = (
        f"{'id':5} {'workload':46} {'N':>8} {'alpha':>5} {'events/s':>10} "
        f"{'block-steps/s':>14} {'blocks/ev':>9} {'steps/ev':>8} {'solo':>5} {'peak MiB':>8} "
        f"{'largest':>9} {'steps':>6} {'set-up':>7}"
    )
    print(header)
    print("-" * len(header))
    runs = {wid: [] for wid, _, _ in jobs}
    with tempfile.TemporaryDirectory() as states:
        env = dict(os.environ, **{STATE_DIR_ENV: states})
        for r in range(args.repeat):
            if args.repeat > 1:
                print(f"round {r + 1} of {args.repeat}", flush=True)
            for wid, alpha, desc in jobs:
                row = _child_run(args, wid, alpha, scale, env)
                row["workload"] = desc
                runs[wid].append(row)
                _print_row(row, alpha)
    for wid, alpha, _ in jobs:
        row = _median_row(runs[wid])
        rows.append(row)
        if args.repeat > 1:
            if wid == jobs[0][0]:
                print(f"\nmedian of {args.repeat} rounds (by block-steps/s)")
            _print_row(row, alpha)
    if args.compile:
        print()
        _compile_rounds(1)
    if args.json:
        with open(args.json, "w") as fh:
            for row in rows:
                fh.write(json.dumps(row) + "\n")


if __name__ == "__main__":
    main()
