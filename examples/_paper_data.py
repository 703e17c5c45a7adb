"""
Shared helpers of the example gallery
=====================================

Not an example.  sphinx-gallery executes only ``plot_*.py``; to keep this
module out of the gallery pages too, set ``"ignore_pattern": r"/_"`` in
``sphinx_gallery_conf``.  It is imported by the figure scripts (their folder
is on ``sys.path`` when they run) and provides:

* run mode: :func:`fast_mode` (``FAULTNET_FAST=1`` or ``--fast``) versus the
  paper-scale default;
* output places: :func:`figures_dir` (``FAULTNET_FIGURES``, default
  ``examples/figures``) and :func:`data_dir` (``FAULTNET_DATA``, default ``data/``);
* :class:`Table`: the "quantity | paper | faultnet" tables every script prints;
* stored paper-scale results: :func:`load_or_run` keeps the output of an
  expensive ``builder(**params)`` in ``data/NAME.npz`` together with its
  provenance (faultnet version, parameters, seed, command, wall time, events,
  transient) and reloads it when the parameters match;
* the registry :data:`ENTRIES` of the magnitude-distribution runs of
  Figs. 8-10 (paper-scale and fast parameters side by side) and their builder
  :func:`run_magnitudes`.

Recompute stored histograms (about 15 minutes for all at paper scale on one core)::

    python examples/_paper_data.py --list
    python examples/_paper_data.py --regenerate fig08_ring_alpha2 fig08_ring_alpha1
    python examples/_paper_data.py --regenerate            # every entry
    FAULTNET_DATA=/tmp/x python examples/_paper_data.py --regenerate fig08_ring_alpha2
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parent

K, SIGMA = 16.0, 0.01  # the paper's spring constant and friction drop (Sects. 3-6)
P_C_SQUARE = 0.592746  # faultnet.graphs.percolation_threshold("square"); paper: 0.5927
P_C_TRIANGULAR = 0.5

#: fine magnitude grid of the stored histograms (M = ln S)
M_EDGES = np.round(np.arange(-16.0, 16.0 + 1e-9, 0.05), 10)


# --------------------------------------------------------------------------- mode and paths


def fast_mode() -> bool:
    """True for ``FAULTNET_FAST=1`` (or ``true``/``yes``) or ``--fast`` on the command line."""
    env = os.environ.get("FAULTNET_FAST", "").strip().lower()
    return env in ("1", "true", "yes", "on") or "--fast" in sys.argv[1:]


#: display bin width of P(M) (a multiple of the fine width; wider for the sparse fast runs)
DISPLAY_WIDTH = 0.5 if fast_mode() else 0.25


def mode_label(fast: bool) -> str:
    if fast:
        return "FAST mode (smoke test: small systems, short runs; numbers are NOT paper scale)"
    return "PAPER mode (paper-scale systems)"


def figures_dir() -> Path:
    path = Path(os.environ.get("FAULTNET_FIGURES") or HERE / "figures")
    path.mkdir(parents=True, exist_ok=True)
    return path


def data_dir() -> Path:
    return Path(os.environ.get("FAULTNET_DATA") or REPO / "data")


def save_figure(fig, name: str) -> Path:
    """Save ``fig`` as ``<figures_dir>/<name>.png`` and say where."""
    path = figures_dir() / f"{name}.png"
    fig.savefig(path, dpi=110)
    print(f"figure saved to {path}")
    return path


def header(title: str, fast: bool, lines=()):
    """Print the title, the mode and the run settings (initial state, transient, ...)."""
    print("=" * 78)
    print(title)
    print(mode_label(fast))
    for line in lines:
        print("  " + line)
    print("=" * 78)


# --------------------------------------------------------------------------- tables


def fmt(value, digits=4):
    """Compact number formatting for the tables (``n/a`` for None/NaN)."""
    if value is None:
        return "n/a"
    if isinstance(value, str):
        return value
    if isinstance(value, (int, np.integer)):
        return f"{int(value):d}"
    value = float(value)
    if not np.isfinite(value):
        return "n/a"
    if value != 0 and (abs(value) < 1e-2 or abs(value) >= 1e4):
        return f"{value:.{digits - 1}e}"
    return f"{value:.{digits}g}"


class Table:
    """Rows of (quantity, paper value, faultnet value, note), printed as a text table."""

    def __init__(self, title: str, fast: bool):
        self.title = title
        self.fast = fast
        self.rows: list[tuple[str, str, str, str]] = []

    def add(self, quantity, paper, faultnet, note=""):
        self.rows.append((str(quantity), fmt(paper), fmt(faultnet), str(note)))

    def print(self):
        heads = ("quantity", "paper", "faultnet", "note")
        widths = [max(len(h), *(len(r[i]) for r in self.rows)) for i, h in enumerate(heads)]
        widths[3] = len(heads[3])
        mode = "FAST mode" if self.fast else "paper mode"
        print()
        print(f"{self.title} [{mode}]")
        line = "  ".join(h.ljust(w) for h, w in zip(heads, widths, strict=True))
        print(line)
        print("-" * max(len(line), 40))
        for row in self.rows:
            print(
                "  ".join(c.ljust(w) for c, w in zip(row[:3], widths[:3], strict=True))
                + "  "
                + row[3]
            )
        print()


def fit_text(fit) -> str:
    return "n/a" if fit is None else f"{fit.b:.3f} +/- {fit.b_err:.3f}"


# --------------------------------------------------------------------------- stored results


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (np.floating,)):
        return float(value)
    return value


def _params_key(params) -> str:
    return json.dumps(_jsonable(params), sort_keys=True)


def save_result(path: Path, result: dict, provenance: dict) -> Path:
    """Write ``result`` (numpy arrays and scalars) and its provenance to ``path`` atomically."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    arrays = {key: np.asarray(val) for key, val in result.items()}
    arrays["provenance"] = np.array(json.dumps(_jsonable(provenance), sort_keys=True))
    tmp = path.with_name(path.name + ".tmp.npz")
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, path)
    return path


