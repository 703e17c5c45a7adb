"""
Fig. 9: the block-spring model on site-percolation clusters
===========================================================

Sakaguchi & Morita (2013), Fig. 9 (k = 16, sigma = 0.01; square lattice,
p_c = 0.5927):

* (a) the percolation clusters at p = 0.56 on a 50 x 50 lattice (the springs
  between occupied neighbours are drawn, one colour per cluster);
* (b) P(M) on the largest cluster at p = p_c of a 150 x 150 lattice for
  alpha = 2, 0.9, 0.25: a hump near M ~ 3 at alpha = 2, a power law with
  b ~ 0.67 at alpha = 0.9, a rapid decay near M ~ -1 at alpha = 0.25;
* (c) P(M) on all clusters at p_c for alpha = 2, 1, 0.25: b = 0.67 at
  alpha = 1, plus a singular peak from isolated blocks (each one a periodic
  one-block stick-slip whose slip is that of Fig. 1b), a shoulder near M ~ 2
  at alpha = 2, a rapid decay near M ~ -1 at alpha = 0.25;
* (d) alpha = 1, isolated blocks removed, p = p_c, 0.5, 0.4: the power law
  (b ~ 0.67) at p_c; a small peak near M ~ 0 at p = 0.5 and 0.4, and a rapid
  decay for M > 1 at p = 0.4.

The dashed black line in (b)-(d) has the slope b = 0.67.

Choices the paper leaves open: open lattice boundaries; one occupation
realisation (seed 2013) for every panel, so that the clusters at p = 0.4,
0.5 and p_c are nested; initial state x uniform in [0, 0.01) (seed 1), u = 0;
events before plate time t = 2 discarded, then 10^6 events per curve; b is
fitted by least squares on -6 <= M <= 2 (our window: the paper gives none)
and by Aki's MLE above M = -6.  Paper mode reads ``data/fig09*.npz`` if
present (``python examples/_paper_data.py --regenerate``); otherwise it runs
for hours.  Fast mode (``FAULTNET_FAST=1`` or ``--fast``) uses a 40 x 40
lattice and a few thousand events.
"""

# %%
# Setup
# -----
import _paper_data as paper
import matplotlib.pyplot as plt
import networkx as nx
import numpy as np

import faultnet
from faultnet import dynamics, plotting

FAST = paper.fast_mode()
WINDOW = (-6.0, 2.0)
B_REF = 0.67
B_NAMES = [f"fig09b_largest_alpha{a:g}" for a in (2.0, 0.9, 0.25)]
C_NAMES = [f"fig09c_all_alpha{a:g}" for a in (2.0, 1.0, 0.25)]
D_NAMES = ["fig09d_pruned_ppc", "fig09d_pruned_p0.5", "fig09d_pruned_p0.4"]
spec = paper.ENTRIES[B_NAMES[0]]["fast" if FAST else "paper"]
paper.header(
    "Fig. 9: Carlson-Langer model on square-lattice percolation clusters",
    FAST,
    [
        "(a) p = 0.56 on a 50x50 open lattice (occupation seed 2013)",
        f"(b)-(d) {spec['graph']['rows']}x{spec['graph']['cols']} open lattice, occupation seed "
        f"{spec['graph']['seed']}, p_c = {paper.P_C_SQUARE}",
        "initial state: x uniform in [0, 0.01), u = 0 (seed 1)",
        f"transient discarded: plate time t < {spec['transient_t']:g}; then "
        f"{spec['n_events']} events per curve"
        + (f" ({spec['n_events'] // 2} at alpha = 0.25)" if FAST else ""),
        f"b fits: least squares on {WINDOW[0]:g} <= M <= {WINDOW[1]:g}, "
        f"Aki MLE above {WINDOW[0]:g}",
    ],
)

# %%
# (a) percolation clusters at p = 0.56
# ------------------------------------
clusters = faultnet.graphs.site_percolation(
    faultnet.graphs.square_lattice(50, 50), 0.56, rng=2013, keep="all"
)

# %%
# (b)-(d) magnitude distributions (runs or stored histograms)
# -----------------------------------------------------------
runs = {}
for name in B_NAMES + C_NAMES + D_NAMES:
    result, prov = paper.magnitudes(name, FAST)
    runs[name] = result
    print(paper.describe_run(name, result, prov))
    print(
        f"    graph: {paper.graph_text(prov['params']['graph'])}: {result['n_blocks']} blocks, "
        f"{result['n_clusters']} clusters, {result['n_isolated']} isolated"
    )


def reference_line(ax, anchor):
    """Dashed line of slope b = 0.67 through the P(M) of ``anchor`` at M = -4."""
    table = paper.magnitude_table(anchor)
    y0 = np.interp(-4.0, table["M"], table["density"])
    m = np.linspace(-7.0, 4.0, 50)
    ax.plot(m, y0 * np.exp(-B_REF * (m + 4.0)), "k--", linewidth=1, label="b = 0.67")


