"""The summary table of a sweep folder (or any folder of catalogs): one row per point.

Each row holds a point's parameters, its catalog's magnitude range and b
fits (:func:`faultnet.io.summary.catalog_stats`), its speed, seed and status.
:func:`summarize` reads a folder at any time: finished points are ``done``,
running or interrupted ones ``partial a/b``, the others ``missing``.
"""

from __future__ import annotations

import json
import os

import pandas as pd

from faultnet.exceptions import CatalogError, InvalidParameterError
from faultnet.io.atomic import is_tmp_name
from faultnet.io.catalog_file import is_catalog_file, read_metadata
from faultnet.io.summary import catalog_stats
from faultnet.runs.checkpoint import checkpoint_status
from faultnet.runs.sweep.config import SweepConfig
from faultnet.runs.sweep.folder import MANIFEST, point_file_name

__all__ = ["SUMMARY_COLUMNS", "failed_row", "point_row", "summarize", "summary_table"]

_FIT_COLUMNS = [
    "M_min", "M_max", "b_mle", "b_mle_err", "m_min", "m_max", "n_fit", "b_lsq", "b_lsq_err",
]  # fmt: skip
#: the columns of the summary table; ``part`` is the point's catalog file name
SUMMARY_COLUMNS = [
    "point", "replica", "graph", "model", "n_blocks", "k", "sigma", "alpha", "nu", "eta", "dt",
    "events", "transient",
    *_FIT_COLUMNS,
    "wall_time_s", "events_per_s", "seed_entropy", "spawn_key", "status", "part",
]  # fmt: skip


def _kelvin(name, md, point, model):
    """A point's ``nu`` or ``eta``: its catalog's (which records them only where not 0), else
    its own, else 0 (None for the automaton, which has neither)."""
    if model == "ofc":
        return None
    value = md.get(name, point.get(name))
    return 0.0 if value is None else value


def _row(point, path, md, st, status):
    model = md.get("model", point.get("model") or "carlson-langer")
    row = {
        "point": point["index"],
        "replica": point["replica"],
        "graph": point["graph"],
        "model": model,
        "n_blocks": md.get("n_blocks"),
        "k": md.get("k", point["k"]),
        "sigma": md.get("sigma", point["sigma"]),
        "alpha": md.get("alpha", point["alpha"]),
        "nu": _kelvin("nu", md, point, model),
        "eta": _kelvin("eta", md, point, model),
        "dt": md.get("dt", point["dt"]),
        "events": st.get("events", 0),
        "transient": st.get("transient"),
        "wall_time_s": md.get("wall_time_s", float("nan")),
        "seed_entropy": str(point["seed_entropy"]),
        "spawn_key": tuple(point["spawn_key"]),
        "status": status,
        "part": os.path.basename(path),
    }
    for key in _FIT_COLUMNS:
        row[key] = st.get(key, float("nan"))
    wall = row["wall_time_s"]
    row["events_per_s"] = row["events"] / wall if wall and wall == wall else float("nan")
    return row


def point_row(point, path, transient, m_min, m_max, status="done"):
    """The summary row of a point whose catalog is ``path``."""
    md = read_metadata(path)
    st = catalog_stats(path, transient=transient, m_min=m_min, m_max=m_max)
    return _row(point, path, md, st, status)


def failed_row(point, path, exc):
    """The summary row of a point whose run raised ``exc``."""
    return _row(point, path, {}, {}, f"failed: {type(exc).__name__}: {exc}")


def summary_table(rows):
    """DataFrame of summary rows with :data:`SUMMARY_COLUMNS`."""
    table = pd.DataFrame(rows, columns=SUMMARY_COLUMNS)
    for col in ("point", "replica", "events"):
        table[col] = table[col].astype("int64")
    return table