def load_result(path: Path) -> tuple[dict, dict]:
    """Read a file written by :func:`save_result`: ``(result, provenance)``."""
    with np.load(path, allow_pickle=False) as f:
        result = {key: f[key] for key in f.files if key != "provenance"}
        provenance = json.loads(str(f["provenance"]))
    for key, val in result.items():
        if val.ndim == 0:
            result[key] = val.item()
    return result, provenance


def _git_commit(where: Path):
    """Commit of the faultnet checkout that computes (``+dirty`` with local changes), or None."""
    import subprocess

    try:
        head = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=where, capture_output=True, text=True, check=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--", "."], cwd=where, capture_output=True, text=True
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None
    return head + ("+dirty" if dirty else "")


def load_or_run(name: str, builder, params: dict, *, store: bool = True, verbose: bool = True):
    """Reload ``<data_dir>/<name>.npz`` if it holds ``builder(**params)``, else compute it.

    The file is used only when its recorded builder name and parameters equal
    ``builder.__name__`` and ``params``; otherwise (or when it is missing) the
    builder runs and, with ``store=True``, the file is (re)written with its
    provenance: faultnet version, parameters, command line, wall time, date,
    Python/numpy/numba versions, plus whatever the builder reports (events,
    transient, seed).

    Returns
    -------
    result : dict
        The builder's output (numpy arrays and Python scalars).
    provenance : dict
        With ``"source"``: ``"loaded <path>"`` or ``"computed"``.
    """
    path = data_dir() / f"{name}.npz"
    key = _params_key(params)
    if path.exists():
        try:
            result, prov = load_result(path)
        except (OSError, ValueError, KeyError) as exc:
            print(f"[{name}] could not read {path} ({exc}); recomputing")
        else:
            if prov.get("builder") == builder.__name__ and _params_key(prov.get("params")) == key:
                prov["source"] = f"loaded {path}"
                if verbose:
                    print(
                        f"[{name}] loaded stored result {path} "
                        f"(computed {prov.get('date')}, faultnet {prov.get('faultnet_version')}, "
                        f"wall {prov.get('wall_time_s', float('nan')):.0f} s)"
                    )
                return result, prov
            print(f"[{name}] {path} holds other parameters; recomputing")
    if verbose:
        print(f"[{name}] computing {builder.__name__}({key}) ...", flush=True)
    import faultnet

    t0 = time.perf_counter()
    result = builder(**params)
    wall = time.perf_counter() - t0
    prov = {
        "name": name,
        "builder": builder.__name__,
        "params": params,
        "faultnet_version": faultnet.__version__,
        "git_commit": _git_commit(Path(faultnet.__file__).parent),
        "command": " ".join([Path(sys.executable).name, *sys.argv]),
        "wall_time_s": wall,
        "date": time.strftime("%Y-%m-%d %H:%M:%S %z"),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "platform": platform.platform(),
    }
    try:
        import numba

        prov["numba"] = numba.__version__
    except ImportError:  # pragma: no cover
        pass
    for field in ("n_events", "n_transient_events", "transient_t", "seed", "t_start", "t_end"):
        if field in result:
            prov[field] = result[field]
    if store:
        save_result(path, result, prov)
        if verbose:
            print(f"[{name}] stored {path} ({wall:.1f} s)")
    prov["source"] = "computed"
    return result, prov


