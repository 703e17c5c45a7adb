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

Paper mode first looks for the stored histograms ``data/fig08_*.npz``
(regenerate with ``python examples/_paper_data.py --regenerate``); without
them a paper-mode run takes hours.  Fast mode (``FAULTNET_FAST=1`` or
``--fast``) uses a ring of 400 blocks and a 20 x 20 lattice with a few thousand
events: its numbers are not the paper's.
"""

# %%
# Setup
# -----
import _paper_data as paper
import matplotlib.pyplot as plt

from faultnet import plotting

FAST = paper.fast_mode()
RING = [f"fig08_ring_alpha{a:g}" for a in (2.0, 1.0, 0.25)]
SQUARE = [f"fig08_square_alpha{a:g}" for a in (2.0, 1.0, 0.25)]
OPEN = "fig08_square_open_alpha1"
RING_WINDOW, SQUARE_WINDOW = (-6.0, 3.0), (-7.0, 4.0)

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
# Runs (or stored histograms)
# ---------------------------
runs = {}
for name in RING + SQUARE + [OPEN]:
    result, prov = paper.magnitudes(name, FAST)
    runs[name] = result
    print(paper.describe_run(name, result, prov))

# %%
# Figure
# ------
fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
for ax, names, window, title in (
    (axes[0], RING, RING_WINDOW, "(a) ring"),
    (axes[1], SQUARE, SQUARE_WINDOW, "(b) square lattice (periodic)"),
):
    for name in names:
        res = runs[name]
        fit = paper.fits(res, window)[0] if res["alpha"] == 1.0 else None
        plotting.plot_magnitude_distribution(
            paper.magnitude_table(res), fit=fit, ax=ax, label=f"alpha = {res['alpha']:g}"
        )
    ax.axvspan(*window, color="0.9", zorder=0)
    ax.set_title(f"{title}, N = {runs[names[0]]['n_blocks']}")
for name, label in ((SQUARE[1], "periodic"), (OPEN, "open")):
    res = runs[name]
    plotting.plot_magnitude_distribution(
        paper.magnitude_table(res),
        fit=paper.fits(res, SQUARE_WINDOW)[0],
        ax=axes[2],
        label=f"alpha = 1, {label}",
    )
axes[2].set_title("(c) lattice boundaries at alpha = 1")
fig.suptitle(f"Fig. 8 [{'FAST mode' if FAST else 'paper mode'}]")
fig.tight_layout()
paper.save_figure(fig, "fig08")

# %%
# Paper versus faultnet
# ---------------------
ring_lsq, ring_mle = paper.fits(runs[RING[1]], RING_WINDOW)
sq_lsq, sq_mle = paper.fits(runs[SQUARE[1]], SQUARE_WINDOW)
open_lsq, open_mle = paper.fits(runs[OPEN], SQUARE_WINDOW)
table = paper.Table("Fig. 8", FAST)
table.add("(a) ring, alpha=1: b (lsq, M in [-6, 3])", "0.45 +/- 0.02", paper.fit_text(ring_lsq))
table.add(
    "(a) ring, alpha=1: b (Aki MLE, M >= -6)",
    "0.45 (lsq fit)",
    paper.fit_text(ring_mle),
    "MLE uses every event above -6",
)
paper.add_peak_row(table, "(a) ring, alpha=2: hump position M", "~ 4", runs[RING[0]], 0.0, 12.0)
table.add(
    "(a) ring, alpha=0.25: P(M) decays near M",
    "~ 1",
    paper.tail_end(runs[RING[2]]),
    "99.9% of events below this M",
)
table.add("(b) square, alpha=1: b (lsq, M in [-7, 4])", "0.85 +/- 0.02", paper.fit_text(sq_lsq))
table.add("(b) square, alpha=1: b (Aki MLE, M >= -7)", "0.85 (lsq fit)", paper.fit_text(sq_mle))
paper.add_peak_row(
    table, "(b) square, alpha=2: peak position M", "~ 8.5", runs[SQUARE[0]], 0.0, 14.0
)
table.add(
    "(b) square, alpha=0.25: P(M) decays near M",
    "~ 1",
    paper.tail_end(runs[SQUARE[2]]),
    "99.9% of events below this M",
)
table.add("(c) open lattice, alpha=1: b (lsq, [-7, 4])", "not stated", paper.fit_text(open_lsq))
table.print()