def summarize(out, *, transient=None, m_min=None, m_max=None) -> pd.DataFrame:
    """Summary table of a sweep folder (or a folder of catalogs): one row per point.

    Columns: point, replica, graph, model, n_blocks, k, sigma, alpha, nu, eta, dt, events,
    transient, M_min, M_max, b_mle, b_mle_err, m_min, m_max, n_fit, b_lsq,
    b_lsq_err, wall_time_s, events_per_s, seed_entropy, spawn_key, status
    (``done``, ``missing``, ``partial a/b``, ``corrupt: ...``) and part (the
    point's catalog file).  ``transient``, ``m_min``, ``m_max`` default to the
    sweep's settings.
    """
    out = os.fspath(out)
    if not os.path.isdir(out):
        raise InvalidParameterError(f"{out} is not a folder")
    manifest = os.path.join(out, MANIFEST)
    if not os.path.isfile(manifest):
        return _summarize_catalogs(out, transient, m_min, m_max)
    conf = _read_config(manifest)
    defining = ("k", "sigma", "alpha", "dt", "events", "replicas", "seed")
    optional = ("nu", "eta", "model", "ofc_alpha")  # in sweeps that set them
    cfg = SweepConfig(
        graphs=conf["graphs"],
        **{key: conf[key] for key in defining},
        **{key: conf[key] for key in optional if key in conf},
    )
    transient = conf.get("transient", 0) if transient is None else transient
    m_min = conf.get("m_min") if m_min is None else m_min
    m_max = conf.get("m_max") if m_max is None else m_max
    points = cfg.points()
    rows = [_sweep_row(p, out, len(points), transient, m_min, m_max) for p in points]
    table = summary_table(rows)
    table.attrs["out"] = out
    return table


def _read_config(manifest):
    """The ``config`` table of a manifest; a garbled file is a CatalogError naming it."""
    try:
        with open(manifest, encoding="utf-8") as fh:
            conf = json.load(fh)["config"]
        if not isinstance(conf, dict) or not isinstance(conf.get("graphs"), list):
            raise ValueError("no sweep settings")
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise CatalogError(
            f"{manifest} is unreadable or garbled ({type(exc).__name__}: {exc}); rerun the "
            "sweep with its file and --force to rewrite it"
        ) from None
    return conf


def _sweep_row(point, out, n_points, transient, m_min, m_max):
    path = os.path.join(out, point_file_name(point["index"], n_points))
    if os.path.exists(path):
        try:
            return point_row(point, path, transient, m_min, m_max)
        except CatalogError as exc:
            return _row(point, path, {}, {}, f"corrupt: {exc}")
    st = checkpoint_status(path)
    status = f"partial {st['events_done']}/{point['events']}" if st else "missing"
    return _row(point, path, {}, {}, status)


def _catalog_point(md, index):
    """The point a catalog's metadata describes (its sweep point, else its run settings)."""
    return md.get("sweep_point") or {
        "index": index,
        "replica": 0,
        "graph": md.get("graph_spec") or md.get("graph"),
        "k": md.get("k"),
        "sigma": md.get("sigma"),
        "alpha": md.get("alpha"),
        "nu": md.get("nu"),
        "eta": md.get("eta"),
        "dt": md.get("dt"),
        "seed_entropy": md.get("seed_entropy"),
        "spawn_key": list(md.get("seed_spawn_key") or ()),
    }


def _summarize_catalogs(out, transient, m_min, m_max):
    rows = []
    names = sorted(n for n in os.listdir(out) if n.endswith(".parquet") and not is_tmp_name(n))
    for i, name in enumerate(names):
        path = os.path.join(out, name)
        if not is_catalog_file(path):
            continue  # another program's Parquet file
        try:
            md = read_metadata(path)
        except CatalogError as exc:  # garbled or truncated: say which and why
            point = _catalog_point({"graph": None}, i)
            rows.append(_row(point, path, {}, {}, f"corrupt: {exc}"))
            continue
        point = _catalog_point(md, i)
        try:
            rows.append(point_row(point, path, transient, m_min, m_max))
        except CatalogError as exc:
            rows.append(_row(point, path, md, {}, f"corrupt: {exc}"))
    if not rows:
        raise InvalidParameterError(f"{out} holds no sweep ({MANIFEST}) and no faultnet catalogs")
    table = summary_table(rows)
    table.attrs["out"] = out
    return table
