"""Reading a catalog file's footer and checking the file: metadata, columns, rows, numbering.

Every reader (:func:`~faultnet.io.parquet.read_catalog`, the statistics of
:mod:`~faultnet.io.summary`,
``faultnet info`` and ``--resume``) opens a catalog through :func:`open_catalog_file`, so a
damaged file is one :class:`~faultnet.exceptions.CatalogError` naming it: a missing file or
column, metadata that is not a JSON object or holds a count as text, a row count that differs
from ``n_events``, event numbers with gaps or duplicates.  The label columns that the metadata
names as encoded (:mod:`faultnet.io.labels`) are decoded by the readers of event rows,
:func:`~faultnet.io.parquet.read_catalog` and :func:`~faultnet.io.parquet.iter_catalog`.
"""

from __future__ import annotations

import io
import json
import os

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from faultnet.exceptions import CatalogError
from faultnet.io.labels import LABEL_TAGS, LABELS_KEY
from faultnet.model.state import State

__all__ = [
    "METADATA_KEY",
    "STATS_COLUMNS",
    "check_event_count",
    "check_event_numbers",
    "decode_metadata",
    "is_catalog_file",
    "open_catalog_file",
    "read_metadata",
    "read_state",
    "state_bytes",
    "verify_catalog",
]

#: the key of the run's metadata (JSON) in the Parquet schema metadata
METADATA_KEY = b"faultnet"
#: the key of the state after the last event (an ``.npz``), from which a run continues
STATE_KEY = b"faultnet_state"

#: metadata keys that must hold integers, and those that must hold numbers (or null)
_INT_KEYS = ("n_events", "first_event", "transient", "n_blocks", "runs", "chunk_events")
_NUMBER_KEYS = ("wall_time_s", "dt", "k", "sigma", "alpha")


#: the columns that verifying and summarising a catalog read
STATS_COLUMNS = ("event", "t", "M", "n_blocks")


def decode_metadata(raw):
    """The metadata dict of a catalog's JSON; ValueError naming what is wrong."""
    md = json.loads(raw)
    if not isinstance(md, dict):
        raise ValueError(f"it is a JSON {type(md).__name__}, not an object")
    for key in _INT_KEYS:
        if key in md and (not isinstance(md[key], int) or isinstance(md[key], bool)):
            raise ValueError(f"{key} must be an integer; got {md[key]!r}")
    for key in _NUMBER_KEYS:
        value = md.get(key)
        if value is not None and (not isinstance(value, (int, float)) or isinstance(value, bool)):
            raise ValueError(f"{key} must be a number; got {value!r}")
    tags = md.get(LABELS_KEY, {})
    if not isinstance(tags, dict) or not all(tag in LABEL_TAGS for tag in tags.values()):
        raise ValueError(
            f"{LABELS_KEY} must map label columns to one of {', '.join(LABEL_TAGS)}; got {tags!r}"
        )
    for key, value in md.items():
        if key.endswith("spawn_key") and isinstance(value, list):
            md[key] = tuple(value)
    return md


def _check_catalog_file(path):
    path = os.fspath(path)
    if os.path.isdir(path):
        raise CatalogError(f"{path} is a folder, not a catalog file")
    if not os.path.exists(path):
        raise CatalogError(f"catalog {path} does not exist")
    return path


def _file_metadata(path):
    try:
        schema = pq.read_schema(path)
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(
            f"{path} is not a readable Parquet file (truncated or corrupt?): {exc}"
        ) from exc
    if not schema.metadata or METADATA_KEY not in schema.metadata:
        raise CatalogError(f"{path} is a Parquet file without faultnet metadata")
    try:
        return schema, decode_metadata(schema.metadata[METADATA_KEY])
    except ValueError as exc:
        raise CatalogError(f"{path}: its faultnet metadata is garbled: {exc}") from None


def is_catalog_file(path) -> bool:
    """False for a readable Parquet file without faultnet metadata (another program's file);
    True for every other file, a damaged catalog included."""
    try:
        schema = pq.read_schema(path)
    except (OSError, pa.ArrowException):
        return True
    return bool(schema.metadata) and METADATA_KEY in schema.metadata