# --------------------------------------------------------------------------- irregularity runs


def run_with_irregularity(model, t_end, seed, keep_profiles=None, chunk=2000):
    """Run until plate time ``t_end``; the irregularity Delta (Eq. 13) after every event.

    Profiles are recorded chunk by chunk and reduced to Delta
    (``faultnet.stats.irregularity``) so that long runs on large rings stay
    small in memory; the profiles of events with ``t`` inside ``keep_profiles``
    = (t0, t1) are kept.  Initial state: x uniform in [0, 0.01) drawn by
    ``numpy.random.default_rng(seed)``, plate at u = 0.

    Returns
    -------
    events : pandas.DataFrame
        ``result.events`` plus ``Delta`` (after the event) and ``Delta_before``.
    profiles : numpy.ndarray or None
        Rows of the kept events (same order as ``events[kept]``).
    kept : numpy.ndarray of bool
    """
    import pandas as pd

    import faultnet

    parts, profs = [], []
    state = np.random.default_rng(seed).uniform(0.0, 0.01, model.n)
    delta_prev = faultnet.irregularity(state, model)
    while True:
        res = faultnet.simulate(model, chunk, x0=state, progress=False, record_profiles=True)
        state = res.state
        ev = res.events.copy()
        delta = faultnet.irregularity(res)
        ev["Delta"] = delta
        ev["Delta_before"] = np.concatenate([[delta_prev], delta[:-1]])
        delta_prev = float(delta[-1])
        if keep_profiles is not None:
            inside = (ev["t"] >= keep_profiles[0]) & (ev["t"] <= keep_profiles[1])
            profs.append(res.profiles[inside.to_numpy()])
        parts.append(ev)
        if ev["t"].iloc[-1] >= t_end:
            break
    events = pd.concat(parts, ignore_index=True)
    events = events[events["t"] <= t_end].reset_index(drop=True)
    kept = None
    profiles = None
    if keep_profiles is not None:
        kept = ((events["t"] >= keep_profiles[0]) & (events["t"] <= keep_profiles[1])).to_numpy()
        profiles = np.concatenate(profs)[: int(kept.sum())]
    return events, profiles, kept


