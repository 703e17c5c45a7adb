"""Parquet event catalogs: atomic, chunked writing and reading with metadata.

A catalog file is an ordinary Parquet file holding the ``events`` table of
:class:`faultnet.SimulationResult` (one row per event).  The run's metadata
(parameters, dt, seed entropy and spawn key, graph spec and hash, faultnet
version, timings, provenance) is stored as JSON under the key ``faultnet``
of the Parquet schema metadata, so any Parquet reader sees the table and
:func:`read_catalog` gives back the same DataFrame and the same dict.

Every file is written atomically: to a temporary name in the same folder,
flushed to disk (``fsync``), then renamed over the target (``os.replace``),
and the folder is synced.  A reader therefore sees either no file or a
complete one, whenever the writer is killed.  Nothing is overwritten unless
asked (``overwrite=True``).

Long runs are written in parts (:func:`write_part`, one per chunk of events)
and joined at the end by :func:`merge_parts`, which streams one part at a
time: memory stays O(chunk), whatever the length of the catalog.

>>> import faultnet, tempfile, os
>>> res = faultnet.simulate(faultnet.CarlsonLanger(faultnet.graphs.ring(20)), 50, rng=3,
...                         progress=False)
>>> path = os.path.join(tempfile.mkdtemp(), "cat.parquet")
>>> _ = write_catalog(res, path)
>>> cat = read_catalog(path)
>>> cat.events.equals(res.events), cat.metadata["seed_entropy"]
(True, 3)
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import secrets
import time
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from faultnet.exceptions import FaultnetError, InvalidParameterError

__all__ = [
    "CATALOG_FORMAT",
    "FORMAT_VERSION",
    "METADATA_KEY",
    "Catalog",
    "CatalogError",
    "OutputExistsError",
    "atomic_path",
    "catalog_stats",
    "events_before",
    "fit_b_values",
    "iter_catalog",
    "merge_parts",
    "read_catalog",
    "read_magnitudes",
    "read_metadata",
    "write_catalog",
    "write_part",
]

CATALOG_FORMAT = "faultnet-catalog"
FORMAT_VERSION = 1
#: key of the JSON metadata in the Parquet schema metadata
METADATA_KEY = b"faultnet"
#: magnitudes beyond this many are thinned (every k-th event) for b fits
MAX_FIT_EVENTS = 2_000_000
#: plate time before which ``faultnet simulate`` leaves events out of its b fits by
#: default: the plate has moved twice the slip threshold, so on average every block
#: has slipped about twice and the random initial state is forgotten
TRANSIENT_PLATE_TIME = 2.0
#: default upper end of the least-squares window: this quantile of M above m_min
#: (the largest 1% of events, too few per bin and where finite-size humps sit, stay out)
LSQ_TOP_QUANTILE = 0.99
_COMPRESSION = "zstd"
_TMP_MARK = ".tmp-"


class CatalogError(FaultnetError, OSError):
    """A file is missing, truncated, corrupt or not a faultnet catalog."""


class OutputExistsError(InvalidParameterError, FileExistsError):
    """Refusing to overwrite an existing output (pass force / overwrite)."""


# --------------------------------------------------------------------------- atomic files


def fsync_dir(path):
    """Flush a folder's entries (new names, renames) to disk; a no-op where unsupported."""
    try:
        fd = os.open(path or ".", os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def fsync_file(path):
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def tmp_name(path):
    """A unique temporary name next to ``path`` (hidden, recognisable by ``.tmp-``)."""
    folder, name = os.path.split(os.fspath(path))
    return os.path.join(folder, f".{name}{_TMP_MARK}{os.getpid()}-{secrets.token_hex(4)}")


def is_tmp_name(name):
    """True for names made by :func:`tmp_name` (leftovers of a killed writer)."""
    return name.startswith(".") and _TMP_MARK in name


@contextlib.contextmanager
def atomic_path(path, overwrite=True):
    """Yield a temporary path; on success move it onto ``path`` atomically.

    The temporary file is fsynced, renamed with ``os.replace`` and the folder
    fsynced.  On an exception the temporary file is removed and ``path`` is
    untouched.

    >>> import tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "x.txt")
    >>> with atomic_path(p) as tmp:
    ...     _ = open(tmp, "w").write("hello")
    >>> open(p).read()
    'hello'
    """
    path = os.fspath(path)
    if not overwrite and os.path.exists(path):
        raise OutputExistsError(f"{path} exists; refusing to overwrite it")
    tmp = tmp_name(path)
    try:
        yield tmp
        fsync_file(tmp)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise
    fsync_dir(os.path.dirname(path))


def atomic_write_bytes(path, data):
    """Write ``data`` to ``path`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(data)


def atomic_write_json(path, obj):
    """Write ``obj`` as indented JSON to ``path`` atomically."""
    atomic_write_bytes(path, (json.dumps(obj, indent=2, default=_json_default) + "\n").encode())


# --------------------------------------------------------------------------- metadata


def _json_default(obj):
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        return float(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (set, frozenset)):
        return sorted(obj)
    raise TypeError(f"metadata value {obj!r} ({type(obj).__name__}) is not JSON-serialisable")


def _encode_metadata(md):
    md = dict(md)
    md.setdefault("format", CATALOG_FORMAT)
    md.setdefault("format_version", FORMAT_VERSION)
    return json.dumps(md, default=_json_default, sort_keys=True).encode()


def _decode_metadata(raw):
    md = json.loads(raw)
    for key, value in md.items():
        if key.endswith("spawn_key") and isinstance(value, list):
            md[key] = tuple(value)
    return md


def provenance() -> dict:
    """Versions of faultnet and its numerical dependencies, for metadata."""
    import platform

    import numba
    import scipy

    from faultnet import __version__

    return {
        "faultnet": __version__,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": numba.__version__,
        "scipy": scipy.__version__,
        "pandas": pd.__version__,
        "pyarrow": pa.__version__,
        "platform": platform.platform(),
    }


def utc_now():
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())


# --------------------------------------------------------------------------- tables


def _plain_labels(typ):
    return pa.types.is_integer(typ) or pa.types.is_string(typ) or pa.types.is_large_string(typ)


def events_to_table(events, metadata=None) -> pa.Table:
    """Arrow table of an events DataFrame, with ``metadata`` in the schema.

    Node labels that Parquet cannot hold as one column type (tuples, mixed
    types) are stored as their ``repr`` and ``metadata["hypocenter_labels"]``
    says so.
    """
    if not isinstance(events, pd.DataFrame):
        raise InvalidParameterError(
            f"events must be a pandas DataFrame; got {type(events).__name__}"
        )
    md = dict(metadata or {})
    try:
        table = pa.Table.from_pandas(events, preserve_index=False)
        plain = "hypocenter" not in table.column_names or _plain_labels(
            table.schema.field("hypocenter").type
        )
    except (pa.ArrowInvalid, pa.ArrowTypeError, pa.ArrowNotImplementedError):
        if "hypocenter" not in events:
            raise
        plain = False
    if not plain:
        events = events.assign(hypocenter=events["hypocenter"].map(repr).astype(str))
        table = pa.Table.from_pandas(events, preserve_index=False)
        md["hypocenter_labels"] = "repr"
    schema_md = dict(table.schema.metadata or {})
    schema_md[METADATA_KEY] = _encode_metadata(md)
    return table.replace_schema_metadata(schema_md)


def write_part(events, path, metadata=None, *, overwrite=True):
    """Write one events DataFrame to ``path`` as a Parquet file, atomically."""
    table = events_to_table(events, metadata)
    with atomic_path(path, overwrite=overwrite) as tmp:
        pq.write_table(table, tmp, compression=_COMPRESSION)
    return os.fspath(path)


def merge_parts(parts, out, metadata, *, overwrite=False):
    """Join part files into one catalog at ``out``, one part in memory at a time.

    The result is written to a temporary file and renamed onto ``out``, so a
    kill during the merge leaves ``out`` as it was.
    """
    parts = [os.fspath(p) for p in parts]
    if not parts:
        raise InvalidParameterError("merge_parts needs at least one part file")
    first = pq.read_schema(parts[0])
    schema_md = {k: v for k, v in (first.metadata or {}).items() if k != METADATA_KEY}
    part_md = (
        _decode_metadata(first.metadata[METADATA_KEY])
        if first.metadata and METADATA_KEY in first.metadata
        else {}
    )
    md = dict(metadata)
    if "hypocenter_labels" in part_md:
        md["hypocenter_labels"] = part_md["hypocenter_labels"]
    schema_md[METADATA_KEY] = _encode_metadata(md)
    schema = first.with_metadata(schema_md)
    with atomic_path(out, overwrite=overwrite) as tmp:
        with pq.ParquetWriter(tmp, schema, compression=_COMPRESSION) as writer:
            for part in parts:
                table = pq.read_table(part)
                if not table.schema.equals(first, check_metadata=False):
                    raise CatalogError(
                        f"part {part} has columns {table.schema.names} of other types than "
                        f"the first part: {first}"
                    )
                writer.write_table(table)
                del table
    return os.fspath(out)


@dataclass
class Catalog:
    """A catalog read from disk: the events DataFrame and the run's metadata."""

    events: pd.DataFrame
    metadata: dict = field(default_factory=dict)
    path: str | None = None

    def __len__(self):
        return len(self.events)

    def summary(self, transient=None) -> str:
        """Parameters, events and b-values of the catalog file (see :func:`catalog_stats`)."""
        if not self.path:
            raise CatalogError("summary() needs a catalog read from a file")
        return (
            format_metadata(self.metadata)
            + "\n"
            + format_stats(self.metadata, catalog_stats(self.path, transient=transient))
        )


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
        return schema, _decode_metadata(schema.metadata[METADATA_KEY])
    except ValueError as exc:
        raise CatalogError(f"{path}: faultnet metadata is not valid JSON: {exc}") from exc


def read_metadata(path) -> dict:
    """The metadata dict of a catalog file, reading only its footer."""
    return _file_metadata(_check_catalog_file(path))[1]


def _to_pandas(table):
    return table.to_pandas()


def read_catalog(path, columns=None) -> Catalog:
    """Read a catalog file: the same DataFrame and metadata that were written.

    Parameters
    ----------
    path : str or os.PathLike
    columns : list of str, optional
        Read only these columns.

    Raises
    ------
    CatalogError
        If the file is missing, truncated, corrupt or carries no faultnet metadata.
    """
    path = _check_catalog_file(path)
    _, md = _file_metadata(path)
    try:
        table = pq.read_table(path, columns=columns)
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(f"cannot read catalog {path}: {exc}") from exc
    return Catalog(events=_to_pandas(table), metadata=md, path=path)


def _row_groups(pf, columns):
    """Yield one row group at a time as a Table.

    ``ParquetFile.iter_batches`` keeps read-ahead buffers that grew the
    resident memory of a 10^7-event summary to ~0.8 GB; reading row groups
    one by one (each at most one writer chunk) stays O(chunk).
    """
    for i in range(pf.metadata.num_row_groups):
        yield pf.read_row_group(i, columns=columns)


def iter_catalog(path, batch_size=1_000_000, columns=None):
    """Yield the catalog as DataFrames of at most ``batch_size`` rows (streaming)."""
    path = _check_catalog_file(path)
    _file_metadata(path)
    pf = pq.ParquetFile(path)
    for batch in pf.iter_batches(batch_size=batch_size, columns=columns):
        yield _to_pandas(pa.Table.from_batches([batch]))


def write_catalog(obj, path, metadata=None, *, overwrite=False):
    """Write a :class:`~faultnet.SimulationResult` or events DataFrame to ``path``.

    The metadata is the result's ``metadata`` (with the graph hash and
    provenance added) updated by ``metadata``.  Refuses to replace an existing
    file unless ``overwrite=True``.

    Returns
    -------
    str
        The path written.
    """
    from faultnet.catalog import SimulationResult

    if isinstance(obj, SimulationResult):
        from faultnet.specs import graph_hash

        md = dict(obj.metadata)
        md.setdefault("graph_hash", graph_hash(obj.model))
        spec = obj.model.graph.graph.get("spec")
        if spec:
            md.setdefault("graph_spec", spec)
        events = obj.events
    else:
        md, events = {}, obj
    md.setdefault("provenance", provenance())
    md.setdefault("created", utc_now())
    md.update(metadata or {})
    return write_part(events, path, md, overwrite=overwrite)


# --------------------------------------------------------------------------- statistics


def read_magnitudes(path, skip=0, max_n=MAX_FIT_EVENTS):
    """Magnitudes ``M`` of a catalog after its first ``skip`` rows, streamed.

    Returns ``(M, step)``: when more than ``max_n`` remain, every ``step``-th
    event is kept so that memory stays bounded.
    """
    path = _check_catalog_file(path)
    _file_metadata(path)
    pf = pq.ParquetFile(path)
    n = pf.metadata.num_rows
    remaining = max(n - int(skip), 0)
    step = max(1, math.ceil(remaining / max_n)) if max_n else 1
    out = []
    row = 0
    try:
        for batch in _row_groups(pf, ["M"]):
            m = batch.column(0).to_numpy()
            start, stop = row, row + len(m)
            row = stop
            if stop <= skip:
                continue
            first = max(skip, start)
            # keep rows r >= skip with (r - skip) % step == 0
            offset = (-(first - skip)) % step
            out.append(m[first - start + offset :: step].astype(np.float64, copy=True))
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(f"cannot read magnitudes of {path}: {exc}") from exc
    return (np.concatenate(out) if out else np.zeros(0)), step


def events_before(path, t):
    """Number of events of a catalog file whose plate time is below ``t``, streamed."""
    path = _check_catalog_file(path)
    count = 0
    try:
        for batch in _row_groups(pq.ParquetFile(path), ["t"]):
            times = batch.column(0).to_numpy()
            count += int(np.searchsorted(times, t))
            if len(times) and times[-1] >= t:
                break
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(f"cannot read catalog {path}: {exc}") from exc
    return count


def fit_b_values(M, m_min=None, m_max=None) -> dict:
    """Both b-value fits of magnitudes ``M`` (non-finite values dropped).

    The MLE (:func:`faultnet.stats.fit_b_mle`) uses ``M >= m_min``, by
    default the maximum-curvature completeness magnitude; the least-squares
    fit (:func:`faultnet.stats.fit_b_lsq`) uses the window ``[m_min, m_max]``,
    by default up to the 99th percentile of the magnitudes above ``m_min``
    (:data:`LSQ_TOP_QUANTILE`).

    Returns a dict with ``b_mle``, ``b_mle_err``, ``m_min``, ``m_max``,
    ``n_fit``, ``b_lsq``, ``b_lsq_err``, ``window`` (how the window was chosen;
    NaN where a fit was impossible, with the reason under ``fit_note``).
    """
    from faultnet import stats

    M = np.asarray(M, dtype=np.float64)
    M = M[np.isfinite(M)]
    nan = float("nan")
    out = {
        "b_mle": nan,
        "b_mle_err": nan,
        "m_min": nan,
        "m_max": nan,
        "n_fit": 0,
        "b_lsq": nan,
        "b_lsq_err": nan,
    }
    notes = []
    try:
        mle = stats.fit_b_mle(M, m_min=m_min)
    except (ValueError, FaultnetError, ZeroDivisionError, FloatingPointError) as exc:
        notes.append(f"MLE fit failed: {exc}")
    else:
        above = M[M >= mle.m_min]
        hi = float(np.quantile(above, LSQ_TOP_QUANTILE)) if m_max is None else float(m_max)
        out["window"] = (
            ("maximum curvature" if m_min is None else "--m-min")
            + " to "
            + (
                f"the {LSQ_TOP_QUANTILE * 100:.0f}th percentile of M above it"
                if m_max is None
                else "--m-max"
            )
        )
        out.update(
            b_mle=float(mle.b),
            b_mle_err=float(mle.b_err),
            m_min=float(mle.m_min),
            m_max=hi,
            n_fit=int(mle.n),
        )
        try:
            lsq = stats.fit_b_lsq(M, mle.m_min, hi)
        except (ValueError, FaultnetError, ZeroDivisionError, FloatingPointError) as exc:
            notes.append(f"LSQ fit failed: {exc}")
        else:
            out.update(b_lsq=float(lsq.b), b_lsq_err=float(lsq.b_err))
    if notes:
        out["fit_note"] = "; ".join(notes)
    return out


def catalog_stats(path, transient=None, m_min=None, m_max=None, max_n=MAX_FIT_EVENTS) -> dict:
    """Summary of a catalog file, streamed column by column.

    ``transient`` events at the start are left out of the fits (default:
    the ``transient`` recorded in the metadata, else 0).  Returns events,
    plate-time range, magnitude range, the largest event's blocks and the b
    fits of :func:`fit_b_values` (``m_min``, ``m_max``: its fit window).
    """
    path = _check_catalog_file(path)
    _, md = _file_metadata(path)
    if transient is None:
        transient = int(md.get("transient") or 0)
    pf = pq.ParquetFile(path)
    n = pf.metadata.num_rows
    t_first = t_last = float("nan")
    m_lo, m_hi, big = math.inf, -math.inf, 0
    try:
        for batch in _row_groups(pf, ["t", "M", "n_blocks"]):
            t = batch.column(0).to_numpy()
            m = batch.column(1).to_numpy()
            if len(t) == 0:
                continue
            if math.isnan(t_first):
                t_first = float(t[0])
            t_last = float(t[-1])
            fin = m[np.isfinite(m)]
            if fin.size:
                m_lo, m_hi = min(m_lo, float(fin.min())), max(m_hi, float(fin.max()))
            big = max(big, int(batch.column(2).to_numpy().max()))
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(f"cannot read catalog {path}: {exc}") from exc
    M, step = read_magnitudes(path, skip=transient, max_n=max_n)
    out = {
        "events": n,
        "transient": int(transient),
        "events_fit": max(n - int(transient), 0),
        "fit_step": step,
        "t_first": t_first,
        "t_last": t_last,
        "M_min": m_lo if n else float("nan"),
        "M_max": m_hi if n else float("nan"),
        "largest_n_blocks": big,
    }
    out.update(fit_b_values(M, m_min=m_min, m_max=m_max))
    return out


def _fmt(x, spec=".3f"):
    return "nan" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, spec)


