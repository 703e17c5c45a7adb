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
-6 <= M <= 2 (our window, as in Fig. 9) and by Aki's MLE above M = -6.

Each curve is one call of ``run_magnitudes`` below.  Paper mode reloads the
magnitudes of these hours-long runs from ``data/fig10b_*.npz``, stored as
histograms with bins of 0.05 in M with the parameters and provenance of each
run (``python examples/_paper_data.py --regenerate`` removes them and runs this
page to compute them again); the magnitudes come back as the bin centres, in
fast mode too.  Fast mode (``FAULTNET_FAST=1`` or ``--fast``) uses a 40 x 40
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
from faultnet import plotting

FAST = paper.fast_mode()
WINDOW = (-6.0, 2.0)
B_REF = 0.67
WIDTH = 0.5 if FAST else 0.25  # bin width of the drawn P(M) (wider for the short fast runs)
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
# One run: the critical cluster, the transient, the recorded magnitudes
# ---------------------------------------------------------------------
# ``graph`` describes the diluted lattice (as stored with the run's data).  The
# transient is run in chunks until the plate time reaches ``transient_t`` and
# thrown away.
def make_graph(graph):
    lattice = faultnet.graphs.triangular_lattice(
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
# (b) the three runs (computed in fast mode, reloaded in paper mode)
# ------------------------------------------------------------------
runs = {}
for name in NAMES:
    result, prov = paper.magnitudes(name, run_magnitudes, FAST)
    runs[name] = result
    print(paper.describe_run(name, result, prov))
print(
    f"critical cluster: {runs[NAMES[0]]['n_blocks']} blocks, {runs[NAMES[0]]['n_springs']} springs"
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


# %%
# Figure
# ------
fig, axes = plt.subplots(1, 2, figsize=(8, 4.4))
plotting.plot_graph(clusters, ax=axes[0], color_by="component", linewidth=0.6)
axes[0].set_title("(a) clusters at p = 0.5, triangular 50 x 50")
for name in NAMES:
    run = runs[name]
    fit = b_fits(run, WINDOW)[0] if run["alpha"] == 1.0 else None
    plotting.plot_magnitude_distribution(
        p_of_m(run), fit=fit, ax=axes[1], label=f"alpha = {run['alpha']:g}"
    )
anchor = p_of_m(runs[NAMES[1]])  # the reference line meets the alpha = 1 curve at M = -4
y0 = np.interp(-4.0, anchor["M"], anchor["density"])
m = np.linspace(-7.0, 4.0, 50)
axes[1].plot(m, y0 * np.exp(-B_REF * (m + 4.0)), "k--", linewidth=1, label="b = 0.67")
axes[1].legend()
axes[1].set_title("(b) critical cluster, triangular lattice")
fig.suptitle(f"Fig. 10 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig10")

# %%
# Paper versus faultnet
# ---------------------
lsq, mle = b_fits(runs[NAMES[1]], WINDOW)
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
value = hump(runs[NAMES[0]], -2.0, 10.0)
table.add(
    "(b) alpha=2: hump position M",
    "not stated (Fig. 9b: ~ 3)",
    value,
    "" if np.isfinite(value) else "no interior maximum of P(M) in [-2, 10]",
)
table.add(
    "(b) alpha=0.25: P(M) decays near M",
    "not stated (Fig. 9b: ~ -1)",
    tail_end(runs[NAMES[2]]),
    "99.9% of events below this M",
)
table.print()
