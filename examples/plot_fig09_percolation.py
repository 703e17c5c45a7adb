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
and by Aki's MLE above M = -6.

Each curve is one call of ``run_magnitudes`` below (the cluster from
``faultnet.graphs.site_percolation``, then ``faultnet.simulate``).  Paper mode
reloads the magnitudes of these hours-long runs from ``data/fig09*.npz``,
stored as histograms with bins of 0.05 in M with the parameters and provenance
of each run (``python examples/_paper_data.py --regenerate`` removes them and
runs this page to compute them again); the magnitudes come back as the bin
centres, in fast mode too.  Fast mode (``FAULTNET_FAST=1`` or ``--fast``) uses
a 40 x 40 lattice and a few thousand events.
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
WIDTH = 0.5 if FAST else 0.25  # bin width of the drawn P(M) (wider for the short fast runs)
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
        f"{spec['graph']['seed']}, p_c = {faultnet.graphs.percolation_threshold('square')}",
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
# One run: a percolation cluster, the transient, the recorded magnitudes
# ----------------------------------------------------------------------
# ``graph`` describes the diluted lattice (as stored with the run's data):
# ``keep="largest"`` keeps the largest cluster, ``"all"`` every cluster, and
# ``prune_isolated`` removes the blocks without neighbours.  The transient is
# run in chunks until the plate time reaches ``transient_t`` and thrown away.
def make_graph(graph):
    lattice = faultnet.graphs.square_lattice(
        graph["rows"], graph["cols"], periodic=graph["periodic"]
    )
    return faultnet.graphs.site_percolation(
        lattice,
        graph["p"],
        rng=graph["seed"],
        keep=graph["keep"],
        prune_isolated=graph["prune_isolated"],
    )


