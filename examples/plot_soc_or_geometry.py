"""
SOC or geometry? The OFC automaton and the Carlson-Langer blocks side by side
=============================================================================

Where does the Gutenberg-Richter law of a fault model come from?  Sakaguchi
and Morita (2013) set two answers against each other: self-organized
criticality, the answer of the Olami-Feder-Christensen automaton (OFC, PRL 68,
1244, 1992), and the fractal geometry of the asperities, theirs: the
Carlson-Langer blocks on a critical percolation cluster give ``P(M) ~ exp(-b
M)`` with ``b ~ 2/3`` (their Fig. 9), on a uniform lattice they do not.

faultnet runs both models on the same graphs.  The OFC automaton
(:class:`faultnet.OFC`) is the quasi-static limit of the same spring network:
the same blocks, springs and plate spring, but a block that reaches the
threshold drops at once to force 0 and passes ``k / K`` of its force to each
neighbour, with no inertia and no velocity-weakening friction.  Here:

* the uniform lattice: a 48 x 48 square lattice with fixed ("open")
  boundaries, OFC at ``alpha = 0.2`` (``k = 1``) and Carlson-Langer at ``k =
  16``, ``sigma = 0.01``, ``alpha = 1``;
* the asperity: the largest cluster of site percolation at ``p_c`` on a 100 x
  100 lattice, the same cluster for both models, OFC with ``k = 1`` and
  Carlson-Langer with the paper's ``alpha = 0.9``.

``M = ln S`` for both, with ``S`` the total slip of an event (the sum of the
topplings' slips for OFC).  Set ``FAULTNET_FAST=1`` for a quick run with
fewer events.
"""

import math
import os

import matplotlib.pyplot as plt
import pandas as pd

import faultnet

FAST = os.environ.get("FAULTNET_FAST", "").strip().lower() in ("1", "true", "yes", "on")
N_CL = 20_000 if FAST else 300_000
N_OFC = 100_000 if FAST else 2_000_000
SIDE, CLUSTER_SIDE = (24, 40) if FAST else (48, 100)
P_C = faultnet.graphs.percolation_threshold("square")

lattice = faultnet.graphs.square_lattice(SIDE, SIDE, boundary="fixed")
cluster = faultnet.graphs.site_percolation(
    faultnet.graphs.square_lattice(CLUSTER_SIDE, CLUSTER_SIDE), P_C, rng=2013
)
print(f"lattice {SIDE}x{SIDE}: {lattice.number_of_nodes()} blocks; cluster at p_c of "
      f"{CLUSTER_SIDE}x{CLUSTER_SIDE}: {cluster.number_of_nodes()} blocks")  # fmt: skip


def steady_magnitudes(model, n_events, transient_drive):
    """The magnitudes of ``n_events`` events that start after the plate time (the drive)
    ``transient_drive``: the runs of ``n_events`` before it are left out whole."""
    res = faultnet.simulate(model, n_events, rng=1, progress=False)
    while res.events["t"].iloc[0] < transient_drive:
        res = faultnet.simulate(model, n_events, x0=res.state, progress=False)
    return res.events["M"].to_numpy()


# %%
# The four runs
# -------------
# The Carlson-Langer runs leave out the plate time before 2, as the paper
# does; the automaton, started from uniform random forces, needs a longer
# drive to forget its start (about ``20 L`` on an L x L lattice,
# ``benchmarks/README.md``).

runs = {
    ("OFC", "lattice"): steady_magnitudes(faultnet.OFC.from_alpha(lattice, 0.2), N_OFC, 20 * SIDE),
    ("OFC", "cluster"): steady_magnitudes(faultnet.OFC(cluster, k=1.0), N_OFC, 20 * CLUSTER_SIDE),
    ("Carlson-Langer", "lattice"): steady_magnitudes(
        faultnet.CarlsonLanger(lattice, k=16, sigma=0.01, alpha=1.0), N_CL, 2.0
    ),
    ("Carlson-Langer", "cluster"): steady_magnitudes(
        faultnet.CarlsonLanger(cluster, k=16, sigma=0.01, alpha=0.9), N_CL, 2.0
    ),
}

# %%
# P(M) and b
# ----------
# b by Aki's maximum likelihood above ``M_MIN``: above the paper's -6 for the
# blocks, and above 0 for the automaton, whose smallest events (one toppling of
# slip ``F / K ~ 0.2``, ``M ~ -1.6``) are not part of its power law.  The dashed
# line has the paper's slope b = 2/3.

M_MIN = {"OFC": 0.0, "Carlson-Langer": -6.0}
rows = []
fig, axes = plt.subplots(1, 2, figsize=(9, 3.8), layout="constrained", sharey=True)
for (model, graph), M in runs.items():
    fit = faultnet.fit_b_mle(M, m_min=M_MIN[model])
    rows.append((model, graph, len(M), fit.m_min, fit.b, fit.b_err))
    ax = axes[0 if graph == "lattice" else 1]
    faultnet.plotting.plot_magnitude_distribution(
        M, ax=ax, label=f"{model}: b = {fit.b:.2f}", bins=60
    )
for ax, title in zip(axes, ["uniform lattice (fixed boundary)", "percolation cluster at p_c"],
                     strict=True):  # fmt: skip
    ax.set_title(title)
    x0 = -2.0
    ax.plot([x0, x0 + 6], [1e-1, 1e-1 * math.exp(-6 * 2 / 3)], "k--", lw=1, label="b = 2/3")
    ax.legend(fontsize=8)
table = pd.DataFrame(rows, columns=["model", "graph", "events", "m_min", "b", "b_err"])
print(table.to_string(index=False, float_format=lambda x: f"{x:.3f}"))

# %%
# What the comparison shows, and what it does not
# -----------------------------------------------
# The automaton needs no geometry: on the uniform lattice its ``P(M)`` falls as
# a power law over five units of ``M`` (b near 0.95 above ``M = 0`` at this
# size, steepening towards the largest avalanches; the sizes in topplings
# follow ``s^-tau`` with ``tau ~ 1.8-1.9``).  The same rule on the critical
# cluster gives no power law at all: avalanches die in the cluster's dangling
# ends and narrow necks, and ``P(M)`` drops steeply above ``M ~ 1`` (b near 2
# above 0).  The blocks at ``alpha = 1`` give b near 0.69 above ``M = -6`` on
# both graphs, close to the paper's 2/3; on the uniform lattice the events
# between ``M ~ -2`` and 4 gather in a shoulder above the power law (the
# paper's 150 x 150 lattice: b = 0.85 on [-7, 4]), while on the critical
# cluster the straight line runs to the largest events (``M ~ 6``).  So here
# the fractal geometry straightens the blocks' law and breaks the
# automaton's.
#
# It does not settle which mechanism acts in the Earth, nor make the two
# models comparable event for event: the automaton has no inertia, no
# friction drop and no time inside an event, and its ``M`` counts the
# topplings' slips, not a dynamic rupture.  The blocks need ``alpha`` near 1
# for a power law at all (the paper's Figs. 8 and 9), a special choice that
# self-organized criticality would not need; the automaton's b depends on its
# alpha and on the system size.  Every number above comes from one system
# size, one seed and one fitting threshold per model.
plt.show()
