"""
Networks of faults: how often a rupture jumps a step-over
==========================================================

Two faults of 60 blocks overlap by 10 blocks across a step-over; springs of
stiffness ``k_coupling`` join the facing blocks.  How often does an event that
starts on one fault spread to the other, and how does that depend on the
coupling and on the size of the event?

The graph comes from :func:`faultnet.graphs.step_over`, which labels every
block with its fault (the node attribute ``fault``) and gives the coupling
springs their own ``k``.  :func:`faultnet.plotting.plot_faults` draws it.  On
such a graph every event also records the fault of its hypocentre (column
``fault``) and how many faults slipped (column ``n_faults``).

Set ``FAULTNET_FAST=1`` for a quick run with fewer events.
"""

import os

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

import faultnet

FAST = os.environ.get("FAULTNET_FAST", "").strip().lower() in ("1", "true", "yes", "on")
N_EVENTS = 3_000 if FAST else 40_000
TRANSIENT_T = 2.0  # plate time after which the random initial state is forgotten
COUPLINGS = [0.1, 2.0, 32.0]

# %%
# The network
# -----------
# Blocks along a fault are one unit apart; the second fault runs ``gap = 1``
# away, and its first 10 blocks face the last 10 of the first.

G = faultnet.graphs.step_over(60, overlap=10, gap=1.0, k_coupling=2.0)
fig, ax = plt.subplots(figsize=(8, 2.2), layout="constrained")
faultnet.plotting.plot_faults(G, ax=ax, node_size=18)
ax.set_title("step_over(60, overlap=10, gap=1.0, k_coupling=2.0)")

# %%
# Events that rupture both faults
# -------------------------------
# For each coupling: simulate and keep the steady state.

rows = []
for k_coupling in COUPLINGS:
    graph = faultnet.graphs.step_over(60, overlap=10, gap=1.0, k_coupling=k_coupling)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    events = faultnet.simulate(model, N_EVENTS, rng=1, progress=False).events
    steady = events[events["t"] > TRANSIENT_T]
    rows.append(steady.assign(k_coupling=k_coupling)[["t", "M", "fault", "n_faults", "k_coupling"]])
table = pd.concat(rows)
summary = table.groupby("k_coupling")["n_faults"].agg(
    events="size", both_faults=lambda n: float(np.mean(n > 1))
)
print(summary.to_string(float_format=lambda x: f"{x:.3f}"))
print(table.groupby(["k_coupling", "fault"]).size().unstack())  # where the events start

# %%
# Small events stay on their fault and the largest cross the step-over at every
# coupling.  In between, the coupling decides, and not monotonically: a stiff
# coupling (32) ties the facing blocks together, so that even small events in
# the overlap count on both faults, while mid-sized events cross it less often
# than the moderate coupling (2).

bins = np.linspace(table["M"].min(), table["M"].max(), 16)
fig, ax = plt.subplots(figsize=(6.4, 4.2), layout="constrained")
for k_coupling, group in table.groupby("k_coupling"):
    frac = faultnet.seismicity.multi_fault_fraction(group, bins=bins)
    ax.errorbar(frac["M"], frac["fraction"], frac["error"], fmt="o-", capsize=2,
                label=f"k_coupling = {k_coupling:g}")  # fmt: skip
ax.set_xlabel("M = ln S")
ax.set_ylabel("fraction of events on both faults")
ax.set_ylim(-0.03, 1.03)
ax.legend()

# %%
# Each fault's own magnitude-frequency law: the b-values of the events that
# start on each fault, above one common threshold.

print(faultnet.seismicity.b_per_fault(table[table["k_coupling"] == 2.0]))
plt.show()
