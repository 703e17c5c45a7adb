"""
Statistical seismology of the ring: alpha = 1 against alpha = 2
================================================================

The tools of :mod:`faultnet.seismicity` on two long catalogs of the ring of
N = 2000 blocks at k = 16, sigma = 0.01: alpha = 1, where P(M) is a power law
(b = 0.45 in the paper), and alpha = 2, where P(M) has a hump of large,
characteristic events.  Questions, as in Mori & Kawamura (PRL 2005, JGR 2006)
and Kawamura et al. (Rev. Mod. Phys. 2012) for the Burridge-Knopoff model:

* What does the distribution of waiting times look like (Corral's rescaling,
  against the exponential law of a Poisson process)?
* Do large events recur periodically, system-wide or at one place?
* Is a large event preceded by rising activity near its hypocentre, and
  followed by Omori-Utsu aftershocks?
* Is there quiescence near the coming hypocentre (a "Mogi doughnut")?
* Does the b-value change around mainshocks?

**Data.**  3,000,000 events per alpha after a transient (plate time t < 5),
one seed each, reduced by ``examples/_seismicity_data.py`` to
``data/seis_ring_alpha1.npz`` and ``data/seis_ring_alpha2.npz`` with their
provenance (about 2 min each on one core); regenerate with
``python examples/_seismicity_data.py --regenerate seis_ring_alpha1
seis_ring_alpha2``.  Mainshocks are events with M >= 4.5 (alpha = 1) or
M >= 5 (alpha = 2); "near" means a hypocentre within 15 blocks of the
mainshock's.  With ``FAULTNET_FAST=1`` (or ``--fast``) a ring of 300 blocks
and 30,000 events is simulated instead and nothing is stored.

**What the literature reports and what faultnet finds** is printed as a table
at the end of the run and summarised in the closing section.
"""

import os
import sys

import matplotlib

matplotlib.use(os.environ.get("MPLBACKEND", "Agg"))
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _seismicity_data as S  # noqa: E402
from _paper_data import Table, fast_mode, header, save_figure  # noqa: E402

from faultnet import seismicity_plots as sp  # noqa: E402

FAST = fast_mode()
header(
    "Statistical seismology of the ring, alpha = 1 and 2 (k = 16, sigma = 0.01)",
    FAST,
    ["initial state x uniform in [0, 0.01), plate at u = 0; transient discarded"],
)

# %%
# Load (or, in fast mode, compute) the two reduced catalogs
runs = {}
for alpha in (1, 2):
    name = f"seis_ring_alpha{alpha}"
    result, prov = S.seismicity_data(name, FAST)
    runs[alpha] = result
    print(S.describe(name, result, prov))

# %%
# Six panels: P(M), waiting times, recurrence, stacked rate near the
# hypocentre, distance profile before the mainshock, b around mainshocks
fig, axes = plt.subplots(2, 3, figsize=(15, 8.5))
colors = {1: "C0", 2: "C3"}
for alpha, r in runs.items():
    c = colors[alpha]
    edges = np.asarray(r["M_edges"])
    counts = np.asarray(r["M_counts"], dtype=float)
    dens = counts / (counts.sum() * np.diff(edges))
    axes[0, 0].semilogy(
        0.5 * (edges[:-1] + edges[1:]),
        np.where(counts > 0, dens, np.nan),
        ".-",
        color=c,
        label=f"alpha = {alpha}",
    )
    axes[0, 0].axvline(r["m_main"], color=c, ls=":", lw=1)
    th = r["theta_thresholds"]
    for i, ls in ((0, "-"), (len(th) - 1, "--")):
        lab = "all events" if np.isinf(th[i]) else f"M >= {th[i]:g}"
        sp.plot_interevent_times(
            (r["theta_edges"], r["theta_counts"][i]),
            ax=axes[0, 1],
            poisson=(alpha == 1 and i == 0),
            color=c,
            ls=ls,
            label=f"alpha = {alpha}, {lab}",
        )
    for key, ls in (("rec_global", "-"), ("rec_local", "--")):
        x = np.asarray(r[key])
        if x.size > 2:
            bins = np.linspace(0, 4, 33)
            axes[0, 2].hist(
                x / x.mean(),
                bins=bins,
                density=True,
                histtype="step",
                color=c,
                ls=ls,
                label=f"alpha = {alpha}, {key[4:]}: CV = {x.std(ddof=1) / x.mean():.2f}",
            )
    sp.plot_stack(
        S.stack_table(r, "stack_near"),
        ax=axes[1, 0],
        color=c,
        label=f"alpha = {alpha}, near (r <= {r['radius']:g})",
    )
    for m_min, ls in ((None, "-"), (-2.0, "--")):
        lab = "all events" if m_min is None else f"M >= {m_min:g}"
        sp.plot_distance_profile(
            S.profile_table(r, window=0.03, m_min=m_min),
            ax=axes[1, 1],
            color=c,
            ls=ls,
            label=f"alpha = {alpha}, {lab}",
        )
    b = np.asarray(r["b_around"], dtype=float)
    axes[1, 2].errorbar(
        [0 + 0.1 * alpha, 1 + 0.1 * alpha, 2 + 0.1 * alpha],
        b[[0, 2, 1], 0],
        yerr=b[[0, 2, 1], 1],
        fmt="o",
        color=c,
        capsize=3,
        label=f"alpha = {alpha}",
    )
