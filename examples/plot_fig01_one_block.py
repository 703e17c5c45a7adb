"""
Fig. 1: stick-slip of one block
===============================

Sakaguchi & Morita (2013), Fig. 1, the one-block Carlson-Langer system
x'' = v0 t - x - phi(v):

* (a) x(t) at sigma = 0.01, alpha = 2: a periodic stick-slip with slip 1.274;
* (b) the slip s versus alpha at sigma = 0.01, with the linear theory Eq. (6),
  s = sigma (1 + exp(alpha pi / sqrt(1 - alpha^2))), dashed: good agreement at
  small alpha, a rapid change near alpha = 1;
* (c) the same at sigma = 1e-4: s is almost 0 below alpha = 1 and rises
  steeply there, like a phase transition.

Initial state: x = 0 at rest with the plate at u = 0 (the block first sticks
until the spring force reaches the static friction 1).  Every event starts at
the threshold with the block at rest, so the motion is periodic from the first
event; three events are run per alpha and the last slip is taken
(``faultnet.dynamics.one_block_slip_curve``).  No transient matters here.

Time axis of panel (a): the plate time t (v0 = 1 while the block sticks,
v0 = 0 during a slip, as in the paper), so slips are vertical steps; the inset
shows x inside one slip against the fast time of the event
(``simulate(..., trace_nodes=[0])``).

Fast mode (``FAULTNET_FAST=1`` or ``--fast``) uses coarser alpha grids.
"""

# %%
# Setup
# -----
import _paper_data as paper
import matplotlib.pyplot as plt
import numpy as np

import faultnet
from faultnet import dynamics

FAST = paper.fast_mode()
n_alpha = 24 if FAST else 120
paper.header(
    "Fig. 1: one block (sigma = 0.01 and 1e-4)",
    FAST,
    [
        "initial state: x = 0 at rest, plate u = 0; periodic from the first event",
        f"(a) 6 events at alpha = 2; (b), (c) {n_alpha} alpha values each, 3 events per alpha",
    ],
)

# %%
# (a) periodic stick-slip at alpha = 2
# ------------------------------------
one = faultnet.CarlsonLanger(faultnet.graphs.chain(1), sigma=0.01, alpha=2.0)
res = faultnet.simulate(one, 6, x0=[0.0], progress=False, trace_nodes=[0])
ev = res.events
# x(t) in plate time: constant while stuck, a jump of S at each event time
t_steps = np.repeat(np.concatenate([[0.0], ev["t"].to_numpy()]), 2)[1:]
x_steps = np.repeat(np.concatenate([[0.0], np.cumsum(ev["S"].to_numpy())]), 2)[:-1]
t_steps = np.append(t_steps, ev["t"].iloc[-1] + 1.0)
x_steps = np.append(x_steps, x_steps[-1])

# %%
# (b), (c) slip versus alpha, with Eq. (6)
# ----------------------------------------
alphas = np.linspace(0.02, 2.0, n_alpha)
curve_b = dynamics.one_block_slip_curve(alphas, sigma=0.01)
curve_c = dynamics.one_block_slip_curve(alphas, sigma=1e-4)
fine = np.linspace(0.0, 0.999, 400)

# %%
# Figure
# ------
fig, axes = plt.subplot_mosaic([["a", "a"], ["b", "c"]], figsize=(8, 7.6))
ax = axes["a"]
ax.plot(t_steps, x_steps, color="C0", label="x(t)")
ax.plot(t_steps, t_steps - 1.0, color="0.5", linestyle=":", label="u - 1 (threshold)")
ax.set_xlabel("plate time t")
ax.set_ylabel("x")
ax.set_title("(a) sigma = 0.01, alpha = 2")
ax.legend(loc="upper left")
inset = ax.inset_axes([0.64, 0.1, 0.33, 0.36])
tr = res.traces[res.traces["event"] == 1]
inset.plot(tr["time"], tr["x"] - tr["x"].iloc[0], color="C1")
inset.set_title("x - x(t_i) inside one slip", fontsize=9)
inset.tick_params(labelsize=9)
for ax, curve, sigma, tag in ((axes["b"], curve_b, 0.01, "(b)"), (axes["c"], curve_c, 1e-4, "(c)")):
    ax.plot(curve["alpha"], curve["s"], "o-", markersize=3, label="faultnet")
    ax.plot(fine, dynamics.linear_slip(sigma, fine), "k--", label="Eq. (6)")
    ax.set_ylim(0.0, 1.15 * curve["s"].max())
    ax.set_xlabel("alpha")
    ax.set_ylabel("slip s")
    ax.set_title(f"{tag} one block, sigma = {sigma:g}")
    ax.axvline(1.0, color="0.7", linewidth=0.8)
    ax.legend(loc="upper left")
fig.suptitle(f"Fig. 1 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig01")


# %%
# Paper versus faultnet
# ---------------------
def slip_at(alpha, sigma):
    return float(dynamics.one_block_slip_curve([alpha], sigma=sigma)["s"].iloc[0])


table = paper.Table("Fig. 1", FAST)
table.add("(a) slip at alpha=2, sigma=0.01", "1.274", f"{ev['S'].iloc[-1]:.5f}")
for a in (0.1, 0.3, 0.5):
    s = slip_at(a, 0.01)
    table.add(
        f"(b) s(alpha={a}) / Eq.(6) - 1",
        "~ 0 (good at small alpha)",
        f"{s / dynamics.linear_slip(0.01, a) - 1:+.2%}",
    )
table.add(
    "(b) s(0.9) -> s(1.1), sigma=0.01",
    "rapid change near 1",
    f"{slip_at(0.9, 0.01):.3g} -> {slip_at(1.1, 0.01):.3g}",
)
table.add("(c) s(0.8), sigma=1e-4", "almost 0", slip_at(0.8, 1e-4))
table.add(
    "(c) s(0.95) -> s(1.05), sigma=1e-4",
    "steep rise near 1",
    f"{slip_at(0.95, 1e-4):.3g} -> {slip_at(1.05, 1e-4):.3g}",
)
table.print()
