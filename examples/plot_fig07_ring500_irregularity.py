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
import numpy as np
import pandas as pd

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

# %%
# Run with the irregularity after every event
# -------------------------------------------
# ``record_profiles=True`` keeps x after every event and ``faultnet.irregularity``
# reduces a result's profiles to Delta (Eq. 13) per event.  Chunks of 5000
# events (``x0=state`` continues the run) keep the 500-block profiles small in
# memory; only Delta is kept.
ring = faultnet.CarlsonLanger(faultnet.graphs.ring(N), k=16, sigma=0.01, alpha=ALPHA)
state = np.random.default_rng(SEED).uniform(0.0, 0.01, ring.n)
delta_prev = faultnet.irregularity(state, ring)
parts = []
while True:
    res = faultnet.simulate(ring, 5000, x0=state, progress=False, record_profiles=True)
    state = res.state
    ev = res.events.copy()
    delta = faultnet.irregularity(res)
    ev["Delta"] = delta
    ev["Delta_before"] = np.concatenate([[delta_prev], delta[:-1]])
    delta_prev = float(delta[-1])
    parts.append(ev)
    if ev["t"].iloc[-1] >= T_END:
        break
events = pd.concat(parts, ignore_index=True)
events = events[events["t"] <= T_END].reset_index(drop=True)
win = events[(events["t"] > WINDOW[0]) & (events["t"] < WINDOW[1])]
steady = events[events["t"] > T_TRANSIENT]
print(
    f"{len(events)} events up to t = {T_END:g}; {len(win)} in the window, "
    f"{len(steady)} after the transient"
)

# %%
# Figure
# ------
fig, axes = plt.subplots(3, 1, figsize=(8, 8.4), sharex=True)
plotting.plot_time_series(win["t"], win["S"], ax=axes[0], kind="S")
axes[0].set_title("(a) S(t)")
plotting.plot_time_series(win["t"], win["Delta"], ax=axes[1], kind="delta")
axes[1].set_title("(b) Delta(t) (red: S > 30)")
plotting.plot_time_series(win["t"], win["S"], ax=axes[2], kind="S", linewidth=0.5)
axes[2].set_yscale("symlog", linthresh=1e-3)
axes[2].set_title("(extra) S(t) on a log axis")
for t in win.loc[win["S"] > S_LARGE, "t"]:
    axes[1].axvline(t, color="C3", linewidth=0.5, alpha=0.5)
for ax in axes[:2]:
    ax.set_xlabel("")  # the panels share the t axis of the bottom one
fig.suptitle(f"Fig. 7 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig07")

# %%
# How Delta changes in small and large slips
# ------------------------------------------
# The change of Delta in each event, split at S = 30; a "phase" is the run of
# small slips between two large ones, and its net change is Delta before the
# next large slip minus Delta after the last one.
change = (steady["Delta"] - steady["Delta_before"]).to_numpy()
large = (steady["S"] > S_LARGE).to_numpy()
before = steady["Delta_before"].to_numpy()
after = steady["Delta"].to_numpy()
idx = np.flatnonzero(large)
phases = np.array(
    [before[j] - after[i] for i, j in zip(idx[:-1], idx[1:], strict=True) if j > i + 1]
)

# %%
# Paper versus faultnet
# ---------------------
table = paper.Table("Fig. 7", FAST)
table.add(
    "large slips (S > 30) in 9.5 < t < 12.5",
    "intermittent",
    f"{int((win['S'] > S_LARGE).sum())} in {len(win)} events",
    f"largest S = {win['S'].max():.0f}",
)
table.add(
    f"mean change of Delta per small slip (S <= {S_LARGE:g})",
    "< 0 (decreases)",
    f"{change[~large].mean():+.3e}",
    f"{(change[~large] < 0).mean():.0%} of {int((~large).sum())} small slips lower it",
)
table.add(
    "net change of Delta between large slips",
    "< 0 (decreases)",
    f"{phases.mean():+.3e}",
    f"{(phases < 0).mean():.0%} of {phases.size} phases end lower",
)
table.add(
    f"mean change of Delta per large slip (S > {S_LARGE:g})",
    "> 0 (jumps up)",
    f"{change[large].mean():+.3e}",
    f"{(change[large] > 0).mean():.0%} of {int(large.sum())} large slips raise it",
)
table.add(
    "Delta before large slips / mean Delta",
    "< 1 (flatter profile)",
    f"{before[large].mean() / before.mean():.3f}",
)
table.print()
