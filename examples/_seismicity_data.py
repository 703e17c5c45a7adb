"""
Stored runs of the statistical-seismology gallery pages
=======================================================

Not an example (see ``_paper_data.py``).  :func:`run_seismicity` simulates a
long catalog at k = 16, sigma = 0.01 and reduces it with
:mod:`faultnet.seismicity.timing` to the small arrays the pages draw: waiting-time
histograms, recurrence intervals (system-wide and at fixed blocks, from the
recorded slips), stacked rates around mainshocks, Omori-Utsu fits, distance
profiles from the coming hypocentre, b before/after mainshocks and in
sliding windows, and the three-way b comparison (faultnet / SeismoStats /
powerlaw).  The results and their provenance go to ``data/seis_*.npz``
through :func:`_paper_data.load_or_run`; fast mode computes a tiny version and
stores nothing.

Recompute::

    python examples/_seismicity_data.py --list
    python examples/_seismicity_data.py --regenerate seis_ring_alpha1
    python examples/_seismicity_data.py --regenerate          # all (~6 min, one core)
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
from _paper_data import P_C_SQUARE, SIGMA, K, build_graph, data_dir, load_or_run

#: rescaled waiting times theta = tau / <tau>: log-spaced bins
THETA_EDGES = np.logspace(-5, 2, 36)
#: distance-profile windows before the mainshock (plate time)
PROFILE_WINDOWS = (0.3, 0.03, 0.003)
#: magnitude thresholds of the counted events (None: every event)
PROFILE_M_MIN = (None, -2.0)
M_EDGES = np.arange(-12.0, 10.01, 0.5)


def _log_edges(window, n=9, tiny=1e-4):
    side = np.concatenate([[0.0], np.logspace(np.log10(tiny), np.log10(window), n)])
    return np.concatenate([-side[::-1], side[1:]])


def _simulate(model, n_events, transient_t, seed, sites, m_local, chunk):
    """Events after the transient, and (site, event) pairs of local large slips."""
    import pandas as pd

    import faultnet

    state, t_now, n_trans = None, 0.0, 0
    while t_now < transient_t:
        res = faultnet.simulate(model, chunk, x0=state, rng=seed, progress=False)
        state, n_trans = res.state, n_trans + len(res.events)
        t_now = float(res.events["t"].iloc[-1])
    parts, hits, done, wall = [], [], 0, 0.0
    site_set = set(sites)
    while done < n_events:
        res = faultnet.simulate(
            model, min(chunk, n_events - done), x0=state, progress=False, record_slips=True
        )
        state, done = res.state, done + len(res.events)
        wall += res.metadata["wall_time_s"]
        ev = res.events[["event", "t", "M", "n_blocks", "hypocenter"]]
        big = set(ev.loc[ev["M"] >= m_local, "event"].tolist())
        sl = res.slips
        sl = sl[sl["node"].isin(site_set) & sl["event"].isin(big)]
        hits.append(sl[["node", "event"]].to_numpy())
        parts.append(ev)
    events = pd.concat(parts, ignore_index=True)
    return events, np.concatenate(hits), n_trans, wall


def _local_intervals(events, hits):
    """Intervals between large slips at each monitored block, pooled."""
    ids = events["event"].to_numpy()
    t = events["t"].to_numpy()
    out = []
    for node in np.unique(hits[:, 0]):
        at = np.sort(t[np.searchsorted(ids, hits[hits[:, 0] == node, 1].astype(np.int64))])
        out.append(np.diff(at))
    return np.concatenate(out) if out else np.zeros(0)


def _omori_row(times, n_seq, t_end):
    from faultnet import seismicity as fs

    try:
        fit = fs.fit_omori(times, 0.0, t_end, n_sequences=max(n_seq, 1))
    except Exception as exc:  # too few events: recorded, shown as n/a
        print(f"  Omori fit skipped: {exc}")
        return np.full(7, np.nan)
    return np.array([fit.K, fit.K_err, fit.c, fit.c_err, fit.p, fit.p_err, fit.n], float)


def run_seismicity(
    graph,
    alpha,
    n_events,
    transient_t,
    seed,
    m_main,
    radius,
    m_local,
    n_sites=20,
    stack_window=0.3,
    omori_t_end=0.1,
    m_complete=-4.0,
    b_window=2000,
    chunk=100_000,
):
    """Simulate and reduce one catalog with faultnet.seismicity.timing (module docstring)."""
    import faultnet
    from faultnet import seismicity as fs

    g = build_graph(graph)
    model = faultnet.CarlsonLanger(g, k=K, sigma=SIGMA, alpha=alpha)
    nodes = list(model.nodes)
    sites = [nodes[i] for i in np.linspace(0, len(nodes) - 1, n_sites).astype(int)]
    ev, hits, n_trans, wall = _simulate(model, n_events, transient_t, seed, sites, m_local, chunk)
    out = {
        "alpha": float(alpha),
        "seed": int(seed),
        "n_events": int(len(ev)),
        "n_transient_events": int(n_trans),
        "transient_t": float(transient_t),
        "t_start": float(ev["t"].iloc[0]),
        "t_end": float(ev["t"].iloc[-1]),
        "n_blocks": int(model.n),
        "m_main": float(m_main),
        "radius": float(radius),
        "m_local": float(m_local),
        "sim_wall_time_s": float(wall),
        "M_edges": M_EDGES,
        "M_counts": np.histogram(ev["M"], bins=M_EDGES)[0],
        "M_max": float(ev["M"].max()),
        "n_mainshocks": int((ev["M"] >= m_main).sum()),
    }
    # waiting times at four thresholds (rescaled by the mean rate) and their CV
    thresholds = np.array([-np.inf, 0.0, 2.0, m_main])
    out["theta_edges"] = THETA_EDGES
    out["theta_thresholds"] = thresholds
    counts, cvs, ns = [], [], []
    for m in thresholds:
        theta = fs.interevent_times(ev, m_min=None if np.isinf(m) else m, rescale=True)
        counts.append(np.histogram(theta, bins=THETA_EDGES)[0])
        cvs.append(theta.std(ddof=1))
        ns.append(theta.size)
    out["theta_counts"], out["theta_cv"], out["theta_n"] = np.array(counts), np.array(cvs), ns
    # recurrence of mainshocks: system-wide and at fixed blocks (rupture reached the block)
    rec = fs.recurrence(ev, m_main)
    out["rec_global"] = rec.intervals
    out["rec_global_cv"] = np.array([rec.cv, rec.cv_err])
    local = _local_intervals(ev, hits)
    out["rec_local"] = local
    if local.size > 2:
        import pandas as pd

        lr = fs.recurrence(pd.DataFrame({"t": np.cumsum(local), "M": 1.0}), 0.0)
        out["rec_local_cv"] = np.array([local.std(ddof=1) / local.mean(), lr.cv_err])
    else:
        out["rec_local_cv"] = np.array([np.nan, np.nan])
    # stacked rates: every event system-wide, and events near the hypocentre
    edges = _log_edges(stack_window)
    for key, kw in (("stack_all", {}), ("stack_near", {"graph": g, "radius": radius})):
        table = fs.stack_mainshocks(ev, m_main, stack_window, bins=edges, **kw)
        out[f"{key}_edges"] = edges
        out[f"{key}_count"] = table["count"].to_numpy()
        out[f"{key}_exposure"] = table["exposure"].to_numpy()
        out[f"{key}_background"] = table.attrs["background"]
    # Omori-Utsu after and inverse Omori before, near the hypocentre
    for side in ("after", "before"):
        times, n_seq = fs.aftershock_times(
            ev, m_main, omori_t_end, side=side, graph=g, radius=radius
        )
        out[f"omori_{side}"] = _omori_row(times, n_seq, omori_t_end)
        out[f"omori_{side}_sequences"] = n_seq
    # distance profiles before the mainshock (Euclidean through pos; hops too off the ring)
    metrics = ("euclidean",) if graph["kind"] == "ring" else ("euclidean", "graph")
    prof = []
    for metric in metrics:
        for w in PROFILE_WINDOWS:
            for m in PROFILE_M_MIN:
                table = fs.distance_profile(
                    ev, g, m_main, w, bins=_distance_edges(graph), m_min=m, metric=metric
                )
                prof.append(np.stack([table["count"], table["expected"]]))
    out["profile_edges"] = _distance_edges(graph)
    out["profile"] = np.array(prof)  # (metric, window, m_min) x (count, expected) x bins
    out["profile_metrics"] = np.array(metrics)
    # b before / after mainshocks near the hypocentre, and in sliding windows
    b = fs.b_around_mainshocks(ev, m_main, stack_window, m_complete, graph=g, radius=radius)
    out["b_around"] = np.array(
        [[f.b, f.b_err, f.n] if f is not None else [np.nan] * 3 for f in b.values()]
    )
    series = fs.b_series(ev, window=b_window, step=b_window // 2, m_min=m_complete)
    out["b_series"] = series[["t", "b", "b_err"]].to_numpy()
    try:
        table = fs.compare_b(ev, m_min=m_complete)
        out["compare_b"] = table[["value", "error", "b", "b_err", "n"]].to_numpy(float)
    except ImportError as exc:
        print(f"  three-way b skipped ({exc}); pip install 'faultnet[seismo]'")
        out["compare_b"] = np.full((3, 5), np.nan)
    return out


def _distance_edges(graph):
    base = np.array([0, 1.5, 3.5, 7.5, 15.5, 31.5, 63.5, 127.5, 255.5, 511.5])
    far = graph["n"] / 2 + 0.5 if graph["kind"] == "ring" else 2.0 * graph["rows"]
    return np.append(base[base < far - 1], far)


# --------------------------------------------------------------------------- page helpers

OMORI_FIELDS = ("K", "K_err", "c", "c_err", "p", "p_err", "n")


def stack_table(result: dict, key: str):
    """The stored stack ``key`` ("stack_all" or "stack_near") as a stack_mainshocks table."""
    import pandas as pd

    edges = np.asarray(result[f"{key}_edges"], dtype=np.float64)
    count = np.asarray(result[f"{key}_count"], dtype=np.float64)
    expo = np.asarray(result[f"{key}_exposure"], dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = np.where(expo > 0, count / expo, np.nan)
        err = np.where(expo > 0, np.sqrt(count) / expo, np.nan)
    table = pd.DataFrame(
        {"t_lo": edges[:-1], "t_hi": edges[1:], "count": count, "exposure": expo,
         "rate": rate, "rate_err": err}
    )  # fmt: skip
    table.attrs["background"] = float(result[f"{key}_background"])
    return table


def profile_table(result: dict, metric: str = "euclidean", window: float = 0.03, m_min=None):
    """One stored distance profile as a distance_profile table."""
    import pandas as pd

    metrics = [str(m) for m in np.atleast_1d(result["profile_metrics"])]
    i = metrics.index(metric) * len(PROFILE_WINDOWS) * len(PROFILE_M_MIN)
    i += PROFILE_WINDOWS.index(window) * len(PROFILE_M_MIN) + PROFILE_M_MIN.index(m_min)
    count, expected = np.asarray(result["profile"][i], dtype=np.float64)
    edges = np.asarray(result["profile_edges"], dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(expected > 0, count / expected, np.nan)
        err = np.where(expected > 0, np.sqrt(count) / expected, np.nan)
    return pd.DataFrame(
        {"r_lo": edges[:-1], "r_hi": edges[1:], "r": 0.5 * (edges[:-1] + edges[1:]),
         "count": count, "expected": expected, "ratio": ratio, "ratio_err": err}
    )  # fmt: skip


def omori_text(row) -> str:
    row = dict(zip(OMORI_FIELDS, np.asarray(row, dtype=np.float64), strict=True))
    if not np.isfinite(row["p"]):
        return "n/a (too few events)"
    at_bound = min(abs(row["p"] - 5.0), abs(row["p"] + 3.0)) < 1e-3
    bound = " (p at the search bound)" if at_bound else ""
    return (
        f"p = {row['p']:.2f} +/- {row['p_err']:.2f}, c = {row['c']:.2g} +/- {row['c_err']:.1g}"
        f" (n = {int(row['n'])}){bound}"
    )


def b_text(row) -> str:
    b, err, n = np.asarray(row, dtype=np.float64)
    return "n/a" if not np.isfinite(b) else f"{b:.3f} +/- {err:.3f} (n = {int(n)})"


def describe(name: str, result: dict, prov: dict) -> str:
    return (
        f"{name}: alpha = {result['alpha']:g}, {result['n_blocks']} blocks, "
        f"{result['n_events']:,} events after {result['n_transient_events']:,} transient ones "
        f"(plate time < {result['transient_t']:g}; recorded t = {result['t_start']:.4g}.."
        f"{result['t_end']:.4g}), seed {result['seed']}, {result['n_mainshocks']} mainshocks "
        f"M >= {result['m_main']:g}; {prov['source']}"
    )


RING = {"kind": "ring", "n": 2000}
PERC = {
    "kind": "percolation",
    "lattice": "square",
    "rows": 150,
    "cols": 150,
    "periodic": False,
    "p": P_C_SQUARE,
    "keep": "largest",
    "prune_isolated": False,
    "seed": 2013,
}

#: name -> {"paper": params, "fast": params}
ENTRIES = {
    "seis_ring_alpha1": {
        "paper": dict(graph=RING, alpha=1.0, n_events=3_000_000, transient_t=5.0, seed=1,
                      m_main=4.5, radius=15.0, m_local=4.5),
        "fast": dict(graph={"kind": "ring", "n": 300}, alpha=1.0, n_events=30_000,
                     transient_t=2.0, seed=1, m_main=3.0, radius=10.0, m_local=3.0,
                     stack_window=0.5, omori_t_end=0.2, b_window=200, chunk=10_000),
    },
    "seis_ring_alpha2": {
        "paper": dict(graph=RING, alpha=2.0, n_events=3_000_000, transient_t=5.0, seed=1,
                      m_main=5.0, radius=15.0, m_local=5.0),
        "fast": dict(graph={"kind": "ring", "n": 300}, alpha=2.0, n_events=30_000,
                     transient_t=2.0, seed=1, m_main=3.0, radius=10.0, m_local=3.0,
                     stack_window=0.5, omori_t_end=0.2, b_window=200, chunk=10_000),
    },
    "seis_percolation_alpha1": {
        "paper": dict(graph=PERC, alpha=1.0, n_events=2_000_000, transient_t=2.0, seed=1,
                      m_main=3.5, radius=5.0, m_local=3.5, m_complete=-6.0),
        "fast": dict(graph={**PERC, "rows": 40, "cols": 40}, alpha=1.0, n_events=15_000,
                     transient_t=1.0, seed=1, m_main=1.5, radius=5.0, m_local=1.5,
                     stack_window=0.5, omori_t_end=0.2, m_complete=-6.0, b_window=200,
                     chunk=10_000),
    },
}  # fmt: skip


def seismicity_data(name: str, fast: bool):
    """The reduced catalog of entry ``name``: computed in fast mode, stored/reloaded otherwise."""
    if fast:
        params = ENTRIES[name]["fast"]
        t0 = time.perf_counter()
        result = run_seismicity(**params)
        return result, {"source": f"computed (fast, {time.perf_counter() - t0:.1f} s)"}
    return load_or_run(name, run_seismicity, ENTRIES[name]["paper"])


def main(argv=None):
    parser = argparse.ArgumentParser(description="Recompute data/seis_*.npz")
    parser.add_argument("--regenerate", nargs="*", metavar="NAME")
    parser.add_argument("--list", action="store_true")
    args = parser.parse_args(argv)
    if args.list or args.regenerate is None:
        for name in ENTRIES:
            status = "stored" if (data_dir() / f"{name}.npz").exists() else "missing"
            print(f"{name:28s} {status}")
        return 0
    names = args.regenerate or list(ENTRIES)
    unknown = [n for n in names if n not in ENTRIES]
    if unknown:
        parser.error(f"unknown entries {unknown}; see --list")
    for name in names:
        path = data_dir() / f"{name}.npz"
        if path.exists():
            path.unlink()
        load_or_run(name, run_seismicity, ENTRIES[name]["paper"])
    return 0


if __name__ == "__main__":
    os.environ.setdefault("MPLBACKEND", "Agg")
    sys.exit(main())