def delta_summary(events, s_large):
    """How Delta changes in small (S <= s_large) and large (S > s_large) events.

    Returns a dict: counts, mean change of Delta per small / large event, the
    fraction of small events that lower Delta and of large events that raise
    it, and the mean Delta just before a large event relative to the mean
    Delta before all events (< 1: large slips start on flatter profiles).
    """
    change = (events["Delta"] - events["Delta_before"]).to_numpy()
    large = (events["S"] > s_large).to_numpy()
    before = events["Delta_before"].to_numpy()
    after = events["Delta"].to_numpy()
    idx = np.flatnonzero(large)
    # net change over each run of small slips between two large slips
    phases = np.array(
        [before[j] - after[i] for i, j in zip(idx[:-1], idx[1:], strict=True) if j > i + 1]
    )
    return {
        "n_phases": int(phases.size),
        "frac_phases_lower": float((phases < 0).mean()) if phases.size else float("nan"),
        "mean_phase_change": float(phases.mean()) if phases.size else float("nan"),
        "n_small": int((~large).sum()),
        "n_large": int(large.sum()),
        "mean_change_small": float(change[~large].mean()) if (~large).any() else float("nan"),
        "mean_change_large": float(change[large].mean()) if large.any() else float("nan"),
        "frac_small_lower": float((change[~large] < 0).mean()) if (~large).any() else float("nan"),
        "frac_large_raise": float((change[large] > 0).mean()) if large.any() else float("nan"),
        "before_large_rel": float(before[large].mean() / before.mean())
        if large.any()
        else float("nan"),
    }


def add_delta_rows(table, summary, s_large, where=""):
    """The Delta rows shared by Figs. 6 and 7."""
    table.add(
        f"{where}mean change of Delta per small slip (S <= {s_large:g})",
        "< 0 (decreases)",
        f"{summary['mean_change_small']:+.3e}",
        f"{summary['frac_small_lower']:.0%} of {summary['n_small']} small slips lower it",
    )
    table.add(
        f"{where}net change of Delta between large slips",
        "< 0 (decreases)",
        f"{summary['mean_phase_change']:+.3e}",
        f"{summary['frac_phases_lower']:.0%} of {summary['n_phases']} phases end lower",
    )
    table.add(
        f"{where}mean change of Delta per large slip (S > {s_large:g})",
        "> 0 (jumps up)",
        f"{summary['mean_change_large']:+.3e}",
        f"{summary['frac_large_raise']:.0%} of {summary['n_large']} large slips raise it",
    )
    table.add(
        f"{where}Delta before large slips / mean Delta",
        "< 1 (flatter profile)",
        f"{summary['before_large_rel']:.3f}",
    )


# --------------------------------------------------------------------------- magnitude runs


def build_graph(spec: dict):
    """A graph from a JSON-able description (ring, square, triangular, percolation)."""
    import faultnet.graphs.builders as G

    kind = spec["kind"]
    if kind == "ring":
        return G.ring(spec["n"])
    if kind == "square":
        return G.square_lattice(spec["rows"], spec["cols"], periodic=spec.get("periodic", False))
    if kind == "triangular":
        return G.triangular_lattice(
            spec["rows"], spec["cols"], periodic=spec.get("periodic", False)
        )
    if kind == "percolation":
        parent = build_graph({**spec, "kind": spec["lattice"]})
        return G.site_percolation(
            parent,
            spec["p"],
            rng=spec["seed"],
            keep=spec["keep"],
            prune_isolated=spec.get("prune_isolated", False),
        )
    raise ValueError(f"unknown graph kind {kind!r}")


def graph_text(spec: dict) -> str:
    kind = spec["kind"]
    if kind == "ring":
        return f"ring N = {spec['n']} (periodic)"
    if kind in ("square", "triangular"):
        bc = "periodic" if spec.get("periodic") else "open"
        return f"{kind} lattice {spec['rows']}x{spec['cols']}, {bc} boundaries"
    what = {"largest": "largest cluster", "all": "all clusters"}[spec["keep"]]
    if spec.get("prune_isolated"):
        what += ", isolated blocks removed"
    return (
        f"site percolation p = {spec['p']:.4g} on a {spec['rows']}x{spec['cols']} open "
        f"{spec['lattice']} lattice ({what}; occupation seed {spec['seed']})"
    )


