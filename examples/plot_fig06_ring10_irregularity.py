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
import numpy as np
import pandas as pd

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

# %%
# Run with the irregularity after every event
# -------------------------------------------
# ``record_profiles=True`` keeps x after every event; ``faultnet.irregularity``
# turns a result's profiles into Delta (Eq. 13) per event, and takes a single
# state too (the initial one here).  The run goes on in chunks of 2000 events
# (``x0=state`` continues it) until the plate time passes ``T_END``; the
# profiles of the drawn window are kept.
ring = faultnet.CarlsonLanger(faultnet.graphs.ring(N), k=16, sigma=0.01, alpha=ALPHA)
state = np.random.default_rng(SEED).uniform(0.0, 0.01, ring.n)
delta_prev = faultnet.irregularity(state, ring)
parts, kept_profiles = [], []
while True:
    res = faultnet.simulate(ring, 2000, x0=state, progress=False, record_profiles=True)
    state = res.state
    ev = res.events.copy()
    delta = faultnet.irregularity(res)
    ev["Delta"] = delta
    ev["Delta_before"] = np.concatenate([[delta_prev], delta[:-1]])
    delta_prev = float(delta[-1])
    inside = (ev["t"] >= WINDOW[0]) & (ev["t"] <= WINDOW[1])
    kept_profiles.append(res.profiles[inside.to_numpy()])
    parts.append(ev)
    if ev["t"].iloc[-1] >= T_END:
        break
events = pd.concat(parts, ignore_index=True)
events = events[events["t"] <= T_END].reset_index(drop=True)
kept = ((events["t"] >= WINDOW[0]) & (events["t"] <= WINDOW[1])).to_numpy()
profiles = np.concatenate(kept_profiles)[: int(kept.sum())]
win = events[kept]
steady = events[events["t"] > T_TRANSIENT]
print(
    f"{len(events)} events up to t = {T_END:g}; {len(win)} in the window, "
    f"{len(steady)} after the transient"
)

# %%
# Figure
# ------
fig, axes = plt.subplot_mosaic([["a", "b"], ["a", "c"]], figsize=(8, 6.4))
t_win = win["t"].to_numpy()
plate = t_win[:, None]  # x relative to the plate: the dent is what lags behind
plotting.plot_profiles(profiles - plate, t=t_win, ax=axes["a"], subtract_mean=True)
axes["a"].set_title("(a) x_i - <x> after each event")
plotting.plot_time_series(t_win, win["S"], ax=axes["b"], kind="S")
axes["b"].set_yscale("symlog", linthresh=1e-3)
axes["b"].set_title("(b) S(t)")
plotting.plot_time_series(t_win, win["Delta"], ax=axes["c"], kind="delta")
large_t = win.loc[win["S"] > S_LARGE, "t"]
for ax in (axes["b"], axes["c"]):
    for t in large_t:
        ax.axvline(t, color="C3", linewidth=0.5, alpha=0.5)
axes["c"].set_title("(c) Delta(t) (red: large slips)")
fig.suptitle(f"Fig. 6 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig06")

# %%
# How Delta changes in small and large slips
# ------------------------------------------
# The change of Delta in each event, split at S = S_LARGE; a "phase" is the run
# of small slips between two large ones, and its net change is Delta before the
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
table = paper.Table("Fig. 6", FAST)
table.add("smallest slip (single block)", "1.007e-3", f"{steady['S'].min():.4e}")
table.add(
    "large (simultaneous) slips in the window",
    "occur once in a while",
    f"{int((win['S'] > S_LARGE).sum())} in {len(win)} events",
    f"{int(((win['S'] > S_LARGE) & (win['n_blocks'] == N)).sum())} of them move all N blocks",
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