def format_stats(md, st) -> str:
    """Human-readable lines for :func:`catalog_stats` output."""
    lines = [
        f"events      {st['events']:,} (first {md.get('first_event', 0)}); plate time "
        f"{_fmt(st['t_first'], '.6g')} .. {_fmt(st['t_last'], '.6g')}",
        f"magnitude   M = ln S in [{_fmt(st['M_min'])}, {_fmt(st['M_max'])}]; largest event "
        f"{st['largest_n_blocks']} blocks",
    ]
    fit_on = f"{st['events_fit']:,} events after a transient of {st['transient']:,}"
    if st.get("fit_step", 1) > 1:
        fit_on += f", every {st['fit_step']}th"
    lines.append(
        f"b (MLE)     {_fmt(st['b_mle'])} ± {_fmt(st['b_mle_err'])} for M >= {_fmt(st['m_min'])} "
        f"(n = {st['n_fit']:,}; {fit_on})"
    )
    window = f" ({st['window']})" if st.get("window") else ""
    lines.append(
        f"b (LSQ)     {_fmt(st['b_lsq'])} ± {_fmt(st['b_lsq_err'])} on "
        f"[{_fmt(st['m_min'])}, {_fmt(st['m_max'])}]{window}"
    )
    if st.get("fit_note"):
        lines.append(f"note        {st['fit_note']}")
    return "\n".join(lines)