def run_magnitudes(graph, alpha, n_events, transient_t, seed, k=K, sigma=SIGMA, progress=None):
    """Magnitude histogram of a long run (the builder of the Fig. 8-10 entries).

    Initial state: x uniform in [0, 0.01) drawn with ``seed``, plate at u = 0.
    Transient: chunks of events (``n_events // 200``, at least 500, at most
    20000) are run and discarded until the plate position (time) reaches
    ``transient_t``; then ``n_events`` events are recorded.  Returns the
    histogram of M = ln S on :data:`M_EDGES` (counts outside go to
    ``underflow``/``overflow``) and summary numbers.
    """
    import networkx as nx

    import faultnet

    g = build_graph(graph)
    model = faultnet.CarlsonLanger(g, k=k, sigma=sigma, alpha=alpha)
    chunk = int(min(20_000, max(500, n_events // 200)))
    state = None
    n_trans = 0
    t_now = 0.0
    while t_now < transient_t:
        res = faultnet.simulate(model, chunk, x0=state, rng=seed, progress=False)
        state = res.state
        n_trans += len(res.events)
        t_now = float(res.events["t"].iloc[-1])
    res = faultnet.simulate(model, int(n_events), x0=state, rng=seed, progress=progress)
    ev = res.events
    M = ev["M"].to_numpy()
    counts, _ = np.histogram(M, bins=M_EDGES)
    t = ev["t"].to_numpy()
    span = float(t[-1] - t[0])
    n_isolated = sum(1 for v in g if g.degree(v) == 0)
    return {
        "M_edges": M_EDGES,
        "counts": counts.astype(np.int64),
        "underflow": int(np.sum(M < M_EDGES[0])),
        "overflow": int(np.sum(M >= M_EDGES[-1])),
        "n_events": int(len(ev)),
        "n_transient_events": int(n_trans),
        "transient_t": float(transient_t),
        "t_start": float(t[0]),
        "t_end": float(t[-1]),
        "slip_rate": float(ev["S"].sum() / (model.n * span)) if span > 0 else float("nan"),
        "M_max": float(M.max()),
        "M_mean": float(M.mean()),
        "largest_event_blocks": int(ev["n_blocks"].max()),
        "n_blocks": int(model.n),
        "n_springs": int(g.number_of_edges()),
        "n_clusters": int(nx.number_connected_components(g)),
        "n_isolated": int(n_isolated),
        "seed": int(seed),
        "alpha": float(alpha),
        "sim_wall_time_s": float(res.metadata["wall_time_s"]),
    }


def samples_from_hist(result: dict) -> np.ndarray:
    """Bin-centre pseudo-magnitudes reproducing the fine histogram (for the library fits).

    The fit windows of the scripts are unions of fine bins, so least-squares
    fits on them are exact; Aki's MLE is exact to O(bin width^2) = 0.0025.
    """
    edges = np.asarray(result["M_edges"], dtype=np.float64)
    centres = 0.5 * (edges[:-1] + edges[1:])
    return np.repeat(centres, np.asarray(result["counts"], dtype=np.int64))


def magnitude_table(result: dict, width: float = DISPLAY_WIDTH):
    """P(M) table (columns M, density, count, width) from a stored fine histogram."""
    import pandas as pd

    edges = np.asarray(result["M_edges"], dtype=np.float64)
    counts = np.asarray(result["counts"], dtype=np.int64)
    step = max(1, int(round(width / (edges[1] - edges[0]))))
    n_coarse = len(counts) // step
    c = counts[: n_coarse * step].reshape(n_coarse, step).sum(axis=1)
    e = edges[: n_coarse * step + 1 : step]
    total = counts.sum() + result.get("underflow", 0) + result.get("overflow", 0)
    w = np.diff(e)
    table = pd.DataFrame(
        {"M": 0.5 * (e[:-1] + e[1:]), "density": c / (total * w), "count": c, "width": w}
    )
    table.attrs["n"] = int(total)
    return table


def fits(result: dict, window, mle_min=None, bins=20):
    """(lsq, mle) b fits of a stored histogram; None where the data do not allow a fit."""
    import faultnet

    M = samples_from_hist(result)
    try:
        lsq = faultnet.fit_b_lsq(M, window[0], window[1], bins=bins)
    except ValueError:
        lsq = None
    try:
        mle = faultnet.fit_b_mle(M, m_min=window[0] if mle_min is None else mle_min)
    except ValueError:
        mle = None
    return lsq, mle


def hump(result: dict, lo: float, hi: float, width: float = DISPLAY_WIDTH):
    """Magnitude of the highest local maximum of P(M) inside [lo, hi] (a hump or peak).

    P(M) is smoothed over three bins (bin-to-bin noise would otherwise make
    spurious maxima); a local maximum is a bin at least as high as both
    neighbours.  NaN when P(M) has no interior maximum in the window (it only
    rises or falls there).
    """
    table = magnitude_table(result, width)
    inside = table[(table["M"] >= lo) & (table["M"] <= hi) & (table["count"] > 0)]
    if len(inside) < 5:
        return float("nan")
    d = np.convolve(inside["density"].to_numpy(), np.ones(3) / 3.0, mode="same")
    k = np.arange(2, len(d) - 2)  # the end bins of the smoothed curve are one-sided
    peaks = k[(d[k] >= d[k - 1]) & (d[k] >= d[k + 1])]
    if peaks.size == 0:
        return float("nan")
    best = peaks[np.argmax(d[peaks])]
    return float(inside["M"].iloc[best])


def add_peak_row(table, quantity, paper_value, result, lo, hi, note=""):
    """A table row with the position of the P(M) maximum inside [lo, hi]."""
    value = hump(result, lo, hi)
    if not np.isfinite(value):
        note = f"no interior maximum of P(M) in [{lo:g}, {hi:g}]"
    table.add(quantity, paper_value, value, note)


def tail_end(result: dict, q: float = 0.999) -> float:
    """Magnitude below which a fraction q of the events lie (where P(M) has decayed)."""
    edges = np.asarray(result["M_edges"], dtype=np.float64)
    cum = np.cumsum(result["counts"]) / max(1, np.sum(result["counts"]))
    return float(edges[1:][np.searchsorted(cum, q)])


def describe_run(name: str, result: dict, prov: dict) -> str:
    return (
        f"{name}: alpha = {result['alpha']:g}, {result['n_blocks']} blocks, "
        f"{result['n_events']} events recorded after discarding "
        f"{result['n_transient_events']} transient events (plate time < "
        f"{result['transient_t']:g}; recorded t = {result['t_start']:.3g}..{result['t_end']:.3g}, "
        f"mean slip rate {result['slip_rate']:.3f} per block per unit time), "
        f"seed {result['seed']}, {prov['source']}"
    )


def _ring(n):
    return {"kind": "ring", "n": n}


def _square(n, periodic=True):
    return {"kind": "square", "rows": n, "cols": n, "periodic": periodic}


def _perc(lattice, n, p, keep, prune=False, seed=2013):
    return {
        "kind": "percolation",
        "lattice": lattice,
        "rows": n,
        "cols": n,
        "periodic": False,
        "p": p,
        "keep": keep,
        "prune_isolated": prune,
        "seed": seed,
    }


def _entry(graph, alpha, n_events, transient_t, seed, fast_graph, fast_events, fast_transient):
    paper = {
        "graph": graph,
        "alpha": alpha,
        "n_events": n_events,
        "transient_t": transient_t,
        "seed": seed,
    }
    fast = {
        "graph": fast_graph,
        "alpha": alpha,
        "n_events": fast_events,
        "transient_t": fast_transient,
        "seed": seed,
    }
    return {"paper": paper, "fast": fast}


#: Magnitude-distribution runs of Figs. 8-10: name -> {"paper": params, "fast": params}.
#: Paper scale: 10^6 events after the transient (plate time t < 5 on the ring,
#: t < 2 on lattices).  Fast: tiny systems, a few thousand events (fewer at
#: alpha = 0.25, whose many-block events are the most expensive).
ENTRIES: dict[str, dict] = {}


def _fast_events(alpha, n=3000):
    return n // 2 if alpha < 0.5 else n


for _a in (2.0, 1.0, 0.25):
    ENTRIES[f"fig08_ring_alpha{_a:g}"] = _entry(
        _ring(2000), _a, 1_000_000, 5.0, 1, _ring(300), _fast_events(_a, 8000), 1.5
    )
for _a in (2.0, 1.0, 0.25):
    ENTRIES[f"fig08_square_alpha{_a:g}"] = _entry(
        _square(150), _a, 1_000_000, 2.0, 1, _square(14), _fast_events(_a), 1.1
    )
ENTRIES["fig08_square_open_alpha1"] = _entry(
    _square(150, periodic=False), 1.0, 1_000_000, 2.0, 1, _square(14, periodic=False), 3000, 1.1
)
for _a in (2.0, 0.9, 0.25):
    ENTRIES[f"fig09b_largest_alpha{_a:g}"] = _entry(
        _perc("square", 150, P_C_SQUARE, "largest"),
        _a,
        1_000_000,
        2.0,
        1,
        _perc("square", 40, P_C_SQUARE, "largest"),
        _fast_events(_a),
        1.1,
    )
for _a in (2.0, 1.0, 0.25):
    ENTRIES[f"fig09c_all_alpha{_a:g}"] = _entry(
        _perc("square", 150, P_C_SQUARE, "all"),
        _a,
        1_000_000,
        2.0,
        1,
        _perc("square", 40, P_C_SQUARE, "all"),
        _fast_events(_a),
        1.1,
    )
for _p, _tag in ((P_C_SQUARE, "pc"), (0.5, "0.5"), (0.4, "0.4")):
    ENTRIES[f"fig09d_pruned_p{_tag}"] = _entry(
        _perc("square", 150, _p, "all", prune=True),
        1.0,
        1_000_000,
        2.0,
        1,
        _perc("square", 40, _p, "all", prune=True),
        3000,
        1.1,
    )
for _a in (2.0, 1.0, 0.25):
    ENTRIES[f"fig10b_triangular_alpha{_a:g}"] = _entry(
        _perc("triangular", 150, P_C_TRIANGULAR, "largest"),
        _a,
        1_000_000,
        2.0,
        1,
        _perc("triangular", 40, P_C_TRIANGULAR, "largest"),
        _fast_events(_a),
        1.1,
    )


def magnitudes(name: str, fast: bool, store: bool = True):
    """The histogram of entry ``name``: computed in fast mode, stored/reloaded in paper mode."""
    if fast:
        params = ENTRIES[name]["fast"]
        t0 = time.perf_counter()
        result = run_magnitudes(**params, progress=False)
        prov = {"source": f"computed (fast, {time.perf_counter() - t0:.1f} s)", "params": params}
        return result, prov
    return load_or_run(name, run_magnitudes, ENTRIES[name]["paper"], store=store)


# --------------------------------------------------------------------------- command line


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Recompute the stored paper-scale histograms of Figs. 8-10 (data/*.npz)."
    )
    parser.add_argument(
        "--regenerate",
        nargs="*",
        metavar="NAME",
        help="recompute these entries (all when no name is given) and store them",
    )
    parser.add_argument("--list", action="store_true", help="list the entries and their status")
    parser.add_argument("--data-dir", help="where to store (default $FAULTNET_DATA or data/)")
    args = parser.parse_args(argv)
    if args.data_dir:
        os.environ["FAULTNET_DATA"] = args.data_dir
    if args.list or args.regenerate is None:
        for name, entry in ENTRIES.items():
            path = data_dir() / f"{name}.npz"
            p = entry["paper"]
            status = "stored" if path.exists() else "missing"
            print(
                f"{name:30s} {status:8s} alpha={p['alpha']:<5g} {p['n_events']} events, "
                f"transient t<{p['transient_t']:g}: {graph_text(p['graph'])}"
            )
        return 0
    names = args.regenerate or list(ENTRIES)
    unknown = [n for n in names if n not in ENTRIES]
    if unknown:
        parser.error(f"unknown entries {unknown}; see --list")
    for name in names:
        path = data_dir() / f"{name}.npz"
        if path.exists():
            path.unlink()  # force a fresh run
        result, prov = load_or_run(name, run_magnitudes, ENTRIES[name]["paper"])
        print(describe_run(name, result, prov))
    return 0


if __name__ == "__main__":
    sys.exit(main())
