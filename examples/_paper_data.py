"""
Shared plumbing of the example gallery
======================================

Not an example.  sphinx-gallery executes only ``plot_*.py``; to keep this
module out of the gallery pages too, set ``"ignore_pattern": r"/_"`` in
``sphinx_gallery_conf``.  It is imported by the figure scripts (their folder
is on ``sys.path`` when they run) and holds what is not faultnet itself:

* run mode: :func:`fast_mode` (``FAULTNET_FAST=1`` or ``--fast``) versus the
  paper-scale default;
* output places: :func:`figures_dir` (``FAULTNET_FIGURES``, default
  ``examples/figures``) and :func:`data_dir` (``FAULTNET_DATA``, default ``data/``);
* :class:`Table`: the "quantity | paper | faultnet" tables every script prints;
* stored paper-scale results: :func:`load_or_run` keeps the output of an
  expensive ``builder(**params)`` (a function of the page that calls it) in
  ``data/NAME.npz`` together with its provenance (faultnet version,
  parameters, seed, command, wall time, events, transient) and reloads it when
  the parameters match;
* the parameters :data:`ENTRIES` of the magnitude-distribution runs of
  Figs. 8-10 (paper-scale and fast side by side) and :func:`magnitudes`, which
  runs or reloads one of them with the page's builder.  The magnitudes are
  stored as a histogram on the grid :data:`M_EDGES` (bins of 0.05) and handed
  back as the bin centres, in fast mode too.

Recompute stored histograms (about 15 minutes for all at paper scale on one
core): the files are removed and the pages that make them run in paper mode::

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
import runpy
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parent

P_C_SQUARE = 0.592746  # faultnet.graphs.percolation_threshold("square"); paper: 0.5927
P_C_TRIANGULAR = 0.5

#: fine magnitude grid of the stored histograms (M = ln S)
M_EDGES = np.round(np.arange(-16.0, 16.0 + 1e-9, 0.05), 10)


# --------------------------------------------------------------------------- mode and paths


def fast_mode() -> bool:
    """True for ``FAULTNET_FAST=1`` (or ``true``/``yes``) or ``--fast`` on the command line."""
    env = os.environ.get("FAULTNET_FAST", "").strip().lower()
    return env in ("1", "true", "yes", "on") or "--fast" in sys.argv[1:]


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
    """Save ``fig`` as ``<figures_dir>/<name>.png`` and print the file's name."""
    path = figures_dir() / f"{name}.png"
    fig.savefig(path, dpi=110)
    print(f"figure saved as {path.name}")
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


def _command() -> str:
    """The running command line; absolute paths relative to the checkout (else their name)."""

    def short(arg):
        path = Path(arg)
        if not path.is_absolute():
            return arg
        try:
            return str(path.relative_to(REPO))
        except ValueError:
            return path.name

    return " ".join([Path(sys.executable).name, *map(short, sys.argv)])