def format_metadata(md) -> str:
    """Human-readable lines for a catalog's parameters and provenance."""
    lines = []
    graph = f"{md.get('graph')}"
    if md.get("graph_spec"):
        graph += f"  (spec {md['graph_spec']})"
    lines.append(f"graph       {graph}: {md.get('n_blocks')} blocks, {md.get('n_springs')} springs")
    if md.get("graph_hash"):
        lines.append(f"graph hash  sha256:{md['graph_hash']}")
    het = "  (per-edge/per-node values in the graph)" if md.get("heterogeneous") else ""
    lines.append(
        f"parameters  k={md.get('k')} sigma={md.get('sigma')} alpha={md.get('alpha')} "
        f"dt={md.get('dt')}{het}"
    )
    seed = f"SeedSequence entropy {md.get('seed_entropy')}, spawn key {md.get('seed_spawn_key')}"
    if md.get("graph_seed_entropy") is not None:
        seed += (
            f"; graph disorder: entropy {md['graph_seed_entropy']}, spawn key "
            f"{md.get('graph_seed_spawn_key')}"
        )
    lines.append(f"seed        {seed}")
    prov = md.get("provenance") or {}
    extra = ", ".join(f"{k} {prov[k]}" for k in ("python", "numpy", "numba") if k in prov)
    lines.append(f"faultnet    {md.get('faultnet_version')}" + (f" ({extra})" if extra else ""))
    wall = md.get("wall_time_s")
    run = []
    if md.get("created"):
        run.append(f"started {md['created']}")
    if md.get("finished"):
        run.append(f"finished {md['finished']}")
    if wall:
        rate = f" = {md.get('n_events', 0) / wall:,.0f} events/s" if md.get("n_events") else ""
        run.append(f"{wall:.2f} s simulating{rate}")
    if md.get("sessions", 1) > 1:
        run.append(f"{md['sessions']} sessions (resumed)")
    if run:
        lines.append("run         " + "; ".join(run))
    return "\n".join(lines)