def open_catalog_file(path, columns=()):
    """``(path, metadata)`` of a catalog file, reading only its footer.

    Raises :class:`~faultnet.exceptions.CatalogError` if the file is missing,
    a folder, unreadable, carries no faultnet metadata or lacks one of ``columns``.
    """
    path = _check_catalog_file(path)
    schema, md = _file_metadata(path)
    missing = [name for name in columns if name not in schema.names]
    if missing:
        raise CatalogError(
            f"catalog {path} has no column {', '.join(map(repr, missing))} (its columns: "
            f"{', '.join(schema.names)}); was it edited? recompute it (--force)"
        )
    return path, md


def read_metadata(path) -> dict:
    """The metadata dict of a catalog file, reading only its footer."""
    return _file_metadata(_check_catalog_file(path))[1]


def check_event_count(path, md, n_rows):
    """Refuse a catalog whose row count differs from the ``n_events`` of its metadata."""
    want = md.get("n_events")
    if isinstance(want, int) and n_rows != want:
        raise CatalogError(
            f"catalog {path} holds {n_rows} events but its metadata says {want}: it is "
            "incomplete or was written by two runs at once; recompute it (--force)"
        )


def check_event_numbers(path, md, events, start):
    """Check that ``events`` (a batch of the ``event`` column) continues ``start``; return next."""
    first = int(md.get("first_event") or 0)
    if not np.array_equal(events, np.arange(first + start, first + start + len(events))):
        bad = int(
            np.flatnonzero(events != np.arange(first + start, first + start + len(events)))[0]
        )
        raise CatalogError(
            f"catalog {path} has event number {int(events[bad])} at row {start + bad} (expected "
            f"{first + start + bad}): events are missing, duplicated or out of order; "
            "recompute it (--force)"
        )
    return start + len(events)


def verify_catalog(path) -> dict:
    """Metadata of a catalog whose rows are exactly events ``first_event ..``, ``n_events`` of them.

    Reads only the ``event`` column, one row group at a time.
    """
    path, md = open_catalog_file(path, STATS_COLUMNS)
    try:
        pf = pq.ParquetFile(path)
        check_event_count(path, md, pf.metadata.num_rows)
        seen = 0
        for i in range(pf.metadata.num_row_groups):
            events = pf.read_row_group(i, columns=["event"]).column(0).to_numpy()
            seen = check_event_numbers(path, md, events, seen)
    except (OSError, pa.ArrowException) as exc:
        if isinstance(exc, CatalogError):
            raise
        raise CatalogError(f"cannot read catalog {path}: {exc}") from exc
    return md


def state_bytes(state) -> bytes:
    """The ``.npz`` bytes of a :class:`~faultnet.State`, stored under :data:`STATE_KEY`."""
    buf = io.BytesIO()
    np.savez(
        buf,
        z=np.asarray(state.z, dtype=np.float64),
        offset=np.float64(state.offset),
        w=np.float64(state.w),
        n_events=np.int64(state.n_events),
    )
    return buf.getvalue()


def read_state(path) -> State:
    """The state after the last event of catalog ``path``: continuing from it extends the run
    exactly as one longer run would have gone on."""
    path = _check_catalog_file(path)
    schema, md = _file_metadata(path)
    raw = schema.metadata.get(STATE_KEY)
    if raw is None:
        raise CatalogError(
            f"catalog {path} holds no final state (it was written without one, by an older "
            "faultnet or from a table of events), so it cannot be continued"
        )
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            state = State(
                z=data["z"].copy(),
                offset=float(data["offset"]),
                w=float(data["w"]),
                n_events=int(data["n_events"]),
            )
    except (OSError, ValueError, KeyError, EOFError) as exc:
        raise CatalogError(f"catalog {path}: its final state is garbled ({exc})") from None
    want = int(md.get("first_event") or 0) + int(md.get("n_events", state.n_events))
    if state.n_events != want:
        raise CatalogError(
            f"catalog {path}: its final state follows event {state.n_events - 1}, but the "
            f"catalog ends at event {want - 1}"
        )
    return state
