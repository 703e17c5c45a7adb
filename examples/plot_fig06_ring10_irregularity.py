"""
Fig. 6: intermittent chaos on a ring of ten blocks
==================================================

Sakaguchi & Morita (2013), Fig. 6, a ring of N = 10 blocks at k = 16,
sigma = 0.01, alpha = 1.5 in its chaotic state, 108 < t < 115.3:

* (a) the profile x_i(t): a dent whose delayed blocks catch up by small slips;
* (b) S(t): small slips of one or a few blocks (the smallest, a single-block
  slip, is 1.007e-3) and, once the dent is shallow, a large simultaneous slip;
* (c) the irregularity Delta = (1/N) sum_i abs(x_{i+1} - x_i) (Eq. 13,
  ``faultnet.irregularity``): it decreases during the small slips and jumps
  when a large slip occurs.

Initial state: x uniform in [0, 0.01) (``numpy.random.default_rng(1)``), plate
at u = 0; faultnet's trajectory is not the paper's, but from this state the ring
is in the chaotic state at the paper's window, which is the one drawn.  The
statistics of Delta use every event with 20 < t <= 300 (paper mode) or
20 < t <= 120 (fast mode); events before t = 20 are discarded as transient.
A large slip is one with S > 1 (the simultaneous slips are of order N s, s the
one-block slip of Fig. 1b; the others are below 0.1).
"""

# %%
# Setup
# -----
import _paper_data as paper
import matplotlib.pyplot as plt

import faultnet
from faultnet import plotting

FAST = paper.fast_mode()
N, ALPHA, SEED = 10, 1.5, 1
WINDOW = (108.0, 115.3)
T_TRANSIENT, T_END = 20.0, (120.0 if FAST else 300.0)
S_LARGE = 1.0
paper.header(
    "Fig. 6: ring N = 10, k = 16, sigma = 0.01, alpha = 1.5",
    FAST,
    [
        f"initial state: x uniform in [0, 0.01) (seed {SEED}), u = 0; run to t = {T_END:g}",
        f"drawn: {WINDOW[0]} < t < {WINDOW[1]}; statistics: {T_TRANSIENT:g} < t <= {T_END:g} "
        f"(t < {T_TRANSIENT:g} discarded); large slip: S > {S_LARGE:g}",
    ],
)

ring = faultnet.CarlsonLanger(faultnet.graphs.ring(N), k=16, sigma=0.01, alpha=ALPHA)
events, profiles, kept = paper.run_with_irregularity(ring, T_END, SEED, keep_profiles=WINDOW)
win = events[kept]
steady = events[events["t"] > T_TRANSIENT]
print(
    f"{len(events)} events up to t = {T_END:g}; {len(win)} in the window, "
    f"{len(steady)} after the transient"
)

# %%
# Figure
# ------
fig, axes = plt.subplots(1, 3, figsize=(15, 4.3))
t_win = win["t"].to_numpy()
plate = t_win[:, None]  # x relative to the plate: the dent is what lags behind
plotting.plot_profiles(profiles - plate, t=t_win, ax=axes[0], subtract_mean=True)
axes[0].set_title("(a) x_i - <x> after each event")
plotting.plot_time_series(t_win, win["S"], ax=axes[1], kind="S")
axes[1].set_yscale("symlog", linthresh=1e-3)
axes[1].set_title("(b) S(t)")
plotting.plot_time_series(t_win, win["Delta"], ax=axes[2], kind="delta")
large_t = win.loc[win["S"] > S_LARGE, "t"]
for ax in axes[1:]:
    for t in large_t:
        ax.axvline(t, color="C3", linewidth=0.5, alpha=0.5)
axes[2].set_title("(c) Delta(t) (red: large slips)")
fig.suptitle(f"Fig. 6 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig06")

# %%
# Paper versus faultnet
# ---------------------
summary = paper.delta_summary(steady, S_LARGE)
table = paper.Table("Fig. 6", FAST)
table.add("smallest slip (single block)", "1.007e-3", f"{steady['S'].min():.4e}")
table.add(
    "large (simultaneous) slips in the window",
    "occur once in a while",
    f"{int((win['S'] > S_LARGE).sum())} in {len(win)} events",
    f"{int(((win['S'] > S_LARGE) & (win['n_blocks'] == N)).sum())} of them move all N blocks",
)
paper.add_delta_rows(table, summary, S_LARGE)
table.print()
