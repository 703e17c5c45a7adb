"""Per-block and per-fault slips on disk: the side tables next to a catalog file.

A long run with ``record_slips=True`` (``faultnet simulate ... --record-slips``) writes the
per-block slips of every event next to its catalog, and a run on a network of faults (blocks
with the node attribute ``fault``) writes each event's slip per fault:

=====================  ================================  ===============================
catalog                ``run.parquet``                   events (:func:`~faultnet.read_catalog`)
per-block slips        ``run.slips.parquet``             ``event``, ``node``, ``slip``
per-fault slips        ``run.fault_slips.parquet``       ``event``, ``fault``, ``slip``
=====================  ================================  ===============================

Each side table is an ordinary Parquet file, rows ordered by event; its metadata names the
catalog's run (:data:`RUN_KEYS`), so that a side table left next to another run's catalog
is refused rather than read.  Labels come back with their type (:mod:`faultnet.io.labels`).

>>> import faultnet, tempfile, os
>>> model = faultnet.CarlsonLanger(faultnet.graphs.ring(30))
>>> out = os.path.join(tempfile.mkdtemp(), "run.parquet")
>>> _ = faultnet.simulate_to_parquet(model, 200, out, rng=5, record_slips=True, progress=False)
>>> sorted(os.listdir(os.path.dirname(out)))
['run.parquet', 'run.slips.parquet']
>>> slips = faultnet.read_slips(out)
>>> list(slips.columns)
['event', 'node', 'slip']
>>> mem = faultnet.simulate(model, 200, rng=5, record_slips=True, progress=False)
>>> slips.equals(mem.slips)
True
"""

from __future__ import annotations

import os

import pyarrow as pa
import pyarrow.parquet as pq

from faultnet.exceptions import CatalogError, InvalidParameterError
from faultnet.io.catalog_file import METADATA_KEY, decode_metadata, open_catalog_file
from faultnet.io.labels import decode_frame, label_tags

__all__ = [
    "RUN_KEYS",
    "SIDE_FORMAT",
    "SIDE_TABLES",
    "check_side_table",
    "iter_slips",
    "read_slips",
    "side_metadata",
    "side_path",
]

#: the tables a run writes besides its events, each in a file of its own next to the catalog
SIDE_TABLES = ("slips", "fault_slips")
SIDE_FORMAT = "faultnet-side-table"
#: the catalog metadata a side table repeats: the run it belongs to
RUN_KEYS = ("n_events", "first_event", "graph_hash", "seed_entropy", "seed_spawn_key", "created")
#: ``per`` of :func:`read_slips` -> side table
_PER = {"block": "slips", "fault": "fault_slips"}
_HOW = {
    "slips": "run it with record_slips=True (faultnet simulate ... --record-slips)",
    "fault_slips": "only a run on a network of faults (blocks with the node attribute "
    "'fault') writes them",
}


def side_path(out, name) -> str:
    """The file of side table ``name`` next to the catalog ``out``.

    >>> side_path("runs/ring.parquet", "slips")
    'runs/ring.slips.parquet'
    """
    out = os.fspath(out)
    stem = out[: -len(".parquet")] if out.endswith(".parquet") else out
    return f"{stem}.{name}.parquet"


def side_metadata(name, catalog_md) -> dict:
    """The metadata of side table ``name`` of the catalog whose metadata is ``catalog_md``."""
    md = {"format": SIDE_FORMAT, "table": name}
    md.update((key, catalog_md.get(key)) for key in RUN_KEYS)
    return md


def _table_file(path, per):
    if per not in _PER:
        raise InvalidParameterError(f"per must be one of {', '.join(map(repr, _PER))}; got {per!r}")
    return check_side_table(path, _PER[per])


def check_side_table(path, name):
    """``(side file, its metadata)`` of the catalog ``path``'s side table ``name``, checked
    to exist and to belong to the catalog's run (reads the footers only)."""
    path, catalog_md = open_catalog_file(path)
    side = side_path(path, name)
    if not os.path.isfile(side):
        raise CatalogError(
            f"{path} has no {name.replace('_', ' ')} next to it ({side} does not exist): "
            f"{_HOW[name]}"
        )
    try:
        raw = (pq.read_schema(side).metadata or {}).get(METADATA_KEY)
        md = decode_metadata(raw) if raw is not None else {}
    except (OSError, ValueError, pa.ArrowException) as exc:
        raise CatalogError(f"{side} is not a readable side table ({exc})") from None
    differ = [key for key in RUN_KEYS if _plain(md.get(key)) != _plain(catalog_md.get(key))]
    if md.get("format") != SIDE_FORMAT or md.get("table") != name or differ:
        raise CatalogError(
            f"{side} does not belong to the catalog {path} (it differs in "
            f"{', '.join(differ) or 'its format'}): it was left by another run; rerun "
            f"with --force to write both anew"
        )
    return side, md


def _plain(value):
    return list(value) if isinstance(value, tuple) else value


def read_slips(path, *, per="block"):
    """The slips of every event of a catalog file, from the side table next to it.

    Parameters
    ----------
    path : str or os.PathLike
        The catalog (``run.parquet``); its slips are read from ``run.slips.parquet``
        (``per="block"``) or ``run.fault_slips.parquet`` (``per="fault"``).
    per : {"block", "fault"}
        Per-block slips (columns ``event``, ``node``, ``slip``; written by a run with
        ``record_slips=True``) or each event's slip summed per fault (``event``, ``fault``,
        ``slip``; written by every run on a network of faults).

    Returns
    -------
    pandas.DataFrame
        Rows ordered by event, as ``result.slips`` or ``result.fault_slips`` of the same run
        in memory.  For files larger than memory, :func:`iter_slips` streams them.

    Raises
    ------
    CatalogError
        If the side table is missing, unreadable or belongs to another run.
    """
    side, md = _table_file(path, per)
    try:
        table = pq.read_table(side)
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(f"cannot read {side}: {exc}") from exc
    return decode_frame(table.to_pandas(), label_tags(md), side)


def iter_slips(path, *, per="block", batch_size=1_000_000):
    """Yield the slips of :func:`read_slips` as DataFrames of at most ``batch_size`` rows."""
    side, md = _table_file(path, per)
    for batch in pq.ParquetFile(side).iter_batches(batch_size=batch_size):
        yield decode_frame(pa.Table.from_batches([batch]).to_pandas(), label_tags(md), side)