def load_or_run(
    name: str,
    builder,
    params: dict,
    *,
    store: bool = True,
    verbose: bool = True,
    encode=None,
    decode=None,
):
    """Reload ``<data_dir>/<name>.npz`` if it holds ``builder(**params)``, else compute it.

    The file is used only when its recorded builder name and parameters equal
    ``builder.__name__`` and ``params``; otherwise (or when it is missing) the
    builder runs and, with ``store=True``, the file is (re)written with its
    provenance: faultnet version, parameters, command line, wall time, date,
    Python/numpy/numba versions, plus whatever the builder reports (events,
    transient, seed).  ``encode`` turns the builder's output into the arrays
    that are stored and ``decode`` turns stored arrays back into what the page
    uses (both default to no change); a computed result is encoded and decoded
    too, so that a page sees the same numbers either way.  Messages name the
    file (``NAME.npz``), never its folder.

    Returns
    -------
    result : dict
        The decoded output (numpy arrays and Python scalars).
    provenance : dict
        With ``"source"``: ``"loaded NAME.npz"`` or ``"computed"``.
    """
    encode = encode or (lambda result: result)
    decode = decode or (lambda result: result)
    path = data_dir() / f"{name}.npz"
    key = _params_key(params)
    if path.exists():
        try:
            result, prov = load_result(path)
        except (OSError, ValueError, KeyError) as exc:
            print(f"[{name}] could not read {path.name} ({type(exc).__name__}); recomputing")
        else:
            if prov.get("builder") == builder.__name__ and _params_key(prov.get("params")) == key:
                prov["source"] = f"loaded {path.name}"
                if verbose:
                    print(
                        f"[{name}] loaded stored result {path.name} "
                        f"(computed {prov.get('date')}, faultnet {prov.get('faultnet_version')}, "
                        f"wall {prov.get('wall_time_s', float('nan')):.0f} s)"
                    )
                return decode(result), prov
            print(f"[{name}] {path.name} holds other parameters; recomputing")
    if verbose:
        print(f"[{name}] computing {builder.__name__}({key}) ...", flush=True)
    import faultnet

    t0 = time.perf_counter()
    result = encode(builder(**params))
    wall = time.perf_counter() - t0
    prov = {
        "name": name,
        "builder": builder.__name__,
        "params": params,
        "faultnet_version": faultnet.__version__,
        "git_commit": _git_commit(Path(faultnet.__file__).parent),
        "command": _command(),
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
            print(f"[{name}] stored {path.name} ({wall:.1f} s)")
    prov["source"] = "computed"
    return decode(result), prov


def run_entry(name: str, builder, entries: dict, fast: bool, *, encode=None, decode=None):
    """``builder(**params)`` of entry ``name``: computed in fast mode, stored/reloaded otherwise.

    ``entries[name]`` holds the ``"paper"`` and ``"fast"`` parameters.  Fast mode
    stores nothing; its result goes through ``encode`` and ``decode`` like a
    stored one.
    """
    if not fast:
        return load_or_run(name, builder, entries[name]["paper"], encode=encode, decode=decode)
    params = entries[name]["fast"]
    t0 = time.perf_counter()
    result = builder(**params)
    if encode is not None:
        result = encode(result)
    if decode is not None:
        result = decode(result)
    prov = {"source": f"computed (fast, {time.perf_counter() - t0:.1f} s)", "params": params}
    return result, prov


# --------------------------------------------------------------------------- magnitude runs


def encode_magnitudes(result: dict) -> dict:
    """The stored form of a magnitude run: ``result["M"]`` as a histogram on :data:`M_EDGES`.

    Magnitudes outside the grid are counted in ``underflow`` and ``overflow``.
    """
    out = dict(result)
    M = np.asarray(out.pop("M"), dtype=np.float64)
    out["M_edges"] = M_EDGES
    out["counts"] = np.histogram(M, bins=M_EDGES)[0].astype(np.int64)
    out["underflow"] = int(np.sum(M < M_EDGES[0]))
    out["overflow"] = int(np.sum(M >= M_EDGES[-1]))
    return out


def decode_magnitudes(stored: dict) -> dict:
    """A stored magnitude run with ``"M"``: the centre of each event's bin (bins of 0.05).

    Fits on windows that are unions of these bins are those of the raw
    magnitudes (least squares exactly; Aki's MLE to O(bin width^2) = 0.0025).
    """
    out = dict(stored)
    edges = np.asarray(out["M_edges"], dtype=np.float64)
    centres = 0.5 * (edges[:-1] + edges[1:])
    out["M"] = np.repeat(centres, np.asarray(out["counts"], dtype=np.int64))
    return out


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


def magnitudes(name: str, builder, fast: bool):
    """The run of entry ``name`` of :data:`ENTRIES`: ``builder(**params)``.

    ``builder`` is the page's function of ``graph`` (a description such as
    ``{"kind": "ring", "n": 2000}``), ``alpha``, ``n_events``, ``transient_t``
    and ``seed`` that returns the magnitudes ``"M"`` and the run's summary
    numbers.  Fast mode computes it; paper mode reloads ``data/NAME.npz``
    (computing and storing it when it is missing).  ``"M"`` comes back binned
    (:func:`decode_magnitudes`).
    """
    return run_entry(
        name, builder, ENTRIES, fast, encode=encode_magnitudes, decode=decode_magnitudes
    )


# --------------------------------------------------------------------------- command line

#: the page that computes each stored entry (by the start of the entry's name)
PAGES = {
    "fig08_": "plot_fig08_magnitude_1d_2d.py",
    "fig09": "plot_fig09_percolation.py",
    "fig10": "plot_fig10_triangular_percolation.py",
    "seis_ring_": "plot_seismicity_ring.py",
    "seis_percolation_": "plot_seismicity_percolation.py",
}


def page_of(name: str) -> Path:
    """The gallery script whose builder computes entry ``name``."""
    for start, page in PAGES.items():
        if name.startswith(start):
            return HERE / page
    raise KeyError(f"no page computes {name!r}")


def regenerate(names) -> None:
    """Remove the stored files of ``names`` and run their pages in paper mode, which
    compute and store them again (and reload the other entries they draw)."""
    for name in names:
        (data_dir() / f"{name}.npz").unlink(missing_ok=True)
    pages = list(dict.fromkeys(page_of(name) for name in names))
    os.environ.pop("FAULTNET_FAST", None)
    for page in pages:
        print(f"running {page.name} in paper mode", flush=True)
        argv = sys.argv
        sys.argv = [page.name]
        try:
            runpy.run_path(str(page), run_name="__main__")
        finally:
            sys.argv = argv


def main(argv=None, entries=None, description=None):
    """``--list`` the stored entries or ``--regenerate`` them (``entries``: default
    :data:`ENTRIES`)."""
    entries = ENTRIES if entries is None else entries
    parser = argparse.ArgumentParser(
        description=description
        or "Recompute the stored paper-scale histograms of Figs. 8-10 (data/*.npz)."
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
        for name, entry in entries.items():
            path = data_dir() / f"{name}.npz"
            p = entry["paper"]
            status = "stored" if path.exists() else "missing"
            what = graph_text(p["graph"]) if "kind" in p.get("graph", {}) else ""
            print(
                f"{name:30s} {status:8s} alpha={p['alpha']:<5g} {p['n_events']} events, "
                f"transient t<{p['transient_t']:g}: {what}"
            )
        return 0
    names = args.regenerate or list(entries)
    unknown = [n for n in names if n not in entries]
    if unknown:
        parser.error(f"unknown entries {unknown}; see --list")
    regenerate(names)
    return 0


if __name__ == "__main__":
    sys.exit(main())
