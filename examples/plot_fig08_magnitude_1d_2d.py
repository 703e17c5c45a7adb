"""
Fig. 8: magnitude distributions in one and two dimensions
=========================================================

Sakaguchi & Morita (2013), Fig. 8: the density P(M) of the magnitude
M = ln S (S: total slip of an event) at alpha = 2, 1 and 0.25, k = 16,
sigma = 0.01,

* (a) on a ring of N = 2000 blocks: a hump near M ~ 4 at alpha = 2, an
  exponential P(M) ~ exp(-b M) with b = 0.45 +/- 0.02 (fit on -6 <= M <= 3) at
  alpha = 1, a rapid decay near M ~ 1 at alpha = 0.25;
* (b) on a 150 x 150 square lattice: a peak near M ~ 8.5 at alpha = 2,
  b = 0.85 +/- 0.02 (fit on -7 <= M <= 4) at alpha = 1, a rapid decay near
  M ~ 1 at alpha = 0.25;
* (c) (not in the paper) the lattice boundary conditions at alpha = 1:
  periodic (used for panel b) versus open.

Choices the paper leaves open: initial state x_i uniform in [0, 0.01) (seed 1),
plate at u = 0; the events before plate time t = 5 (ring) or t = 2 (lattice) are
discarded as transient, then 10^6 events are recorded per curve; the ring and
the lattice of panel (b) are periodic.  b is fitted by least squares on ln P(M)
in the paper's windows (``faultnet.fit_b_lsq``, 20 bins) and, for comparison,
by Aki's maximum likelihood above the window's lower edge (``fit_b_mle``).

Each curve is one call of ``run_magnitudes`` below: ``faultnet.simulate`` in
chunks through the transient, then the recorded events.  A million events on
each of seven systems take hours, so paper mode reloads their magnitudes from
``data/fig08_*.npz``, stored as histograms with bins of 0.05 in M together with
the parameters and provenance of the run (``python examples/_paper_data.py
--regenerate`` removes them and runs this page to compute them again).  The
magnitudes come back as the centres of those bins, in fast mode too.  Fast
mode (``FAULTNET_FAST=1`` or ``--fast``) uses a ring of 300 blocks and a
14 x 14 lattice with a few thousand events: its numbers are not the paper's.
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
RING = [f"fig08_ring_alpha{a:g}" for a in (2.0, 1.0, 0.25)]
SQUARE = [f"fig08_square_alpha{a:g}" for a in (2.0, 1.0, 0.25)]
OPEN = "fig08_square_open_alpha1"
RING_WINDOW, SQUARE_WINDOW = (-6.0, 3.0), (-7.0, 4.0)
WIDTH = 0.5 if FAST else 0.25  # bin width of the drawn P(M) (wider for the short fast runs)

setting = paper.ENTRIES[RING[0]]["fast" if FAST else "paper"]
lattice = paper.ENTRIES[SQUARE[0]]["fast" if FAST else "paper"]
paper.header(
    "Fig. 8: P(M) on a ring and on a square lattice (k = 16, sigma = 0.01)",
    FAST,
    [
        f"(a) {paper.graph_text(setting['graph'])}; (b) {paper.graph_text(lattice['graph'])}",
        f"(c) alpha = 1 on the open {lattice['graph']['rows']}^2 lattice",
        "initial state: x uniform in [0, 0.01), u = 0 (seed 1)",
        f"transient discarded: plate time t < {setting['transient_t']:g} (ring), "
        f"t < {lattice['transient_t']:g} (lattice); then {setting['n_events']} (ring) / "
        f"{lattice['n_events']} (lattice) events per curve",
    ],
)


# %%
# One run: simulate past the transient, then record the magnitudes
# ----------------------------------------------------------------
# ``graph`` describes the ring or lattice (as stored with the run's data).
# ``faultnet.simulate`` continues from ``x0=state``; the transient is run in
# chunks until the plate time reaches ``transient_t`` and thrown away.
def make_graph(graph):
    if graph["kind"] == "ring":
        return faultnet.graphs.ring(graph["n"])
    return faultnet.graphs.square_lattice(graph["rows"], graph["cols"], periodic=graph["periodic"])


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
# The seven runs (computed in fast mode, reloaded in paper mode)
# --------------------------------------------------------------
runs = {}
for name in RING + SQUARE + [OPEN]:
    result, prov = paper.magnitudes(name, run_magnitudes, FAST)
    runs[name] = result
    print(paper.describe_run(name, result, prov))


# %%
# P(M), b fits and the position of a hump
# ---------------------------------------
# ``faultnet.magnitude_distribution`` bins the magnitudes into P(M);
# ``faultnet.fit_b_lsq`` fits ln P(M) on a window (the paper's method, 20 bins)
# and ``faultnet.fit_b_mle`` is Aki's maximum likelihood above a magnitude.
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


def add_peak_row(table, quantity, paper_value, run, lo, hi):
    value = hump(run, lo, hi)
    note = "" if np.isfinite(value) else f"no interior maximum of P(M) in [{lo:g}, {hi:g}]"
    table.add(quantity, paper_value, value, note)


# %%
# Figure
# ------
fig, axes = plt.subplot_mosaic([["a", "b"], ["c", "c"]], figsize=(8, 8.4))
for ax, names, window, title in (
    (axes["a"], RING, RING_WINDOW, "(a) ring"),
    (axes["b"], SQUARE, SQUARE_WINDOW, "(b) square lattice (periodic)"),
):
    for name in names:
        run = runs[name]
        fit = b_fits(run, window)[0] if run["alpha"] == 1.0 else None
        plotting.plot_magnitude_distribution(
            p_of_m(run), fit=fit, ax=ax, label=f"alpha = {run['alpha']:g}"
        )
    ax.axvspan(*window, color="0.9", zorder=0)
    ax.set_title(f"{title}, N = {runs[names[0]]['n_blocks']}")
for name, label in ((SQUARE[1], "periodic"), (OPEN, "open")):
    run = runs[name]
    plotting.plot_magnitude_distribution(
        p_of_m(run), fit=b_fits(run, SQUARE_WINDOW)[0], ax=axes["c"], label=f"alpha = 1, {label}"
    )
axes["c"].set_title("(c) lattice boundaries at alpha = 1")
fig.suptitle(f"Fig. 8 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig08")

# %%
# Paper versus faultnet
# ---------------------
ring_lsq, ring_mle = b_fits(runs[RING[1]], RING_WINDOW)
sq_lsq, sq_mle = b_fits(runs[SQUARE[1]], SQUARE_WINDOW)
open_lsq, open_mle = b_fits(runs[OPEN], SQUARE_WINDOW)
table = paper.Table("Fig. 8", FAST)
table.add("(a) ring, alpha=1: b (lsq, M in [-6, 3])", "0.45 +/- 0.02", paper.fit_text(ring_lsq))
table.add(
    "(a) ring, alpha=1: b (Aki MLE, M >= -6)",
    "0.45 (lsq fit)",
    paper.fit_text(ring_mle),
    "MLE uses every event above -6",
)
add_peak_row(table, "(a) ring, alpha=2: hump position M", "~ 4", runs[RING[0]], 0.0, 12.0)
table.add(
    "(a) ring, alpha=0.25: P(M) decays near M",
    "~ 1",
    tail_end(runs[RING[2]]),
    "99.9% of events below this M",
)
table.add("(b) square, alpha=1: b (lsq, M in [-7, 4])", "0.85 +/- 0.02", paper.fit_text(sq_lsq))
table.add("(b) square, alpha=1: b (Aki MLE, M >= -7)", "0.85 (lsq fit)", paper.fit_text(sq_mle))
add_peak_row(table, "(b) square, alpha=2: peak position M", "~ 8.5", runs[SQUARE[0]], 0.0, 14.0)
table.add(
    "(b) square, alpha=0.25: P(M) decays near M",
    "~ 1",
    tail_end(runs[SQUARE[2]]),
    "99.9% of events below this M",
)
table.add("(c) open lattice, alpha=1: b (lsq, [-7, 4])", "not stated", paper.fit_text(open_lsq))
table.print()