def draw(ax, names, labels, fit_name, title):
    for name, label in zip(names, labels, strict=True):
        res = runs[name]
        fit = paper.fits(res, WINDOW)[0] if name == fit_name else None
        plotting.plot_magnitude_distribution(
            paper.magnitude_table(res), fit=fit, ax=ax, label=label
        )
    reference_line(ax, runs[fit_name])
    ax.legend(fontsize=7)
    ax.set_title(title)


# %%
# Figure
# ------
fig, axes = plt.subplots(1, 4, figsize=(19, 4.6))
plotting.plot_graph(clusters, ax=axes[0], color_by="component", linewidth=0.8)
axes[0].set_title("(a) clusters at p = 0.56, 50 x 50")
draw(
    axes[1],
    B_NAMES,
    ["alpha = 2", "alpha = 0.9", "alpha = 0.25"],
    B_NAMES[1],
    "(b) largest cluster at p_c",
)
draw(
    axes[2],
    C_NAMES,
    ["alpha = 2", "alpha = 1", "alpha = 0.25"],
    C_NAMES[1],
    "(c) all clusters at p_c",
)
draw(
    axes[3],
    D_NAMES,
    ["p = p_c", "p = 0.5", "p = 0.4"],
    D_NAMES[0],
    "(d) alpha = 1, isolated blocks removed",
)
fig.suptitle(f"Fig. 9 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig09")

# %%
# Paper versus faultnet
# ---------------------
table = paper.Table("Fig. 9", FAST)
table.add(
    "(a) clusters at p = 0.56 on 50x50",
    "picture",
    f"{clusters.number_of_nodes()} sites in {nx.number_connected_components(clusters)} clusters",
)
lsq, mle = paper.fits(runs[B_NAMES[1]], WINDOW)
table.add(
    "(b) largest cluster, alpha=0.9: b (lsq)",
    "~ 0.67",
    paper.fit_text(lsq),
    f"M in [{WINDOW[0]:g}, {WINDOW[1]:g}]",
)
table.add(
    "(b) largest cluster, alpha=0.9: b (Aki MLE)",
    "~ 0.67",
    paper.fit_text(mle),
    f"M >= {WINDOW[0]:g}",
)
paper.add_peak_row(table, "(b) alpha=2: hump position M", "~ 3", runs[B_NAMES[0]], -2.0, 10.0)
table.add(
    "(b) alpha=0.25: P(M) decays near M",
    "~ -1",
    paper.tail_end(runs[B_NAMES[2]]),
    "99.9% of events below this M",
)
lsq, mle = paper.fits(runs[C_NAMES[1]], WINDOW)
table.add("(c) all clusters, alpha=1: b (lsq)", "0.67", paper.fit_text(lsq))
table.add("(c) all clusters, alpha=1: b (Aki MLE)", "0.67", paper.fit_text(mle))
for name in C_NAMES:
    res = runs[name]
    m1 = float(np.log(dynamics.one_block_slip_curve([res["alpha"]], sigma=0.01)["s"].iloc[0]))
    edges = np.asarray(res["M_edges"])
    centres = 0.5 * (edges[:-1] + edges[1:])
    spike = np.abs(centres - m1) < 0.05
    share = res["counts"][spike].sum() / res["counts"].sum()
    table.add(
        f"(c) alpha={res['alpha']:g}: isolated-block peak at ln s1",
        "singular peak",
        f"M = {m1:.3f}: {share:.1%} of events",
        f"{res['n_isolated']} isolated blocks",
    )
paper.add_peak_row(
    table,
    "(c) alpha=2: shoulder near M",
    "~ 2",
    runs[C_NAMES[0]],
    0.5,
    10.0,
    "highest bin above the isolated-block peak",
)
table.add(
    "(c) alpha=0.25: P(M) decays near M",
    "~ -1",
    paper.tail_end(runs[C_NAMES[2]]),
    "99.9% of events below this M",
)
lsq, mle = paper.fits(runs[D_NAMES[0]], WINDOW)
table.add("(d) p_c, no isolated blocks: b (lsq)", "~ 0.67", paper.fit_text(lsq))
table.add("(d) p_c, no isolated blocks: b (Aki MLE)", "~ 0.67", paper.fit_text(mle))
paper.add_peak_row(table, "(d) p=0.5: small peak near M", "~ 0", runs[D_NAMES[1]], -3.0, 3.0)
paper.add_peak_row(table, "(d) p=0.4: small peak near M", "~ 0", runs[D_NAMES[2]], -3.0, 3.0)
table.add(
    "(d) p=0.4: P(M) decays for M >",
    "~ 1",
    paper.tail_end(runs[D_NAMES[2]]),
    "99.9% of events below this M",
)
table.print()
