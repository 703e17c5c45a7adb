"""
Fig. 2: intermittency of two coupled blocks at alpha = 2
========================================================

Sakaguchi & Morita (2013), Fig. 2, two blocks (k = 16, sigma = 0.01,
alpha = 2) started at rest from x = (0.001, 0.002):

* (a) the total slip S of each event: small one-block slips
  (S ~ 3.8e-3) repeat 3-20 times between large simultaneous slips (S ~ 2.4);
* (b) x2 - x1 after each event: abs(x2 - x1) falls by 0.0038 per small slip
  until the blocks slip together; the chaotic intermittent sequence is a
  transient that ends in a stable two-period state x2 - x1 = +-0.0019;
* (c) the one-dimensional map x2 - x1 -> x2' - x1' (one event from rest,
  ``faultnet.dynamics.return_map``): x2' - x1' = x2 - x1 -+ 0.0038 for
  abs(x2 - x1) > 0.0019, and a strongly nonlinear simultaneous-slip branch in
  between whose largest abs(x2' - x1') is 0.065.

Initial state (the paper's): x = (0.001, 0.002), plate u = 0.  The whole
sequence is shown (no transient is discarded: the transient *is* the figure).
The time axis is the plate time at the start of each event.

The paper's chaotic phase lasts until t ~ 42; faultnet's sequence (which
agrees with a DOP853 reference integrator at rtol 1e-12 event by event,
``tests/solver/test_two_block.py``) reaches the two-period state earlier.  Each
simultaneous slip magnifies a difference in x2 - x1 about thirty-fold, so the
length of this chaotic transient depends on rounding and is not reproducible
between integrators; the map in (c) and the slip sizes are.

Fast mode (``FAULTNET_FAST=1`` or ``--fast``) evaluates the map on a coarser grid.
"""

# %%
# Setup
# -----
import _paper_data as paper
import matplotlib.pyplot as plt
import numpy as np

import faultnet
from faultnet import dynamics, plotting

FAST = paper.fast_mode()
N_EVENTS = 400
n_map = (200, 300) if FAST else (1000, 6000)  # (outer, inner |d| < 0.002) grid points
paper.header(
    "Fig. 2: two blocks, k = 16, sigma = 0.01, alpha = 2",
    FAST,
    [
        f"(a), (b): {N_EVENTS} events from x = (0.001, 0.002) at rest, u = 0; nothing discarded",
        f"(c): map from one event each, {n_map[0]} points on |d| <= 0.01 plus {n_map[1]} "
        "points on |d| < 0.002",
    ],
)

# %%
# (a), (b) the intermittent sequence
# ----------------------------------
two = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=16, sigma=0.01, alpha=2.0)
res = faultnet.simulate(two, N_EVENTS, x0=[0.001, 0.002], progress=False, record_profiles=True)
ev = res.events
d_after = res.profiles[:, 1] - res.profiles[:, 0]
big = ev["S"].to_numpy() > 0.5  # large = simultaneous slips of order one
# two-period state: alternating one-block slips from some event to the end of the run
tail = ~big[::-1]
n_tail = int(np.argmin(tail)) if not tail.all() else len(big)
first_two_period = len(big) - n_tail
t_two_period = float(ev["t"].iloc[first_two_period]) if n_tail < len(big) else float("nan")
shown = ev["t"].to_numpy() <= (t_two_period + 3.0 if n_tail < len(big) else np.inf)

# %%
# (c) the return map
# ------------------
d_grid = np.unique(
    np.concatenate([np.linspace(-0.01, 0.01, n_map[0]), np.linspace(-0.002, 0.002, n_map[1])])
)
rmap = dynamics.return_map(two, d_grid)

# %%
# Figure
# ------
fig, axes = plt.subplot_mosaic(
    [["a", "b"], ["c", "c"]], figsize=(8, 8.6), height_ratios=[1.0, 1.25]
)
plotting.plot_time_series(ev["t"][shown], ev["S"][shown], ax=axes["a"], kind="S", color="C0")
axes["a"].set_yscale("symlog", linthresh=1e-3)
axes["a"].set_ylim(0, 5)
axes["a"].set_title("(a) total slip S of each event")
axes["b"].plot(ev["t"][shown], d_after[shown], "o-", markersize=3)
for ax in (axes["a"], axes["b"]):
    ax.axvline(t_two_period, color="C2", linewidth=0.8, label="two-period state from here")
