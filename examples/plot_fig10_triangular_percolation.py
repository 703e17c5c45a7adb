"""
Fig. 10: critical percolation cluster of a triangular lattice
=============================================================

Sakaguchi & Morita (2013), Fig. 10 (k = 16, sigma = 0.01; triangular
lattice, site-percolation threshold p_c = 0.5):

* (a) the percolation clusters at p = 0.5 on a triangular lattice (springs
  between occupied neighbours, one colour per cluster; the paper does not give
  the size of this picture: 50 x 50 here);
* (b) P(M) on the critical (largest) cluster at p = 0.5 of a 150 x 150
  triangular lattice for alpha = 2, 1, 0.25: a power law with b ~ 0.67 at
  alpha = 1, as on the square lattice (Fig. 9b), so b does not depend on the
  substrate lattice.

The dashed black line in (b) has the slope b = 0.67.

Choices the paper leaves open: open boundaries (rows offset by half a
spacing, ``faultnet.graphs.triangular_lattice``); occupation seed 2013;
initial state x uniform in [0, 0.01) (seed 1), u = 0; events before plate time
t = 2 discarded, then 10^6 events per curve; b is fitted by least squares on
-6 <= M <= 2 (our window, as in Fig. 9) and by Aki's MLE above M = -6.  Paper
mode reads ``data/fig10b_*.npz`` if present (``python examples/_paper_data.py
--regenerate``), otherwise it runs for hours.  Fast mode (``FAULTNET_FAST=1``
or ``--fast``) uses a 40 x 40 lattice and a few thousand events.
"""

# %%
# Setup
# -----
import _paper_data as paper
import matplotlib.pyplot as plt
import networkx as nx
import numpy as np

import faultnet
from faultnet import plotting

FAST = paper.fast_mode()
WINDOW = (-6.0, 2.0)
B_REF = 0.67
NAMES = [f"fig10b_triangular_alpha{a:g}" for a in (2.0, 1.0, 0.25)]
spec = paper.ENTRIES[NAMES[0]]["fast" if FAST else "paper"]
paper.header(
    "Fig. 10: Carlson-Langer model on the critical cluster of a triangular lattice",
    FAST,
    [
        "(a) p = 0.5 on a 50x50 open triangular lattice (occupation seed 2013)",
        f"(b) largest cluster at p = 0.5 of a {spec['graph']['rows']}x{spec['graph']['cols']} "
        f"open triangular lattice (seed {spec['graph']['seed']})",
        "initial state: x uniform in [0, 0.01), u = 0 (seed 1)",
        f"transient discarded: plate time t < {spec['transient_t']:g}; then up to "
        f"{spec['n_events']} events per curve",
        f"b fits: least squares on {WINDOW[0]:g} <= M <= {WINDOW[1]:g}, "
        f"Aki MLE above {WINDOW[0]:g}",
    ],
)

# %%
# (a) percolation clusters at p = 0.5
# -----------------------------------
clusters = faultnet.graphs.site_percolation(
    faultnet.graphs.triangular_lattice(50, 50), 0.5, rng=2013, keep="all"
)

# %%
# (b) magnitude distributions (runs or stored histograms)
# -------------------------------------------------------
runs = {}
for name in NAMES:
    result, prov = paper.magnitudes(name, FAST)
    runs[name] = result
    print(paper.describe_run(name, result, prov))
print(
    f"critical cluster: {runs[NAMES[0]]['n_blocks']} blocks, {runs[NAMES[0]]['n_springs']} springs"
)

# %%
# Figure
# ------
fig, axes = plt.subplots(1, 2, figsize=(11, 4.6))
plotting.plot_graph(clusters, ax=axes[0], color_by="component", linewidth=0.6)
axes[0].set_title("(a) clusters at p = 0.5, triangular 50 x 50")
for name in NAMES:
    res = runs[name]
    fit = paper.fits(res, WINDOW)[0] if res["alpha"] == 1.0 else None
    plotting.plot_magnitude_distribution(
        paper.magnitude_table(res), fit=fit, ax=axes[1], label=f"alpha = {res['alpha']:g}"
    )
table1 = paper.magnitude_table(runs[NAMES[1]])
y0 = np.interp(-4.0, table1["M"], table1["density"])
m = np.linspace(-7.0, 4.0, 50)
axes[1].plot(m, y0 * np.exp(-B_REF * (m + 4.0)), "k--", linewidth=1, label="b = 0.67")
axes[1].legend(fontsize=8)
axes[1].set_title("(b) critical cluster, triangular lattice")
fig.suptitle(f"Fig. 10 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig10")

# %%
# Paper versus faultnet
# ---------------------
lsq, mle = paper.fits(runs[NAMES[1]], WINDOW)
table = paper.Table("Fig. 10", FAST)
table.add(
    "(a) clusters at p = 0.5 (triangular)",
    "picture",
    f"{clusters.number_of_nodes()} sites in {nx.number_connected_components(clusters)} clusters",
)
table.add(
    "(b) alpha=1: b (lsq)", "0.67", paper.fit_text(lsq), f"M in [{WINDOW[0]:g}, {WINDOW[1]:g}]"
)
table.add("(b) alpha=1: b (Aki MLE)", "0.67", paper.fit_text(mle), f"M >= {WINDOW[0]:g}")
paper.add_peak_row(
    table, "(b) alpha=2: hump position M", "not stated (Fig. 9b: ~ 3)", runs[NAMES[0]], -2.0, 10.0
)
table.add(
    "(b) alpha=0.25: P(M) decays near M",
    "not stated (Fig. 9b: ~ -1)",
    paper.tail_end(runs[NAMES[2]]),
    "99.9% of events below this M",
)
table.print()
