"""Draw the scaling series of ``benchmarks/run.py --scaling --json FILE``.

    python benchmarks/run.py --scaling W4 --json /tmp/scaling.jsonl
    python benchmarks/plot_scaling.py /tmp/scaling.jsonl benchmarks/scaling.png

Left: block-steps per second against the number of blocks N (the cost of one
slipping block over one integration step; flat means no per-event O(N) work
and no loss of cache locality).  Right: wall time per event.
"""

from __future__ import annotations

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("rows", help="JSON lines written by run.py --json")
    ap.add_argument("png", help="output image")
    args = ap.parse_args(argv)
    with open(args.rows) as fh:
        rows = [json.loads(line) for line in fh if line.strip()]
    series = sorted((r for r in rows if r["id"].startswith("L")), key=lambda r: r["blocks"])
    if not series:
        raise SystemExit("no L* rows (periodic square lattices) in " + args.rows)
    n = [r["blocks"] for r in series]
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    a.plot(n, [r["block_steps_per_s"] / 1e6 for r in series], "o-", label="median of rounds")
    for r in series:  # run.py --repeat R: every round, to show this VM's drift
        runs = r.get("block_steps_per_s_all", [])
        a.plot([r["blocks"]] * len(runs), [v / 1e6 for v in runs], ".", color="0.6", ms=4)
    ref = next((r for r in series if r["id"] == "L150"), None)
    if ref is not None:
        a.axhline(0.7 * ref["block_steps_per_s"] / 1e6, color="C3", ls="--", lw=1)
        a.annotate(
            "70% of L=150",
            (n[0], 0.7 * ref["block_steps_per_s"] / 1e6),
            textcoords="offset points",
            xytext=(0, -10),
            fontsize=7,
            color="C3",
        )
    a.set(
        xscale="log",
        xlabel="blocks N (periodic square, alpha = 1)",
        ylabel="block-steps / s (millions)",
        ylim=(0, None),
    )
    b.plot(n, [r["us_per_event"] for r in series], "o-", color="C1")
    b.set(xscale="log", yscale="log", xlabel="blocks N", ylabel="wall time per event (us)")
    for r in series:  # events are bigger on big lattices: label the mean event size
        b.annotate(
            f"{r['mean_blocks']:.0f} blocks/ev",
            (r["blocks"], r["us_per_event"]),
            textcoords="offset points",
            xytext=(0, 6),
            ha="center",
            fontsize=7,
        )
    for r in series:
        a.annotate(
            f"L={int(round(r['blocks'] ** 0.5))}",
            (r["blocks"], r["block_steps_per_s"] / 1e6),
            textcoords="offset points",
            xytext=(0, 6),
            ha="center",
            fontsize=7,
        )
    fig.suptitle(
        "faultnet scaling: periodic square lattices, alpha = 1, one core "
        "(L >= 256: the L = 128 steady state tiled)",
        fontsize=9,
    )
    fig.savefig(args.png, dpi=120)
    print(f"wrote {args.png}")


if __name__ == "__main__":
    main()