axes[0, 0].set(xlabel="M = ln S", ylabel="P(M)", title="(a) magnitudes; dotted: mainshock M")
axes[0, 1].set_title("(b) rescaled waiting times")
axes[0, 1].set_ylim(1e-4, None)
axes[0, 2].set(
    xlabel="interval / mean",
    ylabel="density",
    title="(c) mainshock recurrence: system-wide / at a block",
)
axes[1, 0].set_title("(d) stacked rate near the hypocentre")
axes[1, 1].set_title("(e) activity in the 0.03 before, by distance")
axes[1, 1].set_yscale("log")
axes[1, 2].set_xticks([0.15, 1.15, 2.15], ["before", "whole catalog", "after"])
axes[1, 2].set(ylabel="b (MLE, M >= -4)", title="(f) b near mainshocks (window 0.3)")
for ax in axes.flat:
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)
fig.tight_layout()
save_figure(fig, "seismicity_ring")

# %%
# The table: literature (qualitative) against faultnet's numbers
table = Table("Ring N = 2000, k = 16, sigma = 0.01", FAST)
for alpha, r in runs.items():
    a = f"alpha={alpha}: "
    cv = r["theta_cv"]
    table.add(a + "CV of waiting times, all events", "~1 or above (Hasumi)", cv[0])
    table.add(a + "CV of waiting times, M >= 2", "-> 1 (Poisson)", cv[2])
    g, loc = r["rec_global_cv"], r["rec_local_cv"]
    table.add(a + "CV of mainshock intervals, system-wide", "broad", f"{g[0]:.3f} +/- {g[1]:.3f}")
    table.add(
        a + "CV of large-slip intervals at a block",
        "< 1 (quasi-periodic)",
        f"{loc[0]:.3f} +/- {loc[1]:.3f}",
        f"{np.asarray(r['rec_local']).size} intervals",
    )
    near = S.stack_table(r, "stack_near")
    rel = near["rate"] / near.attrs["background"]
    before_far = rel[(near["t_hi"] <= -0.1)].mean()
    before_close = rel[(near["t_lo"] >= -0.02) & (near["t_hi"] <= 0)].mean()
    after_close = rel[(near["t_lo"] >= 0) & (near["t_hi"] <= 0.02)].mean()
    table.add(a + "near rate / background, 0.3..0.1 before", "rises toward", before_far)
    table.add(a + "near rate / background, last 0.02 before", "the mainshock", before_close)
    table.add(a + "near rate / background, first 0.02 after", "few aftershocks", after_close)
    table.add(
        a + "Omori-Utsu fit after (near, 0..0.1)", "no Omori law", S.omori_text(r["omori_after"])
    )
    table.add(
        a + "inverse Omori fit before (near, 0.1..0)",
        "rising activity",
        S.omori_text(r["omori_before"]),
    )
    prof = S.profile_table(r, window=0.003, m_min=-2.0)
    table.add(
        a + "activity ratio r < 3.5, 0.003 before, M >= -2",
        "< 1 (doughnut)",
        f"{prof['count'][:2].sum() / prof['expected'][:2].sum():.2f}",
        f"{int(prof['count'][:2].sum())} events",
    )
    prof = S.profile_table(r, window=0.03, m_min=None)
    table.add(
        a + "activity ratio r < 1.5, 0.03 before, all events",
        "< 1 (doughnut)",
        prof["ratio"].iloc[0],
    )
    b = np.asarray(r["b_around"], dtype=float)
    table.add(a + "b before mainshocks (near)", "changes", S.b_text(b[0]))
    table.add(a + "b after mainshocks (near)", "(2D: +/-)", S.b_text(b[1]))
    table.add(a + "b whole catalog (M >= -4)", "paper: 0.45 (a=1)", S.b_text(b[2]))
