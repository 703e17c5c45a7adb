"""
Fig. 4: two blocks at alpha = 0.28 -- chaotic simultaneous slips and bistability
================================================================================

Sakaguchi & Morita (2013), Fig. 4, two blocks at k = 16, sigma = 0.01,
alpha = 0.28:

* (a) S(t) and (b) x2 - x1 after each event: no intermittency; the two blocks
  slip together in every event, chaotically (this state is stable for
  0.25 < alpha < 0.32);
* (c) the map x2 - x1 -> x2' - x1': rhombi from the simulation of (a, b), the
  curve from one event per initial difference (``return_map``); squares: the
  coexisting two-period state of alternating one-block slips,
  x2' - x1' = -(x2 - x1) = +-0.00066 (bistability: which state appears depends
  on the initial condition).

Initial states: x = (0.001, 0.002) at rest, u = 0 for the chaotic run (as in
Fig. 2) and x = (0, 0.01) for the two-period run; the first 50 events of each
run are discarded as transient for the statistics (all events are drawn in
(a), (b)).  An extra scan (not in the paper) locates the alpha range of the
simultaneous-slip state: for each alpha the run from x = (0.001, 0.002) is
classified by the fraction of two-block events among its last half.

Fast mode (``FAULTNET_FAST=1`` or ``--fast``) uses fewer events, a coarser
map grid and a coarser alpha scan.
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
ALPHA = 0.28
N_EVENTS = 300 if FAST else 3000
N_SCAN = 600 if FAST else 4000
TRANSIENT = 50
scan_alphas = np.round(np.arange(0.20, 0.40 + 1e-9, 0.02 if FAST else 0.005), 4)
paper.header(
    "Fig. 4: two blocks, k = 16, sigma = 0.01, alpha = 0.28",
    FAST,
    [
        f"chaotic run: {N_EVENTS} events from x = (0.001, 0.002), u = 0; "
        f"two-period run: {N_EVENTS} events from x = (0, 0.01)",
        f"statistics skip the first {TRANSIENT} events of each run",
        f"alpha scan: {len(scan_alphas)} values in [0.20, 0.40], {N_SCAN} events each "
        "from x = (0.001, 0.002)",
    ],
)

# %%
# The two coexisting states
# -------------------------
two = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=16, sigma=0.01, alpha=ALPHA)
chaos = faultnet.simulate(two, N_EVENTS, x0=[0.001, 0.002], progress=False, record_profiles=True)
alt = faultnet.simulate(two, N_EVENTS, x0=[0.0, 0.01], progress=False, record_profiles=True)
d_chaos = chaos.profiles[:, 1] - chaos.profiles[:, 0]
d_alt = alt.profiles[:, 1] - alt.profiles[:, 0]
rmap = dynamics.return_map(two, np.linspace(-0.003, 0.003, 241 if FAST else 1201))

# %%
# Where is the simultaneous-slip state stable?
# --------------------------------------------
together = []
for a in scan_alphas:
    run = faultnet.simulate(
        two.with_params(alpha=float(a)), N_SCAN, x0=[0.001, 0.002], progress=False
    )
    together.append(float((run.events["n_blocks"].iloc[N_SCAN // 2 :] == 2).mean()))
together = np.array(together)

# %%
# Figure
# ------
fig, axes = plt.subplots(2, 2, figsize=(8, 7.6))
axes = axes.ravel()
n_show = min(150, N_EVENTS)
ev = chaos.events.iloc[:n_show]
plotting.plot_time_series(ev["t"], ev["S"], ax=axes[0], kind="S")
axes[0].set_title("(a) S(t): chaotic simultaneous slips")
axes[1].plot(ev["t"], d_chaos[:n_show], "o-", markersize=3)
axes[1].set_xlabel("t")
axes[1].set_ylabel("x2 - x1 after the event")
axes[1].set_title("(b) x2 - x1")
plotting.plot_return_map(rmap, ax=axes[2], s=2, color="0.3")
axes[2].scatter(
    d_chaos[TRANSIENT:-1],
    d_chaos[TRANSIENT + 1 :],
    marker="D",
    s=14,
    facecolors="none",
    edgecolors="C1",
    label="simulation (rhombi)",
    zorder=4,
)
axes[2].scatter(
    d_alt[TRANSIENT:-1],
    d_alt[TRANSIENT + 1 :],
    marker="s",
    s=30,
    facecolors="none",
    edgecolors="C3",
    label="two-period state",
    zorder=4,
)
axes[2].legend(fontsize=9, loc="lower left")
axes[2].set_title("(c) map at alpha = 0.28")
axes[2].set_xticks([-0.003, -0.0015, 0.0, 0.0015, 0.003])
axes[3].plot(scan_alphas, together, "o-", markersize=3)
axes[3].axvspan(0.25, 0.32, color="0.9", label="paper: 0.25..0.32")
axes[3].set_xlabel("alpha")
axes[3].set_ylabel("two-block events (fraction)")
axes[3].set_title("(extra) simultaneous slips vs alpha")
axes[3].legend(fontsize=9)
fig.suptitle(f"Fig. 4 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig04")

# %%
# Paper versus faultnet
# ---------------------
steady = chaos.events.iloc[TRANSIENT:]
all_together = scan_alphas[together == 1.0]
some_together = scan_alphas[together > 0.0]
table = paper.Table("Fig. 4", FAST)
table.add(
    "(a) events with both blocks slipping",
    "all (simultaneous slips)",
    f"{(steady['n_blocks'] == 2).mean():.1%}",
    f"{len(steady)} events after {TRANSIENT}",
)
table.add(
    "(b) x2 - x1 in the simultaneous-slip state",
    "chaotic, no intermittency",
    f"|d| <= {np.abs(d_chaos[TRANSIENT:]).max():.5f}",
    f"S = {steady['S'].min():.3g} .. {steady['S'].max():.3g}",
)
table.add(
    "(c) two-period state x2 - x1",
    "+-0.00066",
    f"{d_alt[-2]:+.6f} / {d_alt[-1]:+.6f}",
    f"one-block slips, S = {alt.events['S'].iloc[-1]:.3e}",
)
table.add(
    "stable simultaneous-slip state",
    "0.25 < alpha < 0.32",
    f"{all_together.min():.3g} <= alpha <= {all_together.max():.3g}"
    if all_together.size
    else "none",
    f"all events two-block; some: {some_together.min():.3g}..{some_together.max():.3g}"
    if some_together.size
    else "",
)
table.print()
