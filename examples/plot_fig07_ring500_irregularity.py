"""
Fig. 7: intermittent chaos on a ring of 500 blocks
==================================================

Sakaguchi & Morita (2013), Fig. 7, a ring of N = 500 blocks at k = 16,
sigma = 0.01, alpha = 1.5, for 9.5 < t < 12.5:

* (a) S(t): large slips occur intermittently; the many small slips between
  them are hardly visible on a linear axis;
* (b) the irregularity Delta (Eq. 13): it jumps upward at every large slip
  (S > 30) and decreases during the repetition of small slips.

Initial state: x uniform in [0, 0.01) (``numpy.random.default_rng(1)``), plate
at u = 0; the paper's window is drawn.  The statistics of Delta use the events
with 5 < t <= 12.5 in fast mode and 5 < t <= 60 in paper mode (t < 5
discarded as transient); a large slip is S > 30 as in the paper.  Panel (c)
(not in the paper) shows the same Delta(t) on a logarithmic S axis to make the
small slips visible.
"""

# %%
# Setup
# -----
import _paper_data as paper
import matplotlib.pyplot as plt

import faultnet
from faultnet import plotting

FAST = paper.fast_mode()
N, ALPHA, SEED = 500, 1.5, 1
WINDOW = (9.5, 12.5)
T_TRANSIENT, T_END = 5.0, (12.5 if FAST else 60.0)
S_LARGE = 30.0
paper.header(
    "Fig. 7: ring N = 500, k = 16, sigma = 0.01, alpha = 1.5",
    FAST,
    [
        f"initial state: x uniform in [0, 0.01) (seed {SEED}), u = 0; run to t = {T_END:g}",
        f"drawn: {WINDOW[0]} < t < {WINDOW[1]}; statistics: {T_TRANSIENT:g} < t <= {T_END:g} "
        f"(t < {T_TRANSIENT:g} discarded); large slip: S > {S_LARGE:g}",
    ],
)

ring = faultnet.CarlsonLanger(faultnet.graphs.ring(N), k=16, sigma=0.01, alpha=ALPHA)
events, _, _ = paper.run_with_irregularity(ring, T_END, SEED, chunk=5000)
win = events[(events["t"] > WINDOW[0]) & (events["t"] < WINDOW[1])]
steady = events[events["t"] > T_TRANSIENT]
print(
    f"{len(events)} events up to t = {T_END:g}; {len(win)} in the window, "
    f"{len(steady)} after the transient"
)

# %%
# Figure
# ------
fig, axes = plt.subplots(1, 3, figsize=(15, 4.3))
plotting.plot_time_series(win["t"], win["S"], ax=axes[0], kind="S")
axes[0].set_title("(a) S(t)")
plotting.plot_time_series(win["t"], win["Delta"], ax=axes[1], kind="delta")
axes[1].set_title("(b) Delta(t) (red: S > 30)")
plotting.plot_time_series(win["t"], win["S"], ax=axes[2], kind="S", linewidth=0.5)
axes[2].set_yscale("symlog", linthresh=1e-3)
axes[2].set_title("(extra) S(t) on a log axis")
for t in win.loc[win["S"] > S_LARGE, "t"]:
    axes[1].axvline(t, color="C3", linewidth=0.5, alpha=0.5)
fig.suptitle(f"Fig. 7 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig07")

# %%
# Paper versus faultnet
# ---------------------
summary = paper.delta_summary(steady, S_LARGE)
table = paper.Table("Fig. 7", FAST)
table.add(
    "large slips (S > 30) in 9.5 < t < 12.5",
    "intermittent",
    f"{int((win['S'] > S_LARGE).sum())} in {len(win)} events",
    f"largest S = {win['S'].max():.0f}",
)
paper.add_delta_rows(table, summary, S_LARGE)
table.print()