cmp_ = np.asarray(runs[1]["compare_b"], dtype=float)
WHO = ("faultnet fit_b_mle: b", "SeismoStats b_value(Mw)/1.5", "powerlaw alpha-1")
for i, who in enumerate(WHO):
    table.add(
        f"alpha=1, three-way b: {who}",
        "agree",
        f"{cmp_[i, 2]:.4f} +/- {cmp_[i, 3]:.4f}",
        f"native {cmp_[i, 0]:.4f} +/- {cmp_[i, 1]:.4f}",
    )
table.print()

# %%
# What this shows
# ---------------
#
# The numbers quoted here are those of the stored paper-scale runs (the table
# above prints them from the data; fast mode prints its own).
#
# * **Waiting times.**  With every event counted the rescaled waiting times
#   are nearly exponential with an excess of short waits (CV 1.06 at
#   alpha = 1, 1.10 at alpha = 2).  Above a magnitude threshold the CV falls
#   slightly *below* 1 (0.93-0.97): large events repel each other a little
#   instead of clustering.  Hasumi reports power-law-like waiting-time
#   distributions for small thresholds in the 2D model that turn exponential
#   as the threshold rises; on the ring the small-threshold distribution is
#   already close to exponential.
# * **Recurrence.**  System-wide, mainshock intervals are broad (CV ~0.9).
#   At a fixed block the intervals between large slips are far more regular
#   (CV ~0.4), the quasi-periodic local recurrence that Mori & Kawamura
#   describe for the 1D model.
# * **Foreshocks and aftershocks.**  Near the coming hypocentre the rate
#   climbs for ~0.3 plate-time units before the mainshock, to several times
#   the background; the inverse-Omori fit of the last 0.1 gives the rise.
#   This is the "gradual increase of smaller events" of Mori & Kawamura.
#   After the mainshock the rate near the hypocentre *drops*, most at
#   alpha = 2 (the rupture has released the stress there): there is no
#   Omori-Utsu sequence (the fitted p is <= 0, the rate grows back), in line
#   with the scarce aftershocks of velocity-weakening block-spring models
#   noted by Kawamura et al. (2012).
# * **Doughnut.**  In the 0.03 before the mainshock, counting every event,
#   activity is *concentrated* at the coming hypocentre (ratio ~7-12 at
#   r < 1.5), not suppressed: no doughnut at this scale, unlike Mori &
#   Kawamura's 1D result.  Counting only events with M >= -2 in the last
#   0.003, the few events close to the hypocentre are fewer than expected in
#   some bins, but the counts are too small to call a doughnut.
# * **b-value.**  Near the coming hypocentre, b before the mainshock differs
#   from b after it (values in the table; at alpha = 2 b is larger before,
#   i.e. relatively more small events), an apparent-b change of the kind
#   Mori & Kawamura (2008) report for the 2D model.
# * **Three tools, one b.**  faultnet's fit_b_mle, SeismoStats' estimate_b on
#   moment-like magnitudes (b_value = 1.5 b) and powerlaw's Fit on the slips
#   (alpha = 1 + b) give the same b to the printed digits: they are the same
#   maximum-likelihood estimator once the conventions are converted.
