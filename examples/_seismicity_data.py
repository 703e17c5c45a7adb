"""
Stored runs of the statistical-seismology gallery pages
=======================================================

Not an example (see ``_paper_data.py``).  The pages ``plot_seismicity_*.py``
simulate a long catalog at k = 16, sigma = 0.01 and reduce it with
:mod:`faultnet.seismicity` in their function ``run_seismicity``; this module
holds the parameters of those runs (:data:`ENTRIES`, paper scale and fast
mode), stores the reductions with their provenance in ``data/seis_*.npz``
through :func:`_paper_data.load_or_run` and reads them back
(:func:`seismicity_data`).  Stored, the tables of
:func:`faultnet.seismicity.stack_mainshocks` and
:func:`faultnet.seismicity.distance_profile` become arrays (:func:`encode`);
:func:`decode` makes tables of them again, in fast mode too.  It also formats
the Omori and b cells of the pages' tables.

Recompute (the files are removed and the pages run in paper mode)::

    python examples/_seismicity_data.py --list
    python examples/_seismicity_data.py --regenerate seis_ring_alpha1
    python examples/_seismicity_data.py --regenerate          # all (~6 min, one core)
"""

from __future__ import annotations

import os
import sys

import numpy as np
from _paper_data import P_C_SQUARE, run_entry
from _paper_data import main as _main

#: distance-profile windows before the mainshock (plate time), as stored
PROFILE_WINDOWS = (0.3, 0.03, 0.003)
#: magnitude thresholds of the counted events (None: every event), as stored
PROFILE_M_MIN = (None, -2.0)
#: the stacks of a run: every event, and the events near the hypocentre
STACKS = ("stack_all", "stack_near")


def encode(result: dict) -> dict:
    """The stored form of a run: the stack tables and the distance profiles as arrays.

    ``result["profiles"]`` maps ``(metric, window, m_min)`` to a
    ``distance_profile`` table, for each metric in :data:`PROFILE_WINDOWS` x
    :data:`PROFILE_M_MIN` in that order.
    """
    out = dict(result)
    for key in STACKS:
        table = out.pop(key)
        out[f"{key}_edges"] = np.append(table["t_lo"].to_numpy(), table["t_hi"].iloc[-1])
        out[f"{key}_count"] = table["count"].to_numpy()
        out[f"{key}_exposure"] = table["exposure"].to_numpy()
        out[f"{key}_background"] = table.attrs["background"]
    profiles = out.pop("profiles")
    metrics = list(dict.fromkeys(metric for metric, _, _ in profiles))
    layout = [(m, w, m_min) for m in metrics for w in PROFILE_WINDOWS for m_min in PROFILE_M_MIN]
    if list(profiles) != layout:
        raise ValueError(f"profiles must be given in the order {layout}")
    first = profiles[layout[0]]
    out["profile_edges"] = np.append(first["r_lo"].to_numpy(), first["r_hi"].iloc[-1])
    out["profile"] = np.array(
        [np.stack([table["count"], table["expected"]]) for table in profiles.values()]
    )  # (metric, window, m_min) x (count, expected) x bins
    out["profile_metrics"] = np.array(metrics)
    return out


def decode(stored: dict) -> dict:
    """A stored run with its tables: ``"stack_all"``, ``"stack_near"`` and ``"profiles"``."""
    out = dict(stored)
    for key in STACKS:
        out[key] = stack_table(stored, key)
    metrics = [str(m) for m in np.atleast_1d(stored["profile_metrics"])]
    out["profiles"] = {
        (m, w, m_min): profile_table(stored, m, w, m_min)
        for m in metrics
        for w in PROFILE_WINDOWS
        for m_min in PROFILE_M_MIN
    }
    return out


OMORI_FIELDS = ("K", "K_err", "c", "c_err", "p", "p_err", "n")


def stack_table(result: dict, key: str):
    """The stored stack ``key`` ("stack_all" or "stack_near") as a stack_mainshocks table.

    ``rate`` is ``count / exposure`` and ``rate_err`` ``sqrt(count) / exposure``.
    """
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
    """One stored distance profile as a distance_profile table.

    ``ratio`` is ``count / expected`` and ``ratio_err`` ``sqrt(count) / expected``.
    """
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
    """Table cell of an Omori-Utsu fit stored as (K, K_err, c, c_err, p, p_err, n)."""
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
    """Table cell of a b fit stored as (b, b_err, n)."""
    b, err, n = np.asarray(row, dtype=np.float64)
    return "n/a" if not np.isfinite(b) else f"{b:.3f} +/- {err:.3f} (n = {int(n)})"


def describe(name: str, result: dict, prov: dict) -> str:
    """One line on a run: its size, transient, seed, mainshocks and where it came from."""
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


def seismicity_data(name: str, builder, fast: bool):
    """``builder(**params)`` of entry ``name``: computed in fast mode, stored/reloaded otherwise.

    ``builder`` is the page's ``run_seismicity``; the result comes back decoded
    (:func:`decode`).
    """
    return run_entry(name, builder, ENTRIES, fast, encode=encode, decode=decode)


if __name__ == "__main__":
    os.environ.setdefault("MPLBACKEND", "Agg")
    sys.exit(_main(entries=ENTRIES, description="Recompute data/seis_*.npz"))