def run_magnitudes(graph, alpha, n_events, transient_t, seed):
    """Magnitudes M = ln S of ``n_events`` events after the transient, and the run's numbers."""
    g = make_graph(graph)
    model = faultnet.CarlsonLanger(g, k=16.0, sigma=0.01, alpha=alpha)
    chunk = int(min(20_000, max(500, n_events // 200)))
    state, n_trans, t_now = None, 0, 0.0
    while t_now < transient_t:
        res = faultnet.simulate(model, chunk, x0=state, rng=seed, progress=False)
        state, n_trans = res.state, n_trans + len(res.events)
        t_now = float(res.events["t"].iloc[-1])
    res = faultnet.simulate(model, int(n_events), x0=state, rng=seed, progress=False)
    ev = res.events
    t = ev["t"].to_numpy()
    span = float(t[-1] - t[0])
    return {
        "M": ev["M"].to_numpy(),
        "n_events": int(len(ev)),
        "n_transient_events": int(n_trans),
        "transient_t": float(transient_t),
        "t_start": float(t[0]),
        "t_end": float(t[-1]),
        "slip_rate": float(ev["S"].sum() / (model.n * span)) if span > 0 else float("nan"),
        "M_max": float(ev["M"].max()),
        "M_mean": float(ev["M"].mean()),
        "largest_event_blocks": int(ev["n_blocks"].max()),
        "n_blocks": int(model.n),
        "n_springs": int(g.number_of_edges()),
        "n_clusters": int(nx.number_connected_components(g)),
        "n_isolated": int(sum(1 for v in g if g.degree(v) == 0)),
        "seed": int(seed),
        "alpha": float(alpha),
        "sim_wall_time_s": float(res.metadata["wall_time_s"]),
    }


# %%
# (b)-(d) the nine runs (computed in fast mode, reloaded in paper mode)
# ---------------------------------------------------------------------
runs = {}
for name in B_NAMES + C_NAMES + D_NAMES:
    result, prov = paper.magnitudes(name, run_magnitudes, FAST)
    runs[name] = result
    print(paper.describe_run(name, result, prov))
    print(
        f"    graph: {paper.graph_text(prov['params']['graph'])}: {result['n_blocks']} blocks, "
        f"{result['n_clusters']} clusters, {result['n_isolated']} isolated"
    )


# %%
# P(M), b fits and the position of a hump
# ---------------------------------------
# ``faultnet.magnitude_distribution`` bins the magnitudes into P(M);
# ``faultnet.fit_b_lsq`` fits ln P(M) on a window (20 bins) and
# ``faultnet.fit_b_mle`` is Aki's maximum likelihood above a magnitude.
BINS = np.arange(-16.0, 16.0 + 1e-9, WIDTH)


def p_of_m(run):
    return faultnet.magnitude_distribution(run["M"], bins=BINS)


def b_fits(run, window):
    """(least squares on the window, Aki MLE above its lower edge); None where no fit."""
    try:
        lsq = faultnet.fit_b_lsq(run["M"], window[0], window[1], bins=20)
    except ValueError:  # too few non-empty bins in the window
        lsq = None
    try:
        mle = faultnet.fit_b_mle(run["M"], m_min=window[0])
    except ValueError:  # too few events above the window's lower edge
        mle = None
    return lsq, mle


def hump(run, lo, hi):
    """M of the highest local maximum of P(M) in [lo, hi] (P smoothed over 3 bins); NaN if none."""
    table = p_of_m(run)
    inside = table[(table["M"] >= lo) & (table["M"] <= hi) & (table["count"] > 0)]
    if len(inside) < 5:
        return float("nan")
    d = np.convolve(inside["density"].to_numpy(), np.ones(3) / 3.0, mode="same")
    k = np.arange(2, len(d) - 2)  # the end bins of the smoothed curve are one-sided
    peaks = k[(d[k] >= d[k - 1]) & (d[k] >= d[k + 1])]
    return float(inside["M"].iloc[peaks[np.argmax(d[peaks])]]) if peaks.size else float("nan")


def tail_end(run, q=0.999):
    """Magnitude below which a fraction q of the events lie (upper edge of a stored bin)."""
    table = faultnet.magnitude_distribution(run["M"], bins=run["M_edges"])
    upper = (table["M"] + 0.5 * table["width"]).to_numpy()
    return float(upper[np.searchsorted(np.cumsum(table["count"]) / table.attrs["n"], q)])


def add_peak_row(table, quantity, paper_value, run, lo, hi, note=""):
    value = hump(run, lo, hi)
    if not np.isfinite(value):
        note = f"no interior maximum of P(M) in [{lo:g}, {hi:g}]"
    table.add(quantity, paper_value, value, note)


def draw(ax, names, labels, fit_name, title):
    """P(M) of the runs ``names``, the fit of ``fit_name`` and a line of slope b = 0.67."""
    for name, label in zip(names, labels, strict=True):
        run = runs[name]
        fit = b_fits(run, WINDOW)[0] if name == fit_name else None
        plotting.plot_magnitude_distribution(p_of_m(run), fit=fit, ax=ax, label=label)
    anchor = p_of_m(runs[fit_name])  # the reference line meets this P(M) at M = -4
    y0 = np.interp(-4.0, anchor["M"], anchor["density"])
    m = np.linspace(-7.0, 4.0, 50)
    ax.plot(m, y0 * np.exp(-B_REF * (m + 4.0)), "k--", linewidth=1, label="b = 0.67")
    ax.legend(fontsize=9)
    ax.set_title(title)


# %%
# Figure
# ------
fig, axes = plt.subplots(2, 2, figsize=(8, 8.4))
axes = axes.ravel()
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
    "(d) alpha = 1, no isolated blocks",
)
fig.suptitle(f"Fig. 9 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig09")

# %%
# Paper versus faultnet
# ---------------------
# The isolated blocks of (c) each repeat the one-block stick-slip of Fig. 1:
# ``faultnet.dynamics.one_block_slip_curve`` gives its slip s1, so they make a
# spike of P(M) at M = ln s1.
table = paper.Table("Fig. 9", FAST)
table.add(
    "(a) clusters at p = 0.56 on 50x50",
    "picture",
    f"{clusters.number_of_nodes()} sites in {nx.number_connected_components(clusters)} clusters",
)
lsq, mle = b_fits(runs[B_NAMES[1]], WINDOW)
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
add_peak_row(table, "(b) alpha=2: hump position M", "~ 3", runs[B_NAMES[0]], -2.0, 10.0)
table.add(
    "(b) alpha=0.25: P(M) decays near M",
    "~ -1",
    tail_end(runs[B_NAMES[2]]),
    "99.9% of events below this M",
)
lsq, mle = b_fits(runs[C_NAMES[1]], WINDOW)
table.add("(c) all clusters, alpha=1: b (lsq)", "0.67", paper.fit_text(lsq))
table.add("(c) all clusters, alpha=1: b (Aki MLE)", "0.67", paper.fit_text(mle))
for name in C_NAMES:
    run = runs[name]
    m1 = float(np.log(dynamics.one_block_slip_curve([run["alpha"]], sigma=0.01)["s"].iloc[0]))
    share = np.mean(np.abs(run["M"] - m1) < 0.05)  # the bins whose centre is within 0.05
    table.add(
        f"(c) alpha={run['alpha']:g}: isolated-block peak at ln s1",
        "singular peak",
        f"M = {m1:.3f}: {share:.1%} of events",
        f"{run['n_isolated']} isolated blocks",
    )
add_peak_row(
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
    tail_end(runs[C_NAMES[2]]),
    "99.9% of events below this M",
)
lsq, mle = b_fits(runs[D_NAMES[0]], WINDOW)
table.add("(d) p_c, no isolated blocks: b (lsq)", "~ 0.67", paper.fit_text(lsq))
table.add("(d) p_c, no isolated blocks: b (Aki MLE)", "~ 0.67", paper.fit_text(mle))
add_peak_row(table, "(d) p=0.5: small peak near M", "~ 0", runs[D_NAMES[1]], -3.0, 3.0)
add_peak_row(table, "(d) p=0.4: small peak near M", "~ 0", runs[D_NAMES[2]], -3.0, 3.0)
table.add(
    "(d) p=0.4: P(M) decays for M >",
    "~ 1",
    tail_end(runs[D_NAMES[2]]),
    "99.9% of events below this M",
)
table.print()
