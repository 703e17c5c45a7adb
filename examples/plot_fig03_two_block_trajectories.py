"""
Fig. 3: inside one simultaneous slip of two blocks
==================================================

Sakaguchi & Morita (2013), Fig. 3, two blocks at k = 16, sigma = 0.01,
alpha = 2, one slip event each from rest with x2(0) - x1(0) = 0.00142 and
0.00169:

* (a) x1(t) (solid) and x2(t) (dashed) during the event;
* (b) x2(t) - x1(t): an amplified oscillation (linearly,
  delta'' = -(2k + 1) delta - phi'(v) delta' with phi' < 0).  After the slip
  x2 - x1 is negative for 0.00142 (the blocks change order) and positive for
  0.00169.  This sensitivity makes the map of Fig. 2(c) chaotic.

Initial state: x = (0, d) at rest with the plate at u = 0; the plate loads
block 1 (it lags, so its spring force is larger) until it fails, and exactly
one event is run (``simulate(..., trace_nodes=[0, 1])`` records x and v of
both blocks at every integration step).  Time is measured from the start of
the event.  The runs are tiny, so fast and paper mode are the same.
"""

# %%
# Setup
# -----
import _paper_data as paper
import matplotlib.pyplot as plt

import faultnet

FAST = paper.fast_mode()
DIFFS = (0.00142, 0.00169)
paper.header(
    "Fig. 3: two blocks inside one event, k = 16, sigma = 0.01, alpha = 2",
    FAST,
    ["initial state: x = (0, d) at rest, u = 0, d = 0.00142 and 0.00169; one event each"],
)

two = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=16, sigma=0.01, alpha=2.0)
runs = {}
for d in DIFFS:
    res = faultnet.simulate(two, 1, x0=[0.0, d], progress=False, trace_nodes=[0, 1])
    tr = res.traces.pivot(index="time", columns="node", values="x")
    runs[d] = (res, tr)

# %%
# Figure
# ------
fig, axes = plt.subplots(2, 1, figsize=(8, 7.6), sharex=True)
for color, d in zip(("C0", "C3"), DIFFS, strict=True):
    res, tr = runs[d]
    axes[0].plot(tr.index, tr[0], color=color, linestyle="-", label=f"x1, d(0) = {d}")
    axes[0].plot(tr.index, tr[1], color=color, linestyle="--", label=f"x2, d(0) = {d}")
    style = "-" if d == DIFFS[0] else "--"
    axes[1].plot(tr.index, tr[1] - tr[0], color=color, linestyle=style, label=f"d(0) = {d}")
axes[0].set_ylabel("x")
axes[0].set_title("(a) x1 (solid), x2 (dashed)")
axes[0].legend()
axes[1].axhline(0.0, color="0.6", linewidth=0.8)
axes[1].set_xlabel("time since the event started")
axes[1].set_ylabel("x2 - x1")
axes[1].set_title("(b) x2 - x1")
axes[1].legend()
fig.suptitle(f"Fig. 3 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig03")

# %%
# Paper versus faultnet
# ---------------------
table = paper.Table("Fig. 3", FAST)
for d, expect in zip(DIFFS, ("< 0 (order reversed)", "> 0"), strict=True):
    res, _ = runs[d]
    x = res.state.x
    row = res.events.iloc[0]
    table.add(
        f"x2' - x1' after the event, d(0) = {d}",
        expect,
        f"{x[1] - x[0]:+.4f}",
        f"S = {row['S']:.3f}, duration {row['duration']:.2f}, {int(row['n_blocks'])} blocks",
    )
x = runs[DIFFS[1]][0].state.x
table.add(
    "|x2' - x1'| at d(0) = 0.00169",
    "0.065 (max of the map)",
    f"{abs(x[1] - x[0]):.4f}",
    "Fig. 2 script: max over a grid",
)
table.print()