axes["b"].legend(fontsize=9, loc="lower left")
axes["b"].axhline(0.0019, color="0.6", linestyle=":")
axes["b"].axhline(-0.0019, color="0.6", linestyle=":")
axes["b"].set_xlabel("t")
axes["b"].set_ylabel("x2 - x1 after the event")
axes["b"].set_title("(b) x2 - x1 (dotted: +-0.0019)")
plotting.plot_return_map(rmap, ax=axes["c"], s=3)
span = np.array([0.0019, 0.01])
line = dict(color="C3", linewidth=1.0, linestyle="--", zorder=4)
axes["c"].plot(span, span - 0.0038, label="d' = d -+ 0.0038", **line)
axes["c"].plot(-span, -span + 0.0038, **line)
axes["c"].legend(loc="lower right")
axes["c"].set_xticks([-0.01, -0.005, 0.0, 0.005, 0.01])
zoom = axes["c"].inset_axes([0.09, 0.56, 0.3, 0.34])
inner = rmap[np.abs(rmap["d"]) < 0.0022]
zoom.scatter(inner["d"], inner["d_next"], s=1, c=np.where(inner["n_blocks"] == 2, "C1", "C0"))
zoom.set_title("|d| < 0.0022 (orange: both slip)", fontsize=9)
zoom.tick_params(labelsize=9)
zoom.set_xticks([-0.002, 0.0, 0.002])
axes["c"].set_title("(c) return map")
fig.suptitle(f"Fig. 2 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig02")

# %%
# Paper versus faultnet
# ---------------------
small_S = ev.loc[ev["n_blocks"] == 1, "S"]
large_S = ev.loc[big, "S"]
# laminar phases: runs of small slips between two simultaneous slips
big_idx = np.flatnonzero(big)
laminar = np.diff(big_idx) - 1
outer = rmap[np.abs(rmap["d"]) > 0.0025]
shift = np.abs(outer["d"] - outer["d_next"])
together = rmap[rmap["n_blocks"] == 2]
table = paper.Table("Fig. 2", FAST)
table.add("(a) small (one-block) slip S", "~ 3.8e-3", f"{small_S.median():.4e}")
table.add(
    "(a) linear estimate sigma/(k+1)(1+e^...)", "~ 0.0039", dynamics.linear_slip(0.01, 2.0, 17.0)
)
table.add(
    "(a) large (simultaneous) slips S",
    "~ 2.4",
    f"median {large_S.median():.3f} ({large_S.min():.3f} .. {large_S.max():.3f})",
    f"{big.sum()} large slips",
)
table.add(
    "(a) small slips between large ones",
    "3-20",
    f"{laminar.min()} .. {laminar.max()} (median {np.median(laminar):.0f})",
    f"{laminar.size} laminar phases",
)
table.add("(b) two-period state x2 - x1", "+-0.0019", f"{d_after[-2]:+.5f} / {d_after[-1]:+.5f}")
table.add(
    "(b) two-period state reached at t",
    "~ 42",
    t_two_period,
    "chaotic transient: rounding-dependent",
)
table.add("(c) |d - d'| for |d| > 0.0019 (one-block slip)", "0.0038", f"{shift.mean():.5f}")
table.add(
    "(c) simultaneous-slip region |d| <",
    "0.0019",
    f"{max(-together['d'].min(), together['d'].max()):.5f}",
)
table.add("(c) largest |x2' - x1'|", "0.065", f"{np.abs(rmap['d_next']).max():.4f}")
table.add(
    "(c) laminar length max|d'| / 0.0038",
    "3-20 (text)",
    f"{np.abs(rmap['d_next']).max() / 0.0038:.1f}",
)
table.print()
